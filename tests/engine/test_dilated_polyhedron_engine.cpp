// Dilated polyhedra through the whole engine: a box resting flat on a plane carries its weight at
// the overlap the averaged Hertz law gives (mass, averaging and force law together), elastic
// collisions keep their energy (box on box, tetrahedron on box, sphere on box), a concave body
// lands on both legs, superquadrics, poly-superquadrics and clumps collide with it elastically,
// and an open mesh is refused with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "../../shapes/sphere.hpp"
#include "collision_test_support.hpp"
#include "dilated_test_support.hpp"
#include "mesh_test_support.hpp"
#include "scene_builders.hpp"
#include "src/clump_scene.hpp"
#include "src/dilated_polyhedron_scene.hpp"
#include "src/poly_superquadric_scene.hpp"
#include "src/superquadric_scene.hpp"

namespace kdem::testing {
namespace {

ShapeConfig dilated_shape(const std::string& name, const test::CoreMesh& mesh, double radius,
                          double mass_precision = 1e-4) {
  std::vector<std::array<double, 3>> points;
  for (const Vec3& p : mesh.points)
    points.push_back({p.x, p.y, p.z});
  return dilated_polyhedron_shape_config(name, points, mesh.triangles, radius, mass_precision);
}

// The volume of a box of half-widths a, b, c dilated by r (core, slabs, quarter cylinders and
// eighth spheres).
double dilated_box_volume(double a, double b, double c, double r) {
  return 8 * a * b * c + 8 * r * (a * b + b * c + c * a) + 2 * pi * r * r * (a + b + c) +
         4.0 / 3.0 * pi * r * r * r;
}

TEST(DilatedPolyhedronEngine, BoxRestingOnAPlaneCarriesItsWeight) {
  const double a = 2e-3, b = 1.5e-3, c = 1e-3, r = 0.5e-3, density = 2500;
  const MaterialConfig stone = material("stone", density, 1e8, 0.3, 0.3, 0.5);
  SceneConfig scene = empty_scene(1e-6, {stone});
  scene.gravity = {0, 0, -9.81};
  scene.shapes.push_back(dilated_shape("box", test::box_mesh(a, b, c), r));
  scene.walls.push_back(plane_wall("stone", {0, 0, 0}, {0, 0, 1}));
  Engine engine(scene);
  engine.add_particles({shaped_particle(1, {0, 0, c + r + 1e-5}, Quat{1, 0, 0, 0})});
  for (int k = 0; k < 30000; ++k)
    engine.step();
  const ParticleSnapshot s = engine.snapshot();
  // At rest on its four bottom corners, each weighted 1/4 (equal overlaps): the total force is
  // one Hertz contact of the body's equivalent radius at the common overlap (book Eq. 4.19).
  const double volume = dilated_box_volume(a, b, c, r);
  const double weight = density * volume * 9.81;
  const double equivalent = std::cbrt(3 * volume / (4 * pi));
  const double e_star = 1e8 / (2 * (1 - 0.3 * 0.3)); // both sides of the same material
  const double overlap = std::pow(weight / (4.0 / 3.0 * e_star * std::sqrt(equivalent)), 2.0 / 3.0);
  EXPECT_NEAR(s.position[2], c + r - overlap, 0.01 * overlap) << "overlap " << overlap;
  EXPECT_NEAR(s.position[0], 0, 1e-9);
  EXPECT_LT(std::fabs(s.velocity[2]), 1e-6);
  EXPECT_EQ(engine.diagnostics().wall_contacts, 4);
  EXPECT_EQ(engine.narrow_phase_totals().failures, 0);
}

// A mesh wall is two-sided: a box resting on a one-triangle-pair floor carries its weight at
// the plane's overlap whether the triangles are wound up or down (the face's side is turned to
// the particle, its inside test follows the corners' winding).
TEST(DilatedPolyhedronEngine, BoxRestsOnAMeshFloorOfEitherWinding) {
  const double a = 2e-3, b = 1.5e-3, c = 1e-3, r = 0.5e-3, density = 2500;
  for (bool wound_down : {false, true}) {
    SceneConfig scene = empty_scene(1e-6, {material("stone", density, 1e8, 0.3, 0.3, 0.5)});
    scene.gravity = {0, 0, -9.81};
    scene.shapes.push_back(dilated_shape("box", test::box_mesh(a, b, c), r));
    std::vector<Triangle> floor = flat_grid(0.02, 0, 1);
    if (wound_down)
      for (Triangle& t : floor)
        std::swap(t[1], t[2]);
    MeshFolder folder;
    scene.walls.push_back(mesh_wall("stone", folder.write("floor", floor)));
    Engine engine(scene);
    // Off the floor's diagonal, so that all four corners lie over one triangle.
    engine.add_particles({shaped_particle(1, {6e-3, -6e-3, c + r + 1e-5}, Quat{1, 0, 0, 0})});
    for (int k = 0; k < 30000; ++k)
      engine.step();
    const ParticleSnapshot s = engine.snapshot();
    const double volume = dilated_box_volume(a, b, c, r);
    const double equivalent = std::cbrt(3 * volume / (4 * pi));
    const double e_star = 1e8 / (2 * (1 - 0.3 * 0.3));
    const double overlap =
        std::pow(density * volume * 9.81 / (4.0 / 3.0 * e_star * std::sqrt(equivalent)), 2.0 / 3.0);
    EXPECT_NEAR(s.position[2], c + r - overlap, 0.01 * overlap) << wound_down;
    EXPECT_EQ(engine.diagnostics().wall_contacts, 4) << wound_down;
  }
}

TEST(DilatedPolyhedronEngine, ElasticCollisionsKeepTheirEnergy) {
  // Pairs at assorted orientations thrown at each other with spin, their bounding spheres apart
  // at the start: a box and a tetrahedron (two dilated polyhedra), and a sphere against the box.
  for (int trial = 0; trial < 6; ++trial) {
    SceneConfig scene = elastic_scene();
    scene.shapes.push_back(dilated_shape("box", test::box_mesh(2e-3, 1.5e-3, 1e-3), 0.4e-3));
    scene.shapes.push_back(dilated_shape("tetrahedron", test::tetrahedron_mesh(2.5e-3), 0.4e-3));
    Engine engine(scene);
    const double angle = 0.7 * trial + 0.3;
    const Quat qa{std::cos(angle), std::sin(angle) * 0.6, std::sin(angle) * 0.8, 0};
    const Quat qb{std::cos(2 * angle), 0, std::sin(2 * angle) * 0.6, std::sin(2 * angle) * 0.8};
    ParticleInit other =
        shaped_particle(2, {7e-3, 0.3e-3 * trial, 0}, qb, {-0.5, 0, 0}, {0, 30.0 * trial, 10});
    if (trial >= 4) { // a sphere of about the tetrahedron's size instead
      other = sphere({7e-3, 0.4e-3 * trial - 1e-3, 0.2e-3}, 1.5e-3, {-0.5, 0, 0});
    }
    engine.add_particles({shaped_particle(1, {0, 0, 0}, qa, {0.2, 0, 0}, {0, 0, 20}), other});
    const Collision c = collide(engine, 200000);
    ASSERT_GT(c.pair_contacts, 0) << trial;
    // Stated tolerance: 1e-3 of the energy. The Hertz law is conservative per contact point; the
    // weights of the averaging move only as the overlaps do, and the leapfrog's error at this
    // step (about 1/400 of the contact time) is of order 1e-5.
    EXPECT_NEAR(c.after, c.before, 1e-3 * c.before) << trial;
    EXPECT_EQ(engine.narrow_phase_totals().failures, 0);
  }
}

TEST(DilatedPolyhedronEngine, ConcaveBodyLandsOnBothLegs) {
  // The U prism upside down (legs down) falls flat onto a plane: both leg ends touch at once
  // (their eight corners), the contacts averaged into one force, and it bounces straight back up.
  // It turns only as far as its centroid, integrated to mass_precision, lies off the plane of
  // symmetry: 1e-5 of its radius of gyration (0.5 mm) offsets the impulse 2 m v by 5e-9 m, which
  // turns it by 2 m v 5e-9 / I, 0.06 rad/s here; the test allows 0.2.
  const double unit = 1e-3, r = 0.2e-3;
  SceneConfig scene = empty_scene(2e-7, {material("glass", 2500, 1e8, 0.3, 1.0, 0.0)});
  scene.shapes.push_back(dilated_shape("u", test::u_prism_mesh(unit, unit), r, 1e-5));
  scene.walls.push_back(plane_wall("glass", {0, 0, 0}, {0, 0, 1}));
  Engine engine(scene);
  // Body frame: principal axes through the centroid, along the mesh's axes. The prism's legs
  // point along +y in the mesh; turned by -90 degrees about x, they point down.
  const Quat legs_down{std::sqrt(0.5), -std::sqrt(0.5), 0, 0};
  engine.add_particles({shaped_particle(1, {0, 0, 3e-3}, legs_down, {0, 0, -0.3})});
  int most = 0;
  for (int k = 0; k < 200000 && engine.diagnostics().time < 0.02; ++k) {
    engine.step();
    most = std::max(most, engine.diagnostics().wall_contacts);
    if (most > 0 && engine.diagnostics().wall_contacts == 0)
      break;
  }
  const ParticleSnapshot s = engine.snapshot();
  EXPECT_EQ(most, 8);
  EXPECT_NEAR(s.velocity[2], 0.3, 1e-3);
  const double spin = std::fabs(s.angular_velocity[0]) + std::fabs(s.angular_velocity[1]) +
                      std::fabs(s.angular_velocity[2]);
  RecordProperty("spin_after_bounce", std::to_string(spin));
  EXPECT_LT(spin, 0.2);
}

// A clump of a cube-like superquadric element and a sphere element.
ShapeConfig mixed_clump(double r0) {
  ClumpElementParameters cube;
  cube.half_axes = {r0, r0, r0};
  cube.n1 = cube.n2 = 6;
  ClumpElementParameters ball;
  ball.sphere = true;
  ball.half_axes = {r0, r0, r0};
  ball.position = {0, 0, 1.5 * r0};
  return clump_shape_config("clump", {cube, ball});
}

TEST(DilatedPolyhedronEngine, OtherFamiliesCollideWithItElastically) {
  // A superquadric, a poly-superquadric and a clump (a superquadric and a sphere element) thrown
  // with spin at a dilated box from assorted orientations: the generic convex narrow phase
  // (GJK per core face) through the engine. Stated tolerance as for the polyhedra above: 1e-3.
  const double s = 1.2e-3;
  const std::vector<ShapeConfig> others = {
      superquadric_shape_config("sq", {s, 0.8 * s, 0.6 * s}, 4, 3),
      poly_superquadric_shape_config("psq", {s, 0.8 * s, 0.7 * s}, {0.6 * s, 0.8 * s, 0.5 * s}, 3,
                                     2.5),
      mixed_clump(0.7 * s)};
  for (size_t kind = 0; kind < others.size(); ++kind)
    for (int trial = 0; trial < 3; ++trial) {
      SceneConfig scene = elastic_scene();
      scene.shapes.push_back(dilated_shape("box", test::box_mesh(2e-3, 1.5e-3, 1e-3), 0.4e-3));
      scene.shapes.push_back(others[kind]);
      Engine engine(scene);
      const double angle = 0.9 * trial + 0.4;
      const Quat qa{std::cos(angle), std::sin(angle) * 0.6, std::sin(angle) * 0.8, 0};
      const Quat qb{std::cos(2 * angle), 0, std::sin(2 * angle) * 0.6, std::sin(2 * angle) * 0.8};
      engine.add_particles(
          {shaped_particle(1, {0, 0, 0}, qa, {0.2, 0, 0}, {0, 0, 20}),
           shaped_particle(2, {7e-3, 0.4e-3 * trial, 0}, qb, {-0.5, 0, 0}, {0, 30, 10.0 * trial})});
      const Collision c = collide(engine, 200000);
      ASSERT_GT(c.pair_contacts, 0) << others[kind].name << " " << trial;
      EXPECT_NEAR(c.after, c.before, 1e-3 * c.before) << others[kind].name << " " << trial;
      EXPECT_EQ(engine.narrow_phase_totals().failures, 0);
      EXPECT_EQ(engine.narrow_phase_totals().fallbacks, 0); // no contact deeper than the dilation
    }
}

TEST(DilatedPolyhedronEngine, AxisymmetricMeshKeepsItsOwnFrame) {
  // A square prism (equal moments about x and y) written turned by 30 degrees about z: its
  // integrated products of inertia are noise within mass_precision, and the body frame must stay
  // the mesh's, not turn about z with the noise. The drawn surface (core moved out by r, body
  // frame) then spans the turned prism's extent along x, as the mesh's own vertices moved out
  // along their angle-weighted normals do.
  const double a = 1e-3, c = 0.4e-3, r = 0.1e-3, turn = pi / 6;
  test::CoreMesh mesh = test::box_mesh(a, a, c);
  for (Vec3& p : mesh.points)
    p = Vec3{std::cos(turn) * p.x - std::sin(turn) * p.y,
             std::sin(turn) * p.x + std::cos(turn) * p.y, p.z};
  SceneConfig scene = elastic_scene();
  scene.shapes.push_back(dilated_shape("prism", mesh, r));
  Engine engine(scene);
  engine.add_particles({shaped_particle(1, {0, 0, 0}, Quat{1, 0, 0, 0})});
  const ParticleSnapshot s = engine.snapshot();
  ASSERT_GE(s.shape_surfaces.size(), 2u);
  const std::vector<double>& points = s.shape_surfaces[1].points;
  double largest_x = -1;
  for (std::size_t k = 0; k + 2 < points.size(); k += 3)
    largest_x = std::max(largest_x, points[k]);
  const DilatedCore core = test::core_of(mesh, r);
  double expected = -1;
  for (std::size_t v = 0; v < core.vertices.size(); ++v)
    expected = std::max(expected, core.vertices[v].position.x + r * core.vertices[v].outward.x);
  // Stated 1e-9 m: the centroid's integration error (the symmetric mesh's centroid is at the
  // origin up to the octree's rounding); a frame turned by the noise shows as a difference of
  // order a times the angle (a 0.6 degree turn: 1e-5 m).
  EXPECT_NEAR(largest_x, expected, 1e-9);
}

TEST(DilatedPolyhedronEngine, OpenMeshesAreRefusedWithTheReason) {
  SceneConfig open = elastic_scene();
  test::CoreMesh mesh = test::box_mesh(1e-3, 1e-3, 1e-3);
  mesh.triangles.pop_back();
  open.shapes.push_back(dilated_shape("lid_missing", mesh, 0.2e-3));
  try {
    Engine engine(open);
    ADD_FAILURE() << "an open mesh was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("lid_missing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("open"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace kdem::testing
