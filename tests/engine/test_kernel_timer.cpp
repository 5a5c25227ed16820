// KernelTimer: launches and time per kernel label, bytes allocated in the engine's space.
#include <gtest/gtest.h>

#include "kernels/types.hpp"
#include "src/kernel_timer.hpp"

namespace kdem {
namespace {

void fill(const ScalarView& v, double value) {
  Kokkos::parallel_for(
      "test::fill", RangePolicy(0, int(v.extent(0))), KOKKOS_LAMBDA(int i) { v(i) = value; });
}

double total(const ScalarView& v) {
  double sum = 0;
  Kokkos::parallel_reduce(
      "test::total", RangePolicy(0, int(v.extent(0))),
      KOKKOS_LAMBDA(int i, double& s) { s += v(i); }, sum);
  return sum;
}

TEST(KernelTimer, CountsLaunchesPerLabel) {
  ScalarView values("values", 1000);
  KernelTimer timer;
  fill(values, 1.0);
  fill(values, 2.0);
  EXPECT_EQ(total(values), 2000.0);
  const auto& tallies = timer.tallies();
  ASSERT_EQ(tallies.count("test::fill"), 1u);
  ASSERT_EQ(tallies.count("test::total"), 1u);
  EXPECT_EQ(tallies.at("test::fill").launches, 2);
  EXPECT_EQ(tallies.at("test::total").launches, 1);
  EXPECT_GE(tallies.at("test::fill").seconds, 0.0);
  timer.reset();
  EXPECT_TRUE(timer.tallies().empty());
}

// A View of 1000 doubles made while the timer is installed counts 8000 bytes (Kokkos reports
// the data size) under its label until it is freed; the peak keeps them.
TEST(KernelTimer, TalliesBytesInTheEngineSpace) {
  KernelTimer timer(false);
  EXPECT_EQ(timer.bytes_allocated(), 0);
  {
    ScalarView values("values", 1000);
    ScalarView more_values("values", 500), others("others", 10);
    fill(values, 3.0);
    EXPECT_EQ(timer.bytes_allocated(), 8000 + 4000 + 80);
    const auto by_label = timer.bytes_by_label();
    ASSERT_EQ(by_label.size(), 2u);
    EXPECT_EQ(by_label.at("values"), 12000);
    EXPECT_EQ(by_label.at("others"), 80);
    EXPECT_EQ(timer.bytes_by_label_json(), "{\"others\": 80, \"values\": 12000}");
  }
  EXPECT_EQ(timer.bytes_allocated(), 0);
  EXPECT_TRUE(timer.bytes_by_label().empty());
  EXPECT_EQ(timer.peak_bytes(), 12080);
}

TEST(KernelTimer, OneAtATime) {
  KernelTimer timer;
  EXPECT_THROW(KernelTimer second, std::logic_error);
}

} // namespace
} // namespace kdem
