// The memory-space discipline of a GPU build, checked where the engine's memory space is not
// host-accessible: the CUDA builds, and the `memcheck` build on the CPU
// (kernels/memory_space_check.hpp). Elsewhere the engine's space is the host's and these tests
// have nothing to observe, so they skip.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <string>

#include "kernels/types.hpp"
#include "scene_builders.hpp"

namespace kdem {
namespace {

constexpr bool engine_space_is_host_accessible =
    Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible;

// What the deep copies of a stretch of time steps moved between the engine's space and the
// host, outside the input region (placing and uploading new particles).
struct TransferLog {
  std::int64_t copies_to_host = 0, copies_to_engine = 0;
  std::int64_t largest_transfer = 0; // bytes
  std::int64_t input_copies = 0;     // inside the "kdem::input" region
  int input_depth = 0;
  std::map<std::string, int> offending; // "destination <- source (bytes)": count
};
TransferLog transfer_log;

void log_copy(const char* destination_space, const char* destination_label,
              const char* source_space, const char* source_label, std::uint64_t bytes) {
  const bool to_host = std::strcmp(destination_space, "Host") == 0;
  const bool from_host = std::strcmp(source_space, "Host") == 0;
  if (to_host == from_host)
    return; // within one space
  if (from_host && std::strcmp(source_label, "Scalar") == 0)
    return; // deep_copy(view, value): a fill in the engine's space, only the value crosses
  if (transfer_log.input_depth > 0) {
    ++transfer_log.input_copies;
    return;
  }
  ++(to_host ? transfer_log.copies_to_host : transfer_log.copies_to_engine);
  transfer_log.largest_transfer = std::max(transfer_log.largest_transfer, std::int64_t(bytes));
  if (bytes > 8 || !to_host)
    ++transfer_log
          .offending[std::string(destination_space) + ":" + destination_label + " <- " +
                     source_space + ":" + source_label + " (" + std::to_string(bytes) + " B)"];
}

void enter_region(const char* name) {
  if (std::string(name) == "kdem::input")
    ++transfer_log.input_depth;
}
void leave_region() {
  if (transfer_log.input_depth > 0)
    --transfer_log.input_depth;
}

// Runs `steps` steps of a scene of tests/cli and returns what they moved to and from the host.
TransferLog transfers_of_steps(const std::string& scene_name, int steps) {
  Engine engine(testing::cli_scene(scene_name));
  transfer_log = TransferLog{};
  memory_check::copy_observer = &log_copy;
  namespace tools = Kokkos::Tools::Experimental;
  // The checked space's callbacks see every deep_copy already; a GPU build installs none, so
  // the observer's are installed here for the stretch observed.
  constexpr bool own_copy_callbacks = !is_checked_space<MemSpace>();
  if (own_copy_callbacks) {
    tools::set_begin_deep_copy_callback(&memory_check::open_copy);
    tools::set_end_deep_copy_callback(&memory_check::close_copy);
  }
  tools::set_push_region_callback(&enter_region);
  tools::set_pop_region_callback(&leave_region);
  for (int k = 0; k < steps; ++k)
    engine.step();
  memory_check::copy_observer = nullptr;
  if (own_copy_callbacks) {
    tools::set_begin_deep_copy_callback(nullptr);
    tools::set_end_deep_copy_callback(nullptr);
  }
  tools::set_push_region_callback(nullptr);
  tools::set_pop_region_callback(nullptr);
  return transfer_log;
}

// A step may bring single values to the host that decide what it does next (list sizes,
// counts of removed particles; 8 bytes at most) and, for an insertion, read the positions and
// radii that new particles must avoid and upload the new particles (input); nothing else.
void expect_only_scalars_cross(const TransferLog& log) {
  // Every scene's steps read list sizes back at their rebuilds: nothing seen would mean the
  // observer saw no copy at all, and the checks below would pass without looking.
  EXPECT_GT(log.copies_to_host, 0) << "no scalar read back: the observer saw nothing";
  std::string offending;
  for (const auto& [copy, count] : log.offending)
    offending += "\n  " + copy + " x" + std::to_string(count);
  EXPECT_LE(log.largest_transfer, 8)
      << "a step moved an array between the engine and the host:" << offending;
  EXPECT_EQ(log.copies_to_engine, 0) << "a step uploaded data that is not input:" << offending;
}

void fill_with_twice_the_index(const ScalarView& values) {
  Kokkos::parallel_for(
      "test::fill", RangePolicy(0, int(values.extent(0))),
      KOKKOS_LAMBDA(int i) { values(i) = 2.0 * i; });
}

TEST(MemorySpaces, HostAccessOutsideKernelsIsRefused) {
  if (engine_space_is_host_accessible)
    GTEST_SKIP() << "the engine's memory space is the host's in this build";
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";
  ScalarView values("values", 4);
  // The checked space's message, or Kokkos' own where the space is a GPU's.
  EXPECT_DEATH(values(1) = 2.0, "accessed on the host outside a kernel|inaccessible memory space");
  // The same access inside a kernel is allowed, and a mirror brings the value back.
  fill_with_twice_the_index(values);
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), values);
  EXPECT_EQ(host(3), 6.0);
}

TEST(MemorySpaces, SphereHopperStepsMoveOnlyScalarsAndInput) {
  if (engine_space_is_host_accessible)
    GTEST_SKIP() << "the engine's memory space is the host's in this build";
  // 3000 steps of the small hopper: particles rain in (input), the lists are rebuilt, the gate
  // opens and the outlet removes particles.
  const TransferLog log = transfers_of_steps("small_hopper", 3000);
  expect_only_scalars_cross(log);
  EXPECT_GT(log.input_copies, 0) << "the scene inserted no particles: the test lost its input";
}

TEST(MemorySpaces, SuperquadricStepsMoveOnlyScalars) {
  if (engine_space_is_host_accessible)
    GTEST_SKIP() << "the engine's memory space is the host's in this build";
  expect_only_scalars_cross(transfers_of_steps("small_superquadrics", 1500));
}

TEST(MemorySpaces, RotatingDrumStepsMoveOnlyScalars) {
  if (engine_space_is_host_accessible)
    GTEST_SKIP() << "the engine's memory space is the host's in this build";
  expect_only_scalars_cross(transfers_of_steps("drum", 1500));
}

} // namespace
} // namespace kdem
