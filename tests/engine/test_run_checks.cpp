// The checks that stop a run gone wrong (Engine::check_health), particles leaving the domain,
// and generation that never places a particle across a wall.
#include <gtest/gtest.h>

#include <limits>

#include "scene_builders.hpp"

namespace kdem::testing {
namespace {

MaterialConfig glass() {
  return material("glass", 2500, 1e8, 0.25, 0.5, 0.5);
}

bool any_cause_mentions(const HealthReport& report, const std::string& words) {
  for (const std::string& cause : report.likely_causes)
    if (cause.find(words) != std::string::npos)
      return true;
  return false;
}

// Advances in steps of `interval` until a check fails or `steps` have run.
HealthReport advance_checking(Engine& engine, int steps, int interval) {
  for (int k = 0; k < steps; k += interval) {
    engine.advance(interval);
    const HealthReport report = engine.check_health();
    if (!report.healthy())
      return report;
  }
  return {};
}

TEST(RunChecks, NonFiniteVelocityIsFoundWithItsParticle) {
  Engine engine(empty_scene(1e-5, {glass()}));
  engine.add_particles({sphere({0, 0, 0}, 0.01), sphere({0.1, 0, 0}, 0.01)});
  EXPECT_TRUE(engine.check_health().healthy());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  engine.add_particles({sphere({0.2, 0, 0}, 0.01, {0, nan, 0})}); // id 2
  const HealthReport report = engine.check_health();
  EXPECT_EQ(report.trigger, "non_finite");
  ASSERT_EQ(report.particles.size(), 1u);
  EXPECT_EQ(report.particles[0].id, 2);
  EXPECT_EQ(report.particles[0].shape, "sphere");
  EXPECT_FALSE(report.likely_causes.empty());
}

// Two spheres of radius r placed 0.4 r into each other: beyond the default 0.25.
TEST(RunChecks, DeepPairOverlapNamesBothParticlesAndTheOverlappingStart) {
  const double r = 0.01;
  Engine engine(empty_scene(1e-6, {glass()}));
  engine.add_particles(
      {sphere({0, 0, 0}, r), sphere({0.5, 0, 0}, r), sphere({2 * r - 0.4 * r, 0, 0}, r)});
  const HealthReport report = engine.check_health();
  EXPECT_EQ(report.trigger, "overlap");
  ASSERT_EQ(report.particles.size(), 2u);
  EXPECT_EQ(std::min(report.particles[0].id, report.particles[1].id), 0);
  EXPECT_EQ(std::max(report.particles[0].id, report.particles[1].id), 2);
  EXPECT_NE(report.finding.find("0.4"), std::string::npos) << report.finding;
}

TEST(RunChecks, OverlapLimitIsTheScenesKey) {
  const double r = 0.01;
  SceneConfig scene = empty_scene(1e-6, {glass()});
  scene.checks.max_overlap_ratio = 0.5;
  Engine engine(scene);
  engine.add_particles({sphere({0, 0, 0}, r), sphere({2 * r - 0.4 * r, 0, 0}, r)});
  EXPECT_TRUE(engine.check_health().healthy());
}

TEST(RunChecks, DeepWallOverlapNamesTheWall) {
  const double r = 0.01;
  SceneConfig scene = empty_scene(1e-6, {glass()});
  scene.walls.push_back(plane_wall("glass", {0, 0, 0}, {0, 0, 1}));
  scene.walls.back().name = "floor";
  Engine engine(scene);
  engine.add_particles({sphere({0, 0, 0.5 * r}, r), sphere({0.1, 0, 0.5}, r)}); // 0.5 r deep
  const HealthReport report = engine.check_health();
  EXPECT_EQ(report.trigger, "overlap");
  EXPECT_NE(report.finding.find("'floor'"), std::string::npos) << report.finding;
  ASSERT_EQ(report.particles.size(), 1u);
  EXPECT_EQ(report.particles[0].id, 0);
}

// 0.2 r of overlap passes the overlap check, but its elastic energy, released, gives the pair a
// kinetic energy no source in the scene accounts for (it started at rest, without gravity):
// the energy check stops it, and the overlapping start is named.
TEST(RunChecks, EnergyReleasedFromAnOverlappingStartTripsTheEnergyCheck) {
  const double r = 0.01;
  Engine engine(empty_scene(1e-6, {glass()}));
  engine.add_particles({sphere({0, 0, 0}, r), sphere({2 * r - 0.2 * r, 0, 0}, r)});
  EXPECT_TRUE(engine.check_health().healthy());
  const HealthReport report = advance_checking(engine, 20000, 10);
  EXPECT_EQ(report.trigger, "energy");
  ASSERT_EQ(report.particles.size(), 1u);
}

// The same pair, touching without overlap and approaching at 1 m/s: the energy they carry is in
// the budget, so the collision passes.
TEST(RunChecks, CollisionWithinTheBudgetPasses) {
  const double r = 0.01;
  Engine engine(empty_scene(1e-6, {glass()}));
  engine.add_particles(
      {sphere({0, 0, 0}, r, {0.5, 0, 0}), sphere({2 * r + 1e-4, 0, 0}, r, {-0.5, 0, 0})});
  EXPECT_TRUE(advance_checking(engine, 20000, 10).healthy());
}

// Too large a time step: a sphere dropped on a stiff floor at 40 times the suggested step
// either sinks beyond the overlap limit or bounces off with energy it never had; the check
// says which, and names the time step.
TEST(RunChecks, LargeTimeStepIsStoppedAndNamed) {
  const double r = 0.002;
  SceneConfig scene = empty_scene(1e-6, {material("steel", 7800, 2e11, 0.3, 0.9, 0.3)});
  scene.gravity = {0, 0, -9.81};
  scene.walls.push_back(plane_wall("steel", {0, 0, 0}, {0, 0, 1}));
  const ParticleInit ball = sphere({0, 0, r + 1e-5}, r, {0, 0, -3});
  Engine probe(scene);
  probe.add_particles({ball});
  const double suggested = probe.time_step_advice().suggested;
  ASSERT_GT(suggested, 0);
  scene.time_step = 40 * suggested;
  Engine engine(scene);
  engine.add_particles({ball});
  const HealthReport report = advance_checking(engine, 20000, 10);
  EXPECT_TRUE(report.trigger == "overlap" || report.trigger == "energy") << report.trigger;
  EXPECT_TRUE(any_cause_mentions(report, "time_step")) << report.likely_causes.front();
}

// A wall turning so fast that its contacts last less than ten time steps is named.
TEST(RunChecks, FastWallIsNamedAsLikelyCause) {
  const double r = 0.005;
  SceneConfig scene = empty_scene(1e-5, {glass()});
  scene.walls.push_back(drum_about_y("glass", 3e5));
  Engine engine(scene);
  engine.add_particles({sphere({0, 0, -0.1 + 0.5 * r}, r)});
  const HealthReport report = engine.check_health();
  EXPECT_EQ(report.trigger, "overlap");
  EXPECT_TRUE(any_cause_mentions(report, "wall 'drum'")) << report.likely_causes.front();
}

// A long healthy run: spheres poured into a turning drum, settled and tumbling for 60000 steps,
// checked every 10; no check trips (the drum's work is within its allowance).
TEST(RunChecks, LongHealthyDrumRunNeverTrips) {
  const SceneConfig scene = cli_scene("drum");
  Engine engine(scene);
  const HealthReport report = advance_checking(engine, 60000, 10);
  EXPECT_TRUE(report.healthy()) << report.trigger << ": " << report.finding;
  EXPECT_EQ(engine.lost_count(), 0);
}

TEST(RunChecks, LongHealthyHopperRunWithInsertionAndOutletNeverTrips) {
  const SceneConfig scene = cli_scene("small_hopper");
  Engine engine(scene);
  const HealthReport report = advance_checking(engine, 10000, 10);
  EXPECT_TRUE(report.healthy()) << report.trigger << ": " << report.finding;
  EXPECT_GT(engine.diagnostics().discharged_count, 0);
}

// ---- leaving the domain -------------------------------------------------------------------

TEST(LeavingDomain, ParticleWhollyOutsideIsRemovedAndCounted) {
  const double r = 0.01;
  Engine engine(empty_scene(1e-4, {glass()})); // domain [-1, 1]^3
  engine.add_particles({sphere({0, 0, 0}, r), sphere({0.9, 0, 0}, r, {10, 0, 0}),
                        sphere({0, -0.9, 0}, r, {0, -10, 0})});
  engine.advance(200); // 0.02 s: the movers are 0.1 m out, wholly outside by 0.09 m
  EXPECT_EQ(engine.particle_count(), 1);
  EXPECT_EQ(engine.lost_count(), 2);
  std::vector<std::int64_t> ids = engine.latest_lost_ids();
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<std::int64_t>{1, 2}));
  const Diagnostics d = engine.diagnostics();
  EXPECT_EQ(d.lost_count, 2);
  EXPECT_NEAR(d.lost_mass, 2 * 2500 * 4.0 / 3.0 * std::acos(-1.0) * r * r * r, 1e-12);
  EXPECT_EQ(d.discharged_count, 0);
  EXPECT_TRUE(engine.check_health().healthy());
}

// Astride the boundary it stays (its centre is outside by less than its radius).
TEST(LeavingDomain, ParticleAstrideTheBoundaryIsKept) {
  const double r = 0.01;
  Engine engine(empty_scene(1e-4, {glass()}));
  engine.add_particles({sphere({1 + 0.9 * r, 0, 0}, r)});
  engine.advance(100);
  EXPECT_EQ(engine.particle_count(), 1);
  EXPECT_EQ(engine.lost_count(), 0);
}

TEST(LeavingDomain, StopModeReportsTheParticleInstead) {
  const double r = 0.01;
  SceneConfig scene = empty_scene(1e-4, {glass()});
  scene.checks.leaving_domain = ChecksConfig::Leaving::Stop;
  Engine engine(scene);
  engine.add_particles({sphere({0, 0, 0}, r), sphere({0.9, 0, 0}, r, {10, 0, 0})});
  engine.advance(200);
  EXPECT_EQ(engine.particle_count(), 2);
  const HealthReport report = engine.check_health();
  EXPECT_EQ(report.trigger, "left_domain");
  ASSERT_EQ(report.particles.size(), 1u);
  EXPECT_EQ(report.particles[0].id, 1);
}

// Without a `domain`, the bounds are the walls' and regions' box grown by half its largest side:
// a sphere rolling off the end of a floor plane is kept until it is that far out.
TEST(LeavingDomain, DerivedDomainHasAMargin) {
  const double r = 0.005;
  SceneConfig scene = empty_scene(1e-4, {glass()});
  scene.has_domain = false;
  ParticleSourceConfig src;
  src.name = "bed";
  src.material = "glass";
  src.sizes.radius = r;
  src.region.min = {-0.05, -0.05, 0};
  src.region.max = {0.05, 0.05, 0.1};
  src.count = 1;
  scene.sources.push_back(src);
  Engine engine(scene); // region box 0.1 m wide: bounds [-0.1, 0.1] x [-0.1, 0.1] x [-0.05, 0.15]
  engine.add_particles({sphere({0.09, 0, 0.05}, r, {1, 0, 0})});
  engine.advance(100); // at x = 0.1: inside the margin
  EXPECT_EQ(engine.lost_count(), 0);
  engine.advance(200); // at x = 0.12: wholly outside
  EXPECT_EQ(engine.lost_count(), 1);
  EXPECT_EQ(engine.particle_count(), 1);
}

// ---- generation against walls -------------------------------------------------------------

ParticleSourceConfig filling(const RegionConfig& region, double r) {
  ParticleSourceConfig src;
  src.name = "fill";
  src.material = "glass";
  src.sizes.radius = r;
  src.region = region;
  src.volume_fraction = 0.3;
  return src;
}

RegionConfig box_region(Vec3d lo, Vec3d hi) {
  RegionConfig region;
  region.min = lo;
  region.max = hi;
  return region;
}

// A region reaching through a floor plane, a tilted plane, and the side of a cylinder: no
// particle is generated touching a wall (no wall contact at the start) and none lies behind one.
TEST(GenerationAgainstWalls, NoParticleIsPlacedAcrossPlanesOrCylinders) {
  const double r = 0.004;
  SceneConfig scene = empty_scene(1e-5, {glass()});
  scene.walls.push_back(plane_wall("glass", {0, 0, 0.02}, {0, 0, 1}));
  scene.walls.push_back(plane_wall("glass", {0.03, 0, 0}, {-1, 0, -1}));
  WallConfig tube;
  tube.kind = WallConfig::Kind::Cylinder;
  tube.name = "tube";
  tube.material = "glass";
  tube.base_center = {0, 0, -0.2};
  tube.axis_direction = {0, 0, 1};
  tube.radius = 0.045;
  tube.length = 0.5;
  scene.walls.push_back(tube);
  scene.sources.push_back(filling(box_region({-0.05, -0.05, -0.05}, {0.05, 0.05, 0.1}), r));
  Engine engine(scene);
  EXPECT_GT(engine.particle_count(), 50);
  EXPECT_EQ(engine.diagnostics().wall_contacts, 0);
  const ParticleSnapshot s = engine.snapshot();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double x = s.position[3 * i], y = s.position[3 * i + 1], z = s.position[3 * i + 2];
    EXPECT_GE(z - 0.02, r);
    EXPECT_GE((0.03 - x - z) / std::sqrt(2.0), r);
    EXPECT_LE(std::hypot(x, y), 0.045 - r);
  }
}

// A region reaching through the funnel of the hopper mesh and a box wall with an open face.
TEST(GenerationAgainstWalls, NoParticleIsPlacedAcrossMeshOrBoxWalls) {
  SceneConfig scene = cli_scene("small_hopper");
  scene.sources.resize(1);
  scene.sources[0].count = 0;
  scene.sources[0].volume_fraction = 0.3;
  scene.sources[0].region = box_region({-0.021, -0.021, 0.0}, {0.021, 0.021, 0.05});
  scene.walls.erase(scene.walls.begin() + 1); // the gate: the funnel holds the bed
  WallConfig box;
  box.kind = WallConfig::Kind::Box;
  box.name = "box";
  box.material = "steel";
  box.min = {-0.015, -0.04, 0.03};
  box.max = {0.015, 0.04, 0.2};
  box.open_faces = {"zmin", "zmax"};
  scene.walls.push_back(box);
  Engine engine(scene);
  EXPECT_GT(engine.particle_count(), 100);
  EXPECT_EQ(engine.diagnostics().wall_contacts, 0);
}

} // namespace
} // namespace kdem::testing
