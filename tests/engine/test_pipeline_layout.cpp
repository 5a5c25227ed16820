// The layout switches of the superquadric narrow phase (compaction of the candidates, team
// size) change how the work is laid out on the hardware, never what is computed: every pair is
// evaluated from the same state whatever its lane, so whole runs must agree bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
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

// Positions by stable id, and the smallest radius, after `steps` steps of a tests/cli scene.
struct State {
  std::map<std::int64_t, std::vector<double>> position;
  double smallest_radius = 0;
  int pair_contacts = 0;
};

State run_scene_sorted(const std::string& name, bool sort_by_cell, int steps) {
  SceneConfig scene = load_scene(std::string(KDEM_SOURCE_DIR) + "/tests/cli/" + name + ".yaml");
  scene.sort_by_cell = sort_by_cell;
  Engine engine(scene);
  for (int k = 0; k < steps; ++k)
    engine.step();
  const ParticleSnapshot s = engine.snapshot();
  State state;
  state.smallest_radius = *std::min_element(s.radius.begin(), s.radius.end());
  for (std::size_t i = 0; i < s.id.size(); ++i)
    state.position[s.id[i]] = {s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2]};
  state.pair_contacts = engine.diagnostics().pair_contacts;
  return state;
}

// Without the sort the same pairs are found and the same forces computed, summed in another
// order: runs differ by rounding only. After 1000 steps a one-ulp change of the positions has
// grown to at most 1e-8 radii in these scenes (measured by make gpu-check), so 1e-6 radii
// separates rounding from a missed or doubled pair (which moves particles by far more).
TEST(PipelineLayout, SortByCellChangesOnlyRounding) {
  for (const std::string name : {"small_hopper", "small_superquadrics"}) {
    const State sorted = run_scene_sorted(name, true, 1000);
    const State unsorted = run_scene_sorted(name, false, 1000);
    ASSERT_EQ(sorted.position.size(), unsorted.position.size()) << name;
    ASSERT_GT(sorted.pair_contacts, 0) << name << ": no contacts, nothing was tested";
    EXPECT_EQ(sorted.pair_contacts, unsorted.pair_contacts) << name;
    double largest = 0;
    for (const auto& [id, x] : sorted.position) {
      const auto found = unsorted.position.find(id);
      ASSERT_NE(found, unsorted.position.end()) << name << ": particle " << id << " missing";
      for (int c = 0; c < 3; ++c)
        largest = std::max(largest, std::fabs(x[c] - found->second[c]));
    }
    EXPECT_LT(largest, 1e-6 * sorted.smallest_radius) << name;
  }
}

} // namespace
} // namespace kdem
