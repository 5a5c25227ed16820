// Head-on sphere-sphere and sphere-wall impacts against Hertz theory.
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "scene_builders.hpp"
#include "src/restitution.hpp"

namespace kdem::testing {
namespace {

struct ImpactRecord {
  std::vector<std::array<double, 3>> history; // time since first touch, overlap, force on 0
  double peak_overlap = 0;
  double peak_force = 0;    // from the velocity change of particle 0 over one step
  double duration = 0;      // s, with linear interpolation of the touching instants
  double rebound_speed = 0; // relative normal speed after separation
};

// Particle 0 moves along +x towards particle 1 (or a wall at x = gap); overlap measured along x.
ImpactRecord record_impact(Engine& engine, double reach, bool against_wall, double wall_x) {
  ImpactRecord r;
  double previous_gap = 0, previous_velocity = 0, touch_start = -1;
  bool touched = false;
  const double dt = engine.time_step();
  for (int k = 0; k < 400000; ++k) {
    const ParticleSnapshot s = engine.snapshot();
    const double x0 = s.position[0], v0 = s.velocity[0];
    const double gap = against_wall ? (wall_x - x0) - reach : (s.position[3] - x0) - reach;
    const double relative_speed = against_wall ? v0 : v0 - s.velocity[3];
    if (k > 0) {
      const double mass_force = -(v0 - previous_velocity) / dt; // repulsion pushes particle 0 to -x
      r.peak_force = std::max(r.peak_force, mass_force);
      if (touch_start >= 0)
        r.history.push_back({engine.time() - touch_start, std::max(-gap, 0.0), mass_force});
      if (previous_gap >= 0 && gap < 0)
        touch_start = engine.time() - dt * gap / (gap - previous_gap);
      if (previous_gap < 0 && gap >= 0) {
        r.duration = engine.time() - dt * gap / (gap - previous_gap) - touch_start;
        r.rebound_speed = -relative_speed;
        return r;
      }
    }
    if (gap < 0)
      touched = true;
    r.peak_overlap = std::max(r.peak_overlap, -gap);
    previous_gap = gap;
    previous_velocity = v0;
    engine.step();
  }
  ADD_FAILURE() << "impact did not end (touched: " << touched << ")";
  return r;
}

void save_history(const std::string& name, const ImpactRecord& r, double mass) {
  auto out = validation_csv(name, "time,overlap,force");
  if (!out)
    return;
  for (const auto& h : r.history)
    *out << h[0] << "," << h[1] << "," << h[2] * mass << "\n";
}

class HertzImpactTest : public ::testing::TestWithParam<double> {};

// Two equal glass-like spheres, 1 mm radius, meeting at 2 m/s relative speed; dt = t_c / 2000 so
// that time discretisation errors (O(dt^2) for velocity Verlet) stay far below the 1 % tolerance.
TEST_P(HertzImpactTest, SphereSphereMatchesHertzAndRestitution) {
  const double e = GetParam();
  const MaterialConfig glass = material("glass", 2500, 1e8, 0.2, e, 0.0);
  const double radius = 1e-3, speed = 2.0;
  const double mass = glass.density * 4.0 / 3.0 * M_PI * radius * radius * radius;
  const HertzImpact h =
      hertz_impact(0.5 * mass, 0.5 * radius, effective_youngs(glass, glass), speed);
  Engine engine(empty_scene(h.duration / 2000, {glass}));
  engine.add_particles({sphere({-radius - 1e-5, 0, 0}, radius, {0.5 * speed, 0, 0}),
                        sphere({radius + 1e-5, 0, 0}, radius, {-0.5 * speed, 0, 0})});
  const ImpactRecord r = record_impact(engine, 2 * radius, false, 0);
  EXPECT_NEAR(r.rebound_speed / speed, e, 0.01 * e);
  if (e == 1.0) {
    EXPECT_NEAR(r.peak_overlap, h.peak_overlap, 0.01 * h.peak_overlap);
    EXPECT_NEAR(r.peak_force * mass, h.peak_force, 0.01 * h.peak_force);
    EXPECT_NEAR(r.duration, h.duration, 0.01 * h.duration);
  } else {
    EXPECT_LT(r.peak_overlap, h.peak_overlap); // damping absorbs part of the approach energy
  }
}

TEST_P(HertzImpactTest, SphereWallMatchesHertzAndRestitution) {
  const double e = GetParam();
  const MaterialConfig steel = material("steel", 7800, 2e11, 0.3, e, 0.0);
  const double radius = 5e-3, speed = 1.0;
  const double mass = steel.density * 4.0 / 3.0 * M_PI * radius * radius * radius;
  const HertzImpact h = hertz_impact(mass, radius, effective_youngs(steel, steel), speed);
  SceneConfig scene = empty_scene(h.duration / 2000, {steel});
  scene.walls.push_back(plane_wall("steel", {0.0, 0, 0}, {-1, 0, 0}));
  Engine engine(scene);
  engine.add_particles({sphere({-radius - 1e-6, 0, 0}, radius, {speed, 0, 0})});
  const ImpactRecord r = record_impact(engine, radius, true, 0.0);
  save_history("hertz_sphere_wall_e" + std::to_string(int(std::lround(100 * e))), r, mass);
  EXPECT_NEAR(r.rebound_speed / speed, e, 0.01 * e);
  if (e == 1.0) {
    EXPECT_NEAR(r.peak_overlap, h.peak_overlap, 0.01 * h.peak_overlap);
    EXPECT_NEAR(r.peak_force * mass, h.peak_force, 0.01 * h.peak_force);
    EXPECT_NEAR(r.duration, h.duration, 0.01 * h.duration);
  }
}

INSTANTIATE_TEST_SUITE_P(Restitution, HertzImpactTest, ::testing::Values(0.1, 0.5, 0.9, 1.0));

// The closed-form damping coefficient reproduces the requested restitution in the scaled
// Hertz equation (independent RK4 integration), to 1e-5.
TEST(Restitution, ClosedFormDampingGivesRequestedRestitution) {
  for (double e : {0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99}) {
    EXPECT_NEAR(restitution_for_damping(damping_for_restitution(e)), e, 1e-5) << "e = " << e;
  }
}

} // namespace
} // namespace kdem::testing
