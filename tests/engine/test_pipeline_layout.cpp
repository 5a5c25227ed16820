// The layout switches of the pipeline change how the work is laid out on the hardware, never
// what is computed. Compaction of the superquadric candidates and the team size of the
// narrow-phase kernels only move a pair to another lane, so whole runs must agree bit for bit;
// without the sort by cell the same forces are summed in another order, so runs agree to
// rounding. With the host lanes of the superquadric narrow phase, compaction also decides which
// four pairs are solved together (a pair solved in lanes or alone agrees to the Newton
// tolerance, not bit for bit: test_superquadric_lanes.cpp), so compaction is compared with the
// lanes off, the team size with them on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "scene_builders.hpp"
#include "src/kernel_timer.hpp"

namespace kdem::testing {
namespace {

RunOutcome run_small_superquadrics(bool compact, int team_size, int steps, bool lanes) {
  SceneConfig scene = cli_scene("small_superquadrics");
  SuperquadricContactConfig& contact = modify_superquadric_contact(scene);
  contact.compact_candidates = compact;
  contact.team_size = team_size;
  contact.lanes = lanes;
  return run_steps(scene, steps);
}

void expect_identical(const RunOutcome& a, const RunOutcome& b, const std::string& what) {
  ASSERT_EQ(a.position.size(), b.position.size()) << what;
  for (const auto& [id, x] : a.position) {
    const auto found = b.position.find(id);
    ASSERT_NE(found, b.position.end()) << what << ": particle " << id << " missing";
    EXPECT_EQ(0, std::memcmp(&x, &found->second, sizeof(Vec3)))
        << what << ": positions differ (particle " << id << ")";
  }
  EXPECT_EQ(a.totals.evaluations, b.totals.evaluations) << what;
  EXPECT_EQ(a.totals.iterations, b.totals.iterations) << what;
  EXPECT_EQ(a.totals.fallbacks, b.totals.fallbacks) << what;
  EXPECT_EQ(a.totals.failures, b.totals.failures) << what;
}

// 2000 steps of the pouring scene: cubes, rods and ellipsoids land on the gate, so pairs enter
// and leave contact and the box tests reject some candidates every step.
TEST(PipelineLayout, CompactionAndTeamSizeDoNotChangeResults) {
  const int steps = 2000;
  const RunOutcome reference = run_small_superquadrics(true, 0, steps, false);
  ASSERT_GT(reference.totals.evaluations, 0) << "the scene evaluated no superquadric pair";
  expect_identical(reference, run_small_superquadrics(false, 0, steps, false),
                   "without compaction");
  expect_identical(reference, run_small_superquadrics(true, 1, steps, false), "teams of 1");
  expect_identical(reference, run_small_superquadrics(false, 64, steps, false),
                   "no compaction, teams of 64 (clamped)");
  const RunOutcome in_lanes = run_small_superquadrics(true, 0, steps, true);
  expect_identical(in_lanes, run_small_superquadrics(true, 2, steps, true), "lanes, teams of 2");
  expect_identical(in_lanes, run_small_superquadrics(true, 64, steps, true),
                   "lanes, teams of 64 (clamped)");
}

RunOutcome run_scene_sorted(const std::string& name, bool sort_by_cell, int steps) {
  SceneConfig scene = cli_scene(name);
  scene.sort_by_cell = sort_by_cell;
  return run_steps(scene, steps);
}

// Without the sort the same pairs are found and the same forces computed, summed in another
// order: runs differ by rounding only. After 1000 steps a one-ulp change of the positions has
// grown to at most 1e-8 radii in these scenes (measured by make gpu-check), so 1e-6 radii
// separates rounding from a missed or doubled pair (which moves particles by far more).
TEST(PipelineLayout, SortByCellChangesOnlyRounding) {
  for (const std::string name : {"small_hopper", "small_superquadrics"}) {
    const RunOutcome sorted = run_scene_sorted(name, true, 1000);
    const RunOutcome unsorted = run_scene_sorted(name, false, 1000);
    ASSERT_EQ(sorted.position.size(), unsorted.position.size()) << name;
    ASSERT_GT(sorted.contacts, 0) << name << ": no contacts, nothing was tested";
    EXPECT_EQ(sorted.contacts, unsorted.contacts) << name;
    double largest = 0;
    for (const auto& [id, x] : sorted.position) {
      const auto found = unsorted.position.find(id);
      ASSERT_NE(found, unsorted.position.end()) << name << ": particle " << id << " missing";
      largest = std::max({largest, std::fabs(x.x - found->second.x),
                          std::fabs(x.y - found->second.y), std::fabs(x.z - found->second.z)});
    }
    EXPECT_LT(largest, 1e-6 * sorted.smallest_radius) << name;
  }
}

struct PairStorage {
  std::int64_t pair_rolling_bytes = 0, wall_rolling_bytes = 0; // live after the steps
  int pair_candidates = 0, wall_candidates = 0;
};

// Four spheres in a row, touching each other and resting on a plane, without gravity: the
// rolling friction coefficient changes nothing they do, so both runs list the same pairs.
PairStorage storage_of_row_of_spheres(double rolling_friction) {
  KernelTimer memory(false);
  PairStorage storage;
  SceneConfig scene =
      empty_scene(1e-6, {material("glass", 2500, 1e8, 0.3, 0.5, 0.5, rolling_friction)});
  scene.walls = {plane_wall("glass", {0, 0, 0}, {0, 0, 1})};
  Engine engine(scene);
  std::vector<ParticleInit> row;
  for (int k = 0; k < 4; ++k)
    row.push_back(sphere({k * 1.999e-3, 0, 0.999e-3}, 1e-3));
  engine.add_particles(row);
  engine.advance(3);
  const auto bytes = memory.bytes_by_label();
  const auto bytes_of = [&](const std::string& label) {
    const auto found = bytes.find(label);
    return found == bytes.end() ? std::int64_t(0) : found->second;
  };
  storage.pair_rolling_bytes = bytes_of("rolling_torque");
  storage.wall_rolling_bytes = bytes_of("wall_rolling_torque");
  storage.pair_candidates = engine.pair_candidates();
  storage.wall_candidates = engine.wall_candidates();
  return storage;
}

// The rolling torque is history only where some material pair has rolling resistance: without
// it the pair and wall lists hold no rolling rows, 24 bytes (one 3-vector) fewer per entry.
TEST(PipelineLayout, RollingHistoryIsStoredOnlyWhenAMaterialHasRollingResistance) {
  const PairStorage without = storage_of_row_of_spheres(0.0);
  const PairStorage with = storage_of_row_of_spheres(0.1);
  ASSERT_EQ(without.pair_candidates, 3);
  ASSERT_EQ(without.wall_candidates, 4);
  ASSERT_EQ(with.pair_candidates, without.pair_candidates);
  ASSERT_EQ(with.wall_candidates, without.wall_candidates);
  EXPECT_EQ(without.pair_rolling_bytes, 0);
  EXPECT_EQ(without.wall_rolling_bytes, 0);
  EXPECT_EQ(with.pair_rolling_bytes, 24 * with.pair_candidates);
  EXPECT_EQ(with.wall_rolling_bytes, 24 * with.wall_candidates);
}

} // namespace
} // namespace kdem::testing
