// Superquadric particles through the whole engine: collisions against closed forms and
// conservation laws, impacts on a wall against rigid-body impact theory, resting contact.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../../shapes/mat3.hpp"
#include "../../shapes/superquadric.hpp"
#include "../../shapes/superquadric_properties.hpp"
#include "scene_builders.hpp"

namespace kdem::testing {
namespace {

ShapeConfig superquadric_shape(const std::string& name, Vec3d half_axes, double n1, double n2) {
  return superquadric_shape_config(name, half_axes, n1, n2);
}

ParticleInit shaped(int shape, Vec3d position, std::array<double, 4> orientation,
                    Vec3d velocity = {0, 0, 0}, Vec3d angular_velocity = {0, 0, 0}) {
  ParticleInit p;
  p.shape = shape;
  p.position = position;
  p.orientation = orientation;
  p.velocity = velocity;
  p.angular_velocity = angular_velocity;
  return p;
}

Quat row4(const std::vector<double>& values, int i) {
  return {values[4 * i], values[4 * i + 1], values[4 * i + 2], values[4 * i + 3]};
}

// Body z turned onto world x: a quarter turn about y.
const std::array<double, 4> z_along_x{std::sqrt(0.5), 0, std::sqrt(0.5), 0};

// Runs until the two particles have separated after touching (or the step budget ends).
void run_until_separated(Engine& engine, int max_steps) {
  bool touched = false;
  for (int k = 0; k < max_steps; ++k) {
    engine.step();
    const int contacts = engine.diagnostics().pair_contacts;
    touched = touched || contacts > 0;
    if (touched && contacts == 0)
      return;
  }
  ADD_FAILURE() << "the collision did not end within " << max_steps << " steps";
}

SceneConfig two_ellipsoid_scene(double restitution, double friction, double curvature_limit) {
  SceneConfig scene =
      empty_scene(1e-7, {material("glass", 2500, 1e8, 0.25, restitution, friction)});
  scene.shapes.push_back(superquadric_shape("prolate", {1e-3, 1e-3, 2e-3}, 2, 2));
  modify_superquadric_contact(scene).curvature_limit = curvature_limit;
  return scene;
}

// Tips of prolate ellipsoids a = b = 1 mm, c = 2 mm meet along their long axes: locally two
// spheres of radius a^2/c = 0.5 mm, so Hertz's impact holds with R* = 0.25 mm, m* = m/2.
TEST(SuperquadricEngine, EllipsoidTipsCollideAsHertzSaysAndKeepMomentum) {
  const double speed = 0.5; // m/s, each
  SceneConfig scene = two_ellipsoid_scene(0.7, 0.0, 10.0);
  Engine engine(scene);
  engine.add_particles({shaped(1, {-2.005e-3, 0, 0}, z_along_x, {speed, 0, 0}),
                        shaped(1, {2.005e-3, 0, 0}, z_along_x, {-speed, 0, 0})});
  const double mass = 2500 * 4.0 / 3.0 * M_PI * 1e-3 * 1e-3 * 2e-3;
  double peak_overlap = 0;
  bool touched = false;
  for (int k = 0; k < 400000; ++k) {
    engine.step();
    const ParticleSnapshot s = engine.snapshot();
    const double gap = (s.position[3] - s.position[0]) - 4e-3;
    peak_overlap = std::max(peak_overlap, -gap);
    touched = touched || gap < 0;
    if (touched && gap > 1e-9)
      break;
  }
  const ParticleSnapshot s = engine.snapshot();
  const double rebound = s.velocity[3] - s.velocity[0];
  // Damping is calibrated for Hertz at constant R*: restitution as for spheres (1 %).
  EXPECT_NEAR(rebound / (2 * speed), 0.7, 0.007);
  RecordProperty("restitution", std::to_string(rebound / (2 * speed)));
  // Equal and opposite pair forces: momentum stays zero to rounding.
  EXPECT_LT(std::abs(mass * (s.velocity[0] + s.velocity[3])), 1e-12 * mass * speed);
  EXPECT_LT(norm(row3(s.angular_velocity, 0)) + norm(row3(s.angular_velocity, 1)), 1e-6);
  // With restitution 0.7 the peak overlap lies below the elastic one, by less than 25 %
  // (the spheres' Hertz tests see the same ratio).
  const HertzImpact h = hertz_impact(
      0.5 * mass, 0.25e-3, effective_youngs(scene.materials[0], scene.materials[0]), 2 * speed);
  EXPECT_LT(peak_overlap, h.peak_overlap);
  EXPECT_GT(peak_overlap, 0.75 * h.peak_overlap);
}

TEST(SuperquadricEngine, ElasticEllipsoidTipsReachTheHertzPeakOverlap) {
  const double speed = 0.5;
  SceneConfig scene = two_ellipsoid_scene(1.0, 0.0, 10.0);
  Engine engine(scene);
  engine.add_particles({shaped(1, {-2.005e-3, 0, 0}, z_along_x, {speed, 0, 0}),
                        shaped(1, {2.005e-3, 0, 0}, z_along_x, {-speed, 0, 0})});
  const double mass = 2500 * 4.0 / 3.0 * M_PI * 1e-3 * 1e-3 * 2e-3;
  double peak_overlap = 0;
  for (int k = 0; k < 200000; ++k) {
    engine.step();
    const ParticleSnapshot s = engine.snapshot();
    peak_overlap = std::max(peak_overlap, 4e-3 - (s.position[3] - s.position[0]));
    if (s.velocity[0] < 0)
      break;
  }
  const HertzImpact h = hertz_impact(
      0.5 * mass, 0.25e-3, effective_youngs(scene.materials[0], scene.materials[0]), 2 * speed);
  // The midway-point overlap of two tips is their Hertz approach to O(overlap / a) = 1e-3.
  EXPECT_NEAR(peak_overlap / h.peak_overlap, 1.0, 0.01);
  RecordProperty("peak_overlap_over_hertz", std::to_string(peak_overlap / h.peak_overlap));
}

// Oblique, frictional collision of two tilted ellipsoids: linear momentum exactly, angular
// momentum about the origin to the integrator's accuracy, energy only lost.
TEST(SuperquadricEngine, ObliqueEllipsoidCollisionKeepsMomenta) {
  SceneConfig scene = two_ellipsoid_scene(0.6, 0.4, 2.0);
  scene.time_step = 1e-7;
  Engine engine(scene);
  const std::array<double, 4> tilt_a{0.9, 0.3, -0.2, 0.1}, tilt_b{0.8, -0.1, 0.4, 0.3};
  auto unit = [](std::array<double, 4> q) {
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    return std::array<double, 4>{q[0] / n, q[1] / n, q[2] / n, q[3] / n};
  };
  engine.add_particles({shaped(1, {-3e-3, 0.6e-3, 0}, unit(tilt_a), {1.0, 0, 0}, {0, 0, 20}),
                        shaped(1, {3e-3, -0.6e-3, 0.2e-3}, unit(tilt_b), {-1.0, 0, 0})});
  auto momenta = [&](Vec3& linear, Vec3& angular, double& energy) {
    const ParticleSnapshot s = engine.snapshot();
    const double mass = 2500 * 4.0 / 3.0 * M_PI * 1e-3 * 1e-3 * 2e-3;
    const Vec3 inertia{mass / 5 * (1e-6 + 4e-6), mass / 5 * (1e-6 + 4e-6), mass / 5 * 2e-6};
    linear = Vec3{};
    angular = Vec3{};
    energy = 0;
    for (int i = 0; i < 2; ++i) {
      const Vec3 x = row3(s.position, i), v = row3(s.velocity, i), w = row3(s.angular_velocity, i);
      const Quat q = row4(s.quaternion, i);
      const Vec3 wb = rotate_inverse(q, w);
      const Vec3 spin = rotate(q, Vec3{inertia.x * wb.x, inertia.y * wb.y, inertia.z * wb.z});
      linear += mass * v;
      angular += cross(x, mass * v) + spin;
      energy += 0.5 * mass * norm2(v) +
                0.5 * dot(wb, Vec3{inertia.x * wb.x, inertia.y * wb.y, inertia.z * wb.z});
    }
  };
  Vec3 p0, l0, p1, l1;
  double e0 = 0, e1 = 0;
  momenta(p0, l0, e0);
  run_until_separated(engine, 200000);
  momenta(p1, l1, e1);
  EXPECT_LT(norm(p1 - p0), 1e-12 * norm(p0) + 1e-15);
  // Velocity Verlet keeps angular momentum to O(dt^2) during the contact: 1e-6 relative.
  EXPECT_LT(norm(l1 - l0), 1e-6 * norm(l0));
  EXPECT_LT(e1, e0);
  EXPECT_GT(engine.diagnostics().step, 0);
  EXPECT_EQ(engine.narrow_phase_totals().failures, 0);
}

// A cylinder-like superquadric (n1 = 8, n2 = 2) falls onto a frictionless plane at several
// tilts; elastic contact, so that the theory's restitution and the contact law's agree. The
// body turns by up to ~1e-2 rad during the contact, which the theory neglects.
class CylinderDrop : public ::testing::TestWithParam<double> {};

TEST_P(CylinderDrop, ReboundFollowsRigidBodyImpactTheory) {
  const double tilt = GetParam(); // rad, body z from world z about world x
  const double density = 7800;
  SceneConfig scene = empty_scene(1e-8, {material("steel", density, 2e11, 0.3, 1.0, 0.0)});
  scene.shapes.push_back(superquadric_shape("cylinder", {1e-3, 1e-3, 2e-3}, 8, 2));
  scene.walls.push_back(plane_wall("steel", {0, 0, 0}, {0, 0, 1}));
  Engine engine(scene);
  const SuperquadricShape shape = make_superquadric(1e-3, 1e-3, 2e-3, 8, 2);
  const Quat orientation{std::cos(tilt / 2), std::sin(tilt / 2), 0, 0};
  const Mat3 rotation = rotation_matrix(orientation);
  const Vec3 down{0, 0, -1};
  const Vec3 lowest = rotation * superquadric_support_point(shape, transpose(rotation) * down);
  const Vec3 v0{0, 0, -0.5};
  engine.add_particles(
      {shaped(1, {0, 0, -lowest.z + 1e-6},
              {orientation.w, orientation.x, orientation.y, orientation.z}, {v0.x, v0.y, v0.z})});

  const double mass = density * superquadric_volume(shape);
  const Vec3 inertia = superquadric_principal_inertia(shape, density);
  Mat3 inverse_body;
  inverse_body.m[0][0] = 1 / inertia.x, inverse_body.m[1][1] = 1 / inertia.y;
  inverse_body.m[2][2] = 1 / inertia.z;
  const ImpactPrediction expected = rigid_body_impact(mass, rotate_tensor(rotation, inverse_body),
                                                      lowest, Vec3{0, 0, 1}, v0, Vec3{}, 1.0);

  ASSERT_TRUE(run_through_wall_impact(engine, 200000));
  const ParticleSnapshot after = engine.snapshot();
  const Vec3 v = row3(after.velocity, 0), w = row3(after.angular_velocity, 0);
  // 1 %: the turn during contact moves the contact point by ~1e-2 of the lever arm at most
  // (measured: below 0.2 % in velocity and spin).
  EXPECT_LT(norm(v - expected.velocity), 0.01 * norm(v0)) << "tilt " << tilt;
  EXPECT_LT(norm(w - expected.angular_velocity), 0.01 * norm(expected.angular_velocity) + 1e-3)
      << "tilt " << tilt;
  // Elastic: the kinetic energy comes back to within the same few per cent.
  const Vec3 wb = rotate_inverse(row4(after.quaternion, 0), w);
  const double energy =
      0.5 * mass * norm2(v) +
      0.5 * (inertia.x * wb.x * wb.x + inertia.y * wb.y * wb.y + inertia.z * wb.z * wb.z);
  EXPECT_NEAR(energy / (0.5 * mass * norm2(v0)), 1.0, 0.01);
  RecordProperty("velocity_error", std::to_string(norm(v - expected.velocity) / norm(v0)));
  RecordProperty("angular_velocity_error", std::to_string(norm(w - expected.angular_velocity) /
                                                          norm(expected.angular_velocity)));
  RecordProperty("predicted_spin", std::to_string(norm(expected.angular_velocity)));
}

INSTANTIATE_TEST_SUITE_P(Tilts, CylinderDrop, ::testing::Values(0.3, 0.8, 1.2));

// A cube resting face down on a belt (a plane translating at u along itself): friction
// accelerates it at mu g until it moves with the belt, without tipping (mu c < a) or turning.
// The time to reach the belt speed is u / (mu g) = 0.02 s; after 0.06 s the residual of the
// tangential spring's oscillation is what is left.
TEST(SuperquadricEngine, CubeOnAConveyorMovesWithTheBelt) {
  SceneConfig scene = empty_scene(1e-5, {material("rubber", 1200, 1e7, 0.4, 0.3, 0.5)});
  scene.gravity = {0, 0, -9.81};
  scene.shapes.push_back(superquadric_shape("cube", {1e-3, 1e-3, 1e-3}, 8, 8));
  scene.domain_min = {-0.005, -0.005, -0.005}; // a small cell grid: lists are rebuilt often
  scene.domain_max = {0.015, 0.005, 0.005};    // as the belt moves
  WallConfig belt = plane_wall("rubber", {0, 0, 0}, {0, 0, 1});
  const double u = 0.1;
  belt.motion.velocity = {u, 0, 0};
  scene.walls.push_back(belt);
  Engine engine(scene);
  engine.add_particles({shaped(1, {0, 0, 1e-3 - 1e-7}, {1, 0, 0, 0})});
  engine.advance(2000); // 0.02 s: still accelerating
  const double accelerating = engine.snapshot().velocity[0];
  engine.advance(4000); // 0.06 s
  const ParticleSnapshot s = engine.snapshot();
  // mu g t = 0.098 m/s at 0.02 s, minus the settling of the first steps: within 10 %.
  EXPECT_NEAR(accelerating, 0.5 * 9.81 * 0.02, 0.1 * u);
  EXPECT_NEAR(s.velocity[0], u, 0.005 * u);
  EXPECT_LT(std::abs(s.velocity[2]), 1e-3 * u);
  EXPECT_LT(norm(row3(s.angular_velocity, 0)), 0.05); // rad/s: no tipping, no turning
  const Quat q = row4(s.quaternion, 0);
  EXPECT_GT(q.w * q.w, 1 - 1e-6);         // still face down
  EXPECT_NEAR(s.position[2], 1e-3, 1e-5); // resting on its face (overlap ~1e-6)
}

} // namespace
} // namespace kdem::testing
