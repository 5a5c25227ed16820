#pragma once
// Small programmatic scenes for engine tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "shapes/mat3.hpp"
#include "shapes/vec3.hpp"
#include "src/engine.hpp"
#include "src/scene.hpp"
#include "src/scene_loader.hpp"
#include "src/superquadric_scene.hpp"

namespace kdem::testing {

inline MaterialConfig material(const std::string& name, double density, double youngs,
                               double poisson, double restitution, double friction,
                               double rolling = 0) {
  MaterialConfig m;
  m.name = name;
  m.density = density;
  m.youngs_modulus = youngs;
  m.poisson_ratio = poisson;
  m.restitution = restitution;
  m.friction = friction;
  m.rolling_friction = rolling;
  return m;
}

// A scene without particles, gravity or walls; tests add what they need.
inline SceneConfig empty_scene(double dt, const std::vector<MaterialConfig>& materials) {
  SceneConfig scene;
  scene.source_file = "test";
  scene.gravity = {0, 0, 0};
  scene.time_step = dt;
  scene.duration = 1;
  scene.materials = materials;
  scene.has_domain = true;
  scene.domain_min = {-1, -1, -1};
  scene.domain_max = {1, 1, 1};
  return scene;
}

inline WallConfig plane_wall(const std::string& material, Vec3d point, Vec3d normal) {
  WallConfig w;
  w.kind = WallConfig::Kind::Plane;
  w.name = "plane";
  w.material = material;
  w.point = point;
  const double n = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  w.normal = {normal[0] / n, normal[1] / n, normal[2] / n};
  return w;
}

// A drum of radius 0.1 m and length 0.1 m about the y axis through the origin, turning at `rpm`.
inline WallConfig drum_about_y(const std::string& material, double rpm) {
  WallConfig drum;
  drum.kind = WallConfig::Kind::Cylinder;
  drum.name = "drum";
  drum.material = material;
  drum.base_center = {0, -0.05, 0};
  drum.axis_direction = {0, 1, 0};
  drum.radius = 0.1;
  drum.length = 0.1;
  drum.motion.axis_point = {0, 0, 0};
  drum.motion.axis_direction = {0, 1, 0};
  drum.motion.rpm = rpm;
  return drum;
}

// Row i of a snapshot's flattened three-column field.
inline Vec3 row3(const std::vector<double>& values, int i) {
  return {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
}

inline ParticleInit sphere(Vec3d position, double radius, Vec3d velocity = {0, 0, 0},
                           int material = 0) {
  ParticleInit p;
  p.position = position;
  p.radius = radius;
  p.velocity = velocity;
  p.material = material;
  return p;
}

// Hertz's elastic impact at relative speed v (Johnson, Contact Mechanics, 1985, 11.1):
// peak overlap (15 m* v^2 / (16 E* sqrt(R*)))^(2/5), peak force 4/3 E* sqrt(R*) d^1.5,
// duration 2 (d_max / v) integral_0^1 (1 - x^2.5)^-1/2 dx = 2.9432 d_max / v.
struct HertzImpact {
  double peak_overlap, peak_force, duration;
};

inline HertzImpact hertz_impact(double effective_mass, double effective_radius,
                                double effective_youngs, double speed) {
  HertzImpact h;
  const double k = 4.0 / 3.0 * effective_youngs * std::sqrt(effective_radius);
  h.peak_overlap = std::pow(15.0 * effective_mass * speed * speed /
                                (16.0 * effective_youngs * std::sqrt(effective_radius)),
                            0.4);
  h.peak_force = k * std::pow(h.peak_overlap, 1.5);
  const double integral = std::sqrt(M_PI) * std::tgamma(1.4) / std::tgamma(0.9); // = 1.4716...
  h.duration = 2.0 * integral * h.peak_overlap / speed;
  return h;
}

inline double effective_youngs(const MaterialConfig& a, const MaterialConfig& b) {
  return 1.0 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}

// With KDEM_VALIDATION_OUT set, a CSV file there (header written) for the plots of
// docs/validation.md (cases/validation/plot_validation.py); otherwise null.
inline std::unique_ptr<std::ofstream> validation_csv(const std::string& name,
                                                     const std::string& header) {
  const char* directory = std::getenv("KDEM_VALIDATION_OUT");
  if (!directory)
    return nullptr;
  auto file = std::make_unique<std::ofstream>(std::string(directory) + "/" + name + ".csv");
  file->precision(12);
  *file << header << "\n";
  return file;
}

// The source tree (tests/main.cpp).
extern const char* const source_dir;

// A scene of tests/cli (small_hopper, small_superquadrics, drum), as its file says.
inline SceneConfig cli_scene(const std::string& name) {
  return load_scene(std::string(source_dir) + "/tests/cli/" + name + ".yaml");
}

// What `steps` steps of a scene end with: positions by stable id, the narrow-phase totals, the
// pair contacts and the smallest (bounding) radius.
struct RunOutcome {
  std::map<std::int64_t, Vec3> position;
  NarrowPhaseTotals totals;
  int contacts = 0;
  double smallest_radius = 0;
};

// The largest distance between the positions of a particle in two runs; infinite where the two
// runs do not hold the same particles.
inline double largest_position_difference(const RunOutcome& a, const RunOutcome& b) {
  if (a.position.size() != b.position.size())
    return std::numeric_limits<double>::infinity();
  double largest = 0;
  for (const auto& [id, x] : a.position) {
    const auto found = b.position.find(id);
    if (found == b.position.end())
      return std::numeric_limits<double>::infinity();
    largest = std::max(largest, norm(x - found->second));
  }
  return largest;
}

inline RunOutcome outcome_of(const Engine& engine) {
  RunOutcome outcome;
  const ParticleSnapshot s = engine.snapshot();
  for (std::size_t i = 0; i < s.id.size(); ++i)
    outcome.position[s.id[i]] = {s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2]};
  outcome.totals = engine.narrow_phase_totals();
  outcome.contacts = engine.diagnostics().pair_contacts;
  if (!s.radius.empty())
    outcome.smallest_radius = *std::min_element(s.radius.begin(), s.radius.end());
  return outcome;
}

inline RunOutcome run_steps(const SceneConfig& scene, int steps) {
  Engine engine(scene);
  for (int k = 0; k < steps; ++k)
    engine.step();
  return outcome_of(engine);
}

// A body of scene shape `shape` at `position` turned by q, moving.
inline ParticleInit shaped_particle(int shape, Vec3d position, Quat q, Vec3d velocity = {0, 0, 0},
                                    Vec3d angular_velocity = {0, 0, 0}) {
  ParticleInit p;
  p.shape = shape;
  p.position = position;
  p.orientation = {q.w, q.x, q.y, q.z};
  p.velocity = velocity;
  p.angular_velocity = angular_velocity;
  return p;
}

// A box of planes (9 mm wide) for bodies of `shape` dropped into it in a 3 x 3 x 3 lattice
// (lattice_bodies), under gravity, with friction and rolling resistance: the scene in which two
// descriptions of the same bodies must move alike.
inline SceneConfig lattice_drop(const ShapeConfig& shape) {
  SceneConfig scene = empty_scene(2e-6, {material("beads", 2500, 1e7, 0.25, 0.5, 0.4, 0.02)});
  scene.gravity = {0, 0, -9.81};
  scene.shapes.push_back(shape);
  scene.walls.push_back(plane_wall("beads", {0, 0, 0}, {0, 0, 1}));
  for (int axis = 0; axis < 2; ++axis)
    for (double side : {-1.0, 1.0}) {
      Vec3d point{0, 0, 0}, normal{0, 0, 0};
      point[axis] = side * 4.5e-3;
      normal[axis] = -side;
      scene.walls.push_back(plane_wall("beads", point, normal));
    }
  return scene;
}

// 27 bodies of shape id `shape` (radius `radius` where the shape is a sphere, id 0) on a
// 2.8 mm lattice, turned, spinning and thrown at each other.
inline std::vector<ParticleInit> lattice_bodies(int shape, double radius = 0) {
  std::vector<ParticleInit> bodies;
  for (int k = 0; k < 27; ++k) {
    const Vec3d at{(k % 3 - 1) * 2.8e-3, (k / 3 % 3 - 1) * 2.8e-3, 2e-3 + (k / 9) * 2.8e-3};
    const Vec3 axis{std::sin(1.0 + k), std::cos(2.0 * k), 0.5};
    const double half = 0.2 * k;
    const Vec3 u = (std::sin(half) / norm(axis)) * axis;
    const Vec3d velocity{0.3 * std::sin(3.0 * k), 0.3 * std::cos(5.0 * k), -0.2 - 0.3 * (k / 9)};
    ParticleInit p = shaped_particle(shape, at, Quat{std::cos(half), u.x, u.y, u.z}, velocity,
                                     {100.0 * std::cos(k), 0, 50.0});
    p.radius = radius;
    bodies.push_back(p);
  }
  return bodies;
}

// Rigid-body impact theory (e.g. Brach, Mechanical Impact Dynamics, 1991): a body hitting a
// frictionless wall at point r (from its centre) with normal n gets the impulse
// J = -(1 + e) v_c.n / (1/m + (r x n).I^-1 (r x n)), v_c the contact point's velocity.
struct ImpactPrediction {
  Vec3 velocity, angular_velocity;
};

inline ImpactPrediction rigid_body_impact(double mass, const Mat3& inverse_inertia_world, Vec3 r,
                                          Vec3 n, Vec3 v, Vec3 w, double restitution) {
  const Vec3 rn = cross(r, n);
  const double normal_speed = dot(v + cross(w, r), n);
  const double impulse =
      -(1 + restitution) * normal_speed / (1 / mass + dot(rn, inverse_inertia_world * rn));
  return {v + (impulse / mass) * n, w + inverse_inertia_world * (impulse * rn)};
}

// Steps until the particles have touched a wall and left it again; false (with a test failure
// naming why) when they never touched or are still touching after max_steps.
inline bool run_through_wall_impact(Engine& engine, int max_steps) {
  bool touched = false;
  for (int k = 0; k < max_steps; ++k) {
    engine.step();
    const int contacts = engine.diagnostics().wall_contacts;
    touched = touched || contacts > 0;
    if (touched && contacts == 0)
      return true;
  }
  ADD_FAILURE() << (touched ? "still in contact" : "never touched") << " after " << max_steps
                << " steps";
  return false;
}

} // namespace kdem::testing
