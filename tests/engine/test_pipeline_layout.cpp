// The layout switches of the superquadric narrow phase (compaction of the candidates, team
// size) change how the work is laid out on the hardware, never what is computed: every pair is
// evaluated from the same state whatever its lane, so whole runs must agree bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "src/engine.hpp"
#include "src/scene_loader.hpp"

namespace kdem {
namespace {

struct Outcome {
  std::vector<double> position;
  NarrowPhaseTotals totals;
};

Outcome run_small_superquadrics(bool compact, int team_size, int steps) {
  SceneConfig scene =
      load_scene(std::string(KDEM_SOURCE_DIR) + "/tests/cli/small_superquadrics.yaml");
  scene.superquadric_contact.compact_candidates = compact;
  scene.superquadric_contact.team_size = team_size;
  Engine engine(scene);
  for (int k = 0; k < steps; ++k)
    engine.step();
  return {engine.snapshot().position, engine.narrow_phase_totals()};
}

void expect_identical(const Outcome& a, const Outcome& b, const std::string& what) {
  ASSERT_EQ(a.position.size(), b.position.size()) << what;
  EXPECT_EQ(0,
            std::memcmp(a.position.data(), b.position.data(), a.position.size() * sizeof(double)))
      << what << ": positions differ";
  EXPECT_EQ(a.totals.evaluations, b.totals.evaluations) << what;
  EXPECT_EQ(a.totals.iterations, b.totals.iterations) << what;
  EXPECT_EQ(a.totals.fallbacks, b.totals.fallbacks) << what;
  EXPECT_EQ(a.totals.failures, b.totals.failures) << what;
}

// 2000 steps of the pouring scene: cubes, rods and ellipsoids land on the gate, so pairs enter
// and leave contact and the box tests reject some candidates every step.
TEST(PipelineLayout, CompactionAndTeamSizeDoNotChangeResults) {
  const int steps = 2000;
  const Outcome reference = run_small_superquadrics(true, 0, steps);
  ASSERT_GT(reference.totals.evaluations, 0) << "the scene evaluated no superquadric pair";
  expect_identical(reference, run_small_superquadrics(false, 0, steps), "without compaction");
  expect_identical(reference, run_small_superquadrics(true, 1, steps), "teams of 1");
  expect_identical(reference, run_small_superquadrics(true, 2, steps), "teams of 2");
  expect_identical(reference, run_small_superquadrics(false, 64, steps),
                   "no compaction, teams of 64 (clamped)");
}

} // namespace
} // namespace kdem
