// Each particle carries the source that made it and its source's tag: through insertion,
// outlets (removal re-orders the particles), checkpoints and restarts, and into the counts of
// the time series.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>

#include "scene_builders.hpp"

namespace kdem {
namespace {

// The superquadric hopper of the whole-program checks (sources cubes, rods, ellipsoids,
// spheres; an outlet below the orifice), with the first two sources tagged "blocky" and the
// spheres "round".
SceneConfig tagged_hopper() {
  SceneConfig scene = testing::cli_scene("small_superquadrics");
  scene.sources.at(0).tag = "blocky";
  scene.sources.at(1).tag = "blocky";
  scene.sources.at(3).tag = "round";
  return scene;
}

// The tag a particle of each source must carry (index in tag_names).
int expected_tag(int source) {
  return source <= 1 ? 0 : (source == 3 ? 1 : -1);
}

void expect_labels_match_counts(const Engine& engine) {
  const ParticleSnapshot s = engine.snapshot();
  const Diagnostics d = engine.diagnostics();
  std::vector<std::int64_t> per_source(engine.source_names().size(), 0);
  std::vector<std::int64_t> per_tag(engine.tag_names().size(), 0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    ASSERT_GE(s.source[i], 0);
    EXPECT_EQ(s.tag[i], expected_tag(s.source[i]));
    ++per_source.at(s.source[i]);
    if (s.tag[i] >= 0)
      ++per_tag.at(s.tag[i]);
  }
  EXPECT_EQ(d.particles_per_source, per_source);
  EXPECT_EQ(d.particles_per_tag, per_tag);
  EXPECT_EQ(std::accumulate(per_source.begin(), per_source.end(), std::int64_t(0)),
            std::int64_t(s.size()));
}

TEST(ParticleTags, SourcesAndTagsAreNamedOnceEach) {
  Engine engine(tagged_hopper());
  EXPECT_EQ(engine.source_names(),
            (std::vector<std::string>{"cubes", "rods", "ellipsoids", "spheres"}));
  EXPECT_EQ(engine.tag_names(), (std::vector<std::string>{"blocky", "round"}));
  expect_labels_match_counts(engine);
  EXPECT_EQ(engine.diagnostics().particles_per_tag, (std::vector<std::int64_t>{250, 100}));
}

TEST(ParticleTags, LabelsFollowTheirParticlesThroughDischargeAndRestart) {
  Engine engine(tagged_hopper());
  std::map<std::int64_t, int> source_of_id;
  const ParticleSnapshot first = engine.snapshot();
  for (std::size_t i = 0; i < first.size(); ++i)
    source_of_id[first.id[i]] = first.source[i];
  engine.advance(8000);
  ASSERT_GT(engine.diagnostics().discharged_count, 0) << "the outlet must have re-ordered rows";
  expect_labels_match_counts(engine);
  const ParticleSnapshot moved = engine.snapshot();
  for (std::size_t i = 0; i < moved.size(); ++i)
    EXPECT_EQ(moved.source[i], source_of_id.at(moved.id[i])) << "particle " << moved.id[i];
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / "kdem_particle_tags.h5").string();
  engine.write_checkpoint(path);
  Engine restarted(tagged_hopper());
  restarted.read_checkpoint(path);
  std::remove(path.c_str());
  const ParticleSnapshot before = engine.snapshot(), after = restarted.snapshot();
  ASSERT_EQ(before.id, after.id);
  EXPECT_EQ(before.source, after.source);
  EXPECT_EQ(before.tag, after.tag);
}

TEST(ParticleTags, ParticlesAddedByTheProgramHaveNoSourceOrTag) {
  Engine engine(tagged_hopper());
  const std::int64_t before = engine.particle_count();
  engine.add_particles({testing::sphere({0, 0, 0.2}, 0.002)});
  const ParticleSnapshot s = engine.snapshot();
  int unlabelled = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    unlabelled += s.source[i] == -1 && s.tag[i] == -1 ? 1 : 0;
  EXPECT_EQ(unlabelled, 1);
  const Diagnostics d = engine.diagnostics();
  EXPECT_EQ(std::accumulate(d.particles_per_source.begin(), d.particles_per_source.end(),
                            std::int64_t(0)),
            before);
}

} // namespace
} // namespace kdem
