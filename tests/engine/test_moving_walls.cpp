// Walls that move: a translating plane (a conveyor belt) and a turning drum.
#include <gtest/gtest.h>

#include "scene_builders.hpp"

namespace kdem::testing {
namespace {

Vec3d row(const std::vector<double>& v, int i) {
  return {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
}

// A sphere at rest on a belt moving at u: friction accelerates and spins it until its contact
// point moves with the belt. Angular momentum about the contact line is conserved
// (m v R + I w = 0), so v_final = u / (1 + m R^2 / I) = 2 u / 7 for a solid sphere, for any mu.
// The residual of the tangential spring's oscillation is below 0.5 % of u after 0.2 s.
TEST(MovingWalls, SphereOnConveyorReachesTwoSeventhsOfBeltSpeed) {
  const MaterialConfig m = material("rubber", 1200, 1e7, 0.4, 0.3, 0.6);
  SceneConfig scene = empty_scene(2e-6, {m});
  scene.gravity = {0, 0, -9.81};
  WallConfig belt = plane_wall("rubber", {0, 0, 0}, {0, 0, 1});
  const double u = 0.5;
  belt.motion.velocity = {u, 0, 0};
  scene.walls.push_back(belt);
  Engine engine(scene);
  const double radius = 0.005;
  engine.add_particles({sphere({0, 0, radius - 2e-6}, radius)});
  engine.advance(100000); // 0.2 s
  const ParticleSnapshot s = engine.snapshot();
  EXPECT_NEAR(s.velocity[0], 2.0 / 7.0 * u, 0.005 * u);
  const double contact_point_speed = s.velocity[0] - radius * s.angular_velocity[1];
  EXPECT_NEAR(contact_point_speed, u, 0.005 * u);
  EXPECT_NEAR(s.position[2], radius, 0.01 * radius); // still on the belt
}

// A drum turning about its axis carries a sphere resting at its bottom: the wall velocity at
// the contact point is omega x r, and once the sphere rolls without slipping its contact point
// moves with the wall. Checked on the velocity of the contact point after 0.3 s, within 1 % of
// the wall speed (the sphere rocks about the bottom with a small, undamped amplitude).
TEST(MovingWalls, TurningDrumDrivesSphereToRollWithoutSlip) {
  const MaterialConfig m = material("steel", 7800, 2e9, 0.3, 0.5, 0.8);
  SceneConfig scene = empty_scene(2e-6, {m});
  scene.gravity = {0, 0, -9.81};
  scene.walls.push_back(drum_about_y("steel", 2.0));
  Engine engine(scene);
  const double radius = 0.01;
  engine.add_particles({sphere({0, 0, -0.1 + radius - 1e-6}, radius)});
  engine.advance(150000); // 0.3 s
  const ParticleSnapshot s = engine.snapshot();
  const Vec3d x = row(s.position, 0), v = row(s.velocity, 0), w = row(s.angular_velocity, 0);
  const double omega = 2.0 * 2 * M_PI / 60; // about +y
  const double rho = std::sqrt(x[0] * x[0] + x[2] * x[2]);
  const Vec3d outward{x[0] / rho, 0, x[2] / rho};
  const Vec3d contact{x[0] + radius * outward[0], 0, x[2] + radius * outward[2]};
  // velocities at the contact point: wall omega x contact, sphere v + w x (contact - x)
  const Vec3d wall{omega * contact[2], 0, -omega * contact[0]};
  const Vec3d arm{contact[0] - x[0], 0, contact[2] - x[2]};
  const Vec3d body{v[0] + w[1] * arm[2] - w[2] * arm[1], v[1] + w[2] * arm[0] - w[0] * arm[2],
                   v[2] + w[0] * arm[1] - w[1] * arm[0]};
  const double wall_speed = omega * 0.1;
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(body[k], wall[k], 0.01 * wall_speed) << "component " << k;
}

} // namespace
} // namespace kdem::testing
