// Triangle-mesh walls against the analytic plane: a sphere meeting a flat mesh on a face, on a
// shared edge or on a shared vertex must behave exactly as on the plane (one contact, same
// overlap, same force); on a convex edge or vertex it must bounce along the line from the
// contact point to its centre.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "mesh_test_support.hpp"
#include "scene_builders.hpp"

namespace kdem::testing {
namespace {

// Flat square [-h, h]^2 at z = 0 as two triangles sharing the diagonal from (-h, -h) to (h, h).
std::vector<Triangle> flat_square(double h) {
  return {Triangle{Vec3d{-h, -h, 0}, Vec3d{h, -h, 0}, Vec3d{h, h, 0}},
          Triangle{Vec3d{-h, -h, 0}, Vec3d{h, h, 0}, Vec3d{-h, h, 0}}};
}

// Flat hexagon of circumradius h at z = 0 as a fan of six triangles around the origin.
std::vector<Triangle> flat_fan(double h) {
  std::vector<Triangle> t;
  for (int k = 0; k < 6; ++k) {
    const double a = k * M_PI / 3, b = (k + 1) * M_PI / 3;
    t.push_back(Triangle{Vec3d{0, 0, 0}, Vec3d{h * std::cos(a), h * std::sin(a), 0},
                         Vec3d{h * std::cos(b), h * std::sin(b), 0}});
  }
  return t;
}

// Roof: a ridge along y at z = 0 from (0, -h, 0) to (0, h, 0), faces falling at `slope` to
// both sides.
std::vector<Triangle> roof(double h, double slope) {
  const double drop = h * std::tan(slope);
  return {Triangle{Vec3d{0, -h, 0}, Vec3d{0, h, 0}, Vec3d{-h, 0, -drop}},
          Triangle{Vec3d{0, h, 0}, Vec3d{0, -h, 0}, Vec3d{h, 0, -drop}}};
}

// Square pyramid with its apex at the origin and its base at z = -depth.
std::vector<Triangle> pyramid(double h, double depth) {
  const Vec3d apex{0, 0, 0};
  const Vec3d base[4] = {{h, h, -depth}, {-h, h, -depth}, {-h, -h, -depth}, {h, -h, -depth}};
  std::vector<Triangle> t;
  for (int k = 0; k < 4; ++k)
    t.push_back(Triangle{apex, base[k], base[(k + 1) % 4]});
  return t;
}

struct Rebound {
  Vec3d velocity{0, 0, 0};
  Vec3d spin{0, 0, 0};
  double peak_force = 0; // N, largest m |dv| / dt over one step
  int most_contacts = 0; // largest Diagnostics::wall_contacts seen
  int contact_steps = 0; // steps with a wall contact
  std::int64_t steps = 0;
};

// Runs the sphere (particle 0) until it has touched and separated again.
Rebound bounce(Engine& engine, double mass, std::int64_t limit = 100000) {
  Rebound r;
  const double dt = engine.time_step();
  Vec3d previous{0, 0, 0};
  bool touched = false;
  for (std::int64_t k = 0; k < limit; ++k) {
    const ParticleSnapshot s = engine.snapshot();
    const Diagnostics d = engine.diagnostics();
    const Vec3d v{s.velocity[0], s.velocity[1], s.velocity[2]};
    if (k > 0) {
      const Vec3d dv = sub(v, previous);
      r.peak_force = std::max(r.peak_force, mass * std::sqrt(dot(dv, dv)) / dt);
    }
    previous = v;
    r.most_contacts = std::max(r.most_contacts, d.wall_contacts);
    if (d.wall_contacts > 0) {
      touched = true;
      ++r.contact_steps;
    } else if (touched) {
      r.velocity = v;
      r.spin = {s.angular_velocity[0], s.angular_velocity[1], s.angular_velocity[2]};
      r.steps = k;
      return r;
    }
    engine.step();
  }
  ADD_FAILURE() << "the sphere did not bounce within " << limit << " steps";
  return r;
}

struct Setup {
  MaterialConfig material;
  double radius = 5e-3, speed = 1.0;
  double mass() const { return material.density * 4.0 / 3.0 * M_PI * std::pow(radius, 3); }
  // dt = t_c / 1000 for a head-on impact at `speed` on a plane of the same material.
  double time_step() const {
    return hertz_impact(mass(), radius, effective_youngs(material, material), speed).duration /
           1000;
  }
};

Setup default_setup() {
  Setup s;
  s.material = material("steel", 7800, 2e11, 0.3, 0.7, 0.3);
  return s;
}

// The sphere starts `start_gap` off the surface point `contact`, on the side `normal`, moving
// with `velocity`; the wall is the given mesh file, or the analytic plane through `contact`
// with that normal when `file` is empty.
Rebound drop(const Setup& setup, const std::string& file, const Vec3d& contact, const Vec3d& normal,
             const Vec3d& velocity) {
  SceneConfig scene = empty_scene(setup.time_step(), {setup.material});
  scene.walls.push_back(file.empty() ? plane_wall(setup.material.name, contact, normal)
                                     : mesh_wall(setup.material.name, file));
  Engine engine(scene);
  const double start_gap = 5.5 * std::abs(dot(velocity, normal)) * engine.time_step();
  engine.add_particles(
      {sphere(along(contact, normal, setup.radius + start_gap), setup.radius, velocity)});
  return bounce(engine, setup.mass());
}

// Mesh and plane give the same rebound to 1e-9 relative: the only differences are the rounding
// of the closest-point computation (relative 1e-16 of the distance, i.e. 1e-16 R / d ~ 1e-13 of
// the overlap here), accumulated over ~1000 steps.
void expect_same_as_plane(const Rebound& mesh, const Rebound& plane, double speed) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mesh.velocity[c], plane.velocity[c], 1e-9 * speed) << "component " << c;
    EXPECT_NEAR(mesh.spin[c], plane.spin[c], 1e-9 * speed / 5e-3) << "component " << c;
  }
  EXPECT_NEAR(mesh.peak_force, plane.peak_force, 1e-9 * plane.peak_force);
  EXPECT_EQ(mesh.steps, plane.steps);
  EXPECT_EQ(mesh.contact_steps, plane.contact_steps);
  EXPECT_EQ(mesh.most_contacts, 1);
  EXPECT_EQ(plane.most_contacts, 1);
}

// (a)-(c): flat meshes, dropped head-on and obliquely (with friction: v_t = 0.5 v_n).
void check_flat(const std::vector<Triangle>& triangles, const Vec3d& contact) {
  MeshFolder folder;
  const std::string file = folder.write("flat", triangles);
  const Setup setup = default_setup();
  for (const Vec3d velocity :
       {Vec3d{0, 0, -setup.speed}, Vec3d{0.3 * setup.speed, -0.4 * setup.speed, -setup.speed}}) {
    const Rebound plane = drop(setup, "", contact, {0, 0, 1}, velocity);
    const Rebound mesh = drop(setup, file, contact, {0, 0, 1}, velocity);
    expect_same_as_plane(mesh, plane, setup.speed);
    // And the plane's own rebound has the requested restitution (as in test_hertz_impacts).
    EXPECT_NEAR(plane.velocity[2], setup.material.restitution * setup.speed, 5e-3 * setup.speed);
  }
}

TEST(MeshWall, FlatFaceFarFromEdgesActsAsThePlane) {
  check_flat(flat_square(0.05), {-0.02, 0.025, 0});
}

TEST(MeshWall, SharedEdgeOfAFlatMeshActsAsThePlane) {
  check_flat(flat_square(0.05), {0.01, 0.01, 0});
}

TEST(MeshWall, SharedVertexOfAFlatFanActsAsThePlane) {
  check_flat(flat_fan(0.05), {0, 0, 0});
}

// (d), (e): convex features. The sphere comes in head-on along a direction n inside the
// feature's normal cone (so the closest point stays on the ridge or the apex): it must leave
// along n, with the requested restitution. The contact is the plane's normal impact along n
// (the same overlap history), so the rebound speed also equals the plane's to 1e-9.
void check_convex(const std::vector<Triangle>& triangles, const Vec3d& normal) {
  MeshFolder folder;
  const std::string file = folder.write("convex", triangles);
  const Setup setup = default_setup();
  const Vec3d velocity{-setup.speed * normal[0], -setup.speed * normal[1],
                       -setup.speed * normal[2]};
  const Rebound mesh = drop(setup, file, {0, 0, 0}, normal, velocity);
  const Rebound plane = drop(setup, "", {0, 0, 0}, normal, velocity);
  const double speed = std::sqrt(dot(mesh.velocity, mesh.velocity));
  const Vec3d off_line = cross(mesh.velocity, normal);
  // Direction: the sine of the angle between the rebound and n, 1e-12 (round-off only: every
  // force acts along n).
  EXPECT_LT(std::sqrt(dot(off_line, off_line)), 1e-12 * speed);
  EXPECT_GT(dot(mesh.velocity, normal), 0.0);
  EXPECT_NEAR(speed / setup.speed, setup.material.restitution, 0.01 * setup.material.restitution);
  EXPECT_NEAR(speed, std::sqrt(dot(plane.velocity, plane.velocity)), 1e-9 * setup.speed);
  EXPECT_EQ(mesh.most_contacts, 1);
}

// Ridge faces at 30 degrees: the ridge's normal cone spans +-30 degrees about +z in the x-z
// plane; the sphere comes in at 12 degrees from the vertical.
TEST(MeshWall, ConvexEdgeBouncesAlongTheContactLine) {
  const double slope = 30 * M_PI / 180, tilt = 12 * M_PI / 180;
  check_convex(roof(0.05, slope), {std::sin(tilt), 0, std::cos(tilt)});
}

// Pyramid with 45 degree faces: the apex's normal cone contains every direction n with
// n . e <= 0 for the four edge directions e = (+-1, +-1, -1) / sqrt(3); (0.1, 0.15, 1) is inside.
TEST(MeshWall, ConvexVertexBouncesAlongTheContactLine) {
  check_convex(pyramid(0.05, 0.05), unit({0.1, 0.15, 1.0}));
}

// Every centre position is claimed by exactly one mesh feature (kernels/walls.hpp,
// claimed_triangle_feature), also within the tolerance band that separates faces, edges and
// vertices: these tests place spheres inside that band.
// Resting on a flat mesh under gravity: the number of contacts when the centre sits a hair's
// breadth (1e-13 .. 3e-12 m, i.e. inside the band of 1e-9 of the mesh size) off the shared
// diagonal edge, on either side, and off the centre vertex of a fan, in 24 directions.
int contacts_when_resting_at(const std::string& file, double x, double y) {
  const MaterialConfig m = material("steel", 7800, 2e11, 0.3, 0.5, 0.0);
  const double radius = 5e-3, g = 9.81;
  const double mass = m.density * 4.0 / 3.0 * M_PI * std::pow(radius, 3);
  const double overlap =
      std::pow(mass * g / (4.0 / 3.0 * effective_youngs(m, m) * std::sqrt(radius)), 2.0 / 3.0);
  SceneConfig scene = empty_scene(2e-6, {m});
  scene.gravity = {0, 0, -g};
  scene.walls.push_back(mesh_wall("steel", file));
  Engine engine(scene);
  engine.add_particles({sphere({x, y, radius - overlap}, radius)});
  return engine.diagnostics().wall_contacts;
}

TEST(MeshWall, OneContactNextToASharedEdgeOrVertex) {
  MeshFolder folder;
  const std::string square = folder.write("square", flat_square(0.05));
  const std::string fan = folder.write("fan", flat_fan(0.05));
  for (double offset : {-3e-12, -1e-12, -1e-13, 0.0, 1e-13, 1e-12, 3e-12}) {
    const double shift = offset / std::sqrt(2.0); // perpendicular to the diagonal x = y
    EXPECT_EQ(contacts_when_resting_at(square, 0.004 - shift, 0.004 + shift), 1)
        << "edge, offset " << offset;
  }
  for (int k = 0; k < 24; ++k)
    for (double offset : {1e-13, 1e-12, 3e-12})
      EXPECT_EQ(contacts_when_resting_at(fan, offset * std::cos(k * M_PI / 12),
                                         offset * std::sin(k * M_PI / 12)),
                1)
          << "vertex, direction " << 15 * k << " deg, offset " << offset;
}

// A sphere resting on a flat two-triangle mesh under gravity slides (mu = 0) across the shared
// diagonal edge: the mesh must give the same trajectory as the analytic plane, with exactly
// one contact at every step (no bump where the triangles meet). The start point and speed put
// the centre on the edge at step 15000 up to the round-off of the position updates (~1e-12 m),
// the case that reveals the bug above (there: 2 contacts and a vertical kick of g dt).
TEST(MeshWall, SphereSlidesAcrossASharedEdgeWithoutABump) {
  MeshFolder folder;
  const std::string file = folder.write("flat", flat_square(0.05));
  const MaterialConfig m = material("steel", 7800, 2e11, 0.3, 0.5, 0.0);
  const double radius = 5e-3, g = 9.81;
  const double mass = m.density * 4.0 / 3.0 * M_PI * std::pow(radius, 3);
  const double overlap =
      std::pow(mass * g / (4.0 / 3.0 * effective_youngs(m, m) * std::sqrt(radius)), 2.0 / 3.0);
  struct Track {
    std::vector<double> height, vertical_speed;
    int most_contacts = 0, fewest_contacts = 100;
  };
  auto slide = [&](bool on_mesh) {
    SceneConfig scene = empty_scene(2e-6, {m});
    scene.gravity = {0, 0, -g};
    scene.walls.push_back(on_mesh ? mesh_wall("steel", file)
                                  : plane_wall("steel", {0, 0, 0}, {0, 0, 1}));
    Engine engine(scene);
    // Crosses the diagonal x = y at x = 0.004 after 0.03 s.
    engine.add_particles({sphere({-0.011, 0.004, radius - overlap}, radius, {0.5, 0, 0})});
    Track t;
    for (int k = 0; k < 30000; ++k) {
      engine.step();
      const ParticleSnapshot s = engine.snapshot();
      const Diagnostics d = engine.diagnostics();
      t.height.push_back(s.position[2]);
      t.vertical_speed.push_back(s.velocity[2]);
      t.most_contacts = std::max(t.most_contacts, d.wall_contacts);
      t.fewest_contacts = std::min(t.fewest_contacts, d.wall_contacts);
    }
    return t;
  };
  const Track plane = slide(false), mesh = slide(true);
  double worst_height = 0, worst_speed = 0, largest_speed = 0;
  for (std::size_t k = 0; k < plane.height.size(); ++k) {
    worst_height = std::max(worst_height, std::abs(mesh.height[k] - plane.height[k]));
    worst_speed = std::max(worst_speed, std::abs(mesh.vertical_speed[k] - plane.vertical_speed[k]));
    largest_speed = std::max(largest_speed, std::abs(mesh.vertical_speed[k]));
  }
  // Same trajectory to 1e-9 of the resting overlap (round-off, as above), and the vertical
  // speed stays at the plane's (it is 0 up to the resting oscillation's round-off).
  EXPECT_LT(worst_height, 1e-9 * overlap);
  EXPECT_LT(worst_speed, 1e-9 * 0.5);
  EXPECT_EQ(mesh.most_contacts, 1);
  EXPECT_EQ(mesh.fewest_contacts, 1);
}

// A sphere rolls without slipping down a 10 degree slope (gravity tilted; the surface is z = 0)
// across a flat mesh of 1 cm squares cut into triangles, crossing axis-parallel and diagonal
// edges: static friction, the tangential spring, carries (2/7) m g sin(10 deg) all the way. The
// mesh must give the analytic plane's trajectory within 1 % in position and velocity, and its
// force at every step within 1 %, which it does only if the spring passes from each triangle to
// the next.
TEST(MeshWall, SphereRollsAcrossTrianglesWithItsTangentialSpring) {
  MeshFolder folder;
  const std::string file = folder.write("grid", flat_grid(0.1, 0, 20));
  const MaterialConfig m = material("rubber", 2500, 1e7, 0.3, 0.5, 0.5);
  const double radius = 5e-3, g = 9.81, slope = 10 * M_PI / 180, dt = 2e-5;
  const double mass = m.density * 4.0 / 3.0 * M_PI * std::pow(radius, 3);
  const double rest = std::pow(mass * g * std::cos(slope) /
                                   (4.0 / 3.0 * effective_youngs(m, m) * std::sqrt(radius)),
                               2.0 / 3.0);
  const Vec3d downhill = unit({1, 0.37, 0});
  struct Track {
    std::vector<Vec3d> position, velocity;
  };
  auto roll = [&](bool on_mesh) {
    SceneConfig scene = empty_scene(dt, {m});
    scene.gravity = {g * std::sin(slope) * downhill[0], g * std::sin(slope) * downhill[1],
                     -g * std::cos(slope)};
    scene.walls.push_back(on_mesh ? mesh_wall("rubber", file)
                                  : plane_wall("rubber", {0, 0, 0}, {0, 0, 1}));
    Engine engine(scene);
    engine.add_particles({sphere({-0.0633, -0.0247, radius - rest}, radius)});
    Track t;
    for (int k = 0; k < 15000; ++k) {
      engine.step();
      const ParticleSnapshot s = engine.snapshot();
      t.position.push_back({s.position[0], s.position[1], s.position[2]});
      t.velocity.push_back({s.velocity[0], s.velocity[1], s.velocity[2]});
    }
    return t;
  };
  const Track plane = roll(false), mesh = roll(true);
  const Vec3d start = plane.position.front();
  double worst_position = 0, worst_velocity = 0;
  for (std::size_t k = 0; k < plane.position.size(); ++k) {
    const Vec3d travelled = sub(plane.position[k], start);
    const double distance = std::sqrt(dot(travelled, travelled)) + 1e-3; // from 1 mm on
    const double speed = std::sqrt(dot(plane.velocity[k], plane.velocity[k])) + 1e-3;
    const Vec3d dx = sub(mesh.position[k], plane.position[k]);
    const Vec3d dv = sub(mesh.velocity[k], plane.velocity[k]);
    worst_position = std::max(worst_position, std::sqrt(dot(dx, dx)) / distance);
    worst_velocity = std::max(worst_velocity, std::sqrt(dot(dv, dv)) / speed);
  }
  // The plane's run rolls without slipping: (5/7) g sin(slope) along the slope.
  const double expected_speed = 5.0 / 7.0 * g * std::sin(slope) * 15000 * dt;
  const double speed = std::sqrt(dot(plane.velocity.back(), plane.velocity.back()));
  EXPECT_NEAR(speed, expected_speed, 0.01 * expected_speed);
  const Vec3d travelled = sub(plane.position.back(), start);
  EXPECT_GT(std::sqrt(dot(travelled, travelled)), 0.045); // 5.5 cm: across about ten edges
  EXPECT_LT(worst_position, 0.01);
  EXPECT_LT(worst_velocity, 0.01);
  // The force too: the acceleration, step by step, is the plane's. A spring restarted at an edge
  // lets the sphere slip there, the friction force gone for a few steps (the acceleration then
  // g sin(slope), 40 % above the rolling one); trajectories hardly show it (0.3 % in velocity
  // here), the force does.
  const double rolling_acceleration = 5.0 / 7.0 * g * std::sin(slope);
  double worst_acceleration = 0;
  for (std::size_t k = 100; k + 1 < plane.velocity.size(); ++k) {
    const Vec3d dv = sub(sub(mesh.velocity[k + 1], mesh.velocity[k]),
                         sub(plane.velocity[k + 1], plane.velocity[k]));
    worst_acceleration =
        std::max(worst_acceleration, std::sqrt(dot(dv, dv)) / dt / rolling_acceleration);
  }
  EXPECT_LT(worst_acceleration, 0.01);
}

} // namespace
} // namespace kdem::testing
