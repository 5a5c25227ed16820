// The layout switches of the pipeline change how the work is laid out on the hardware, never
// what is computed. Compaction of the superquadric candidates and the team size of the
// narrow-phase kernels only move a pair to another lane, so whole runs must agree bit for bit;
// without the sort by cell the same forces are summed in another order, so runs agree to
// rounding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "scene_builders.hpp"

namespace kdem::testing {
namespace {

RunOutcome run_small_superquadrics(bool compact, int team_size, int steps) {
  SceneConfig scene = cli_scene("small_superquadrics");
  scene.superquadric_contact.compact_candidates = compact;
  scene.superquadric_contact.team_size = team_size;
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
  const RunOutcome reference = run_small_superquadrics(true, 0, steps);
  ASSERT_GT(reference.totals.evaluations, 0) << "the scene evaluated no superquadric pair";
  expect_identical(reference, run_small_superquadrics(false, 0, steps), "without compaction");
  expect_identical(reference, run_small_superquadrics(true, 1, steps), "teams of 1");
  expect_identical(reference, run_small_superquadrics(true, 2, steps), "teams of 2");
  expect_identical(reference, run_small_superquadrics(false, 64, steps),
                   "no compaction, teams of 64 (clamped)");
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

} // namespace
} // namespace kdem::testing
