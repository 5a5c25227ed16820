// Level-set bodies against the other families with an exact surface (superquadrics,
// poly-superquadrics, clumps, dilated polyhedra; kernels/level_set/mixed_pairs.hpp), through the
// engine: overlaps against the Hertz closed form at rest and for a corner pressed between the
// level-set body's points, and the energy of elastic collisions.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "collision_test_support.hpp"
#include "dilated_test_support.hpp"
#include "scene_builders.hpp"
#include "shapes/superquadric.hpp"
#include "shapes/superquadric_properties.hpp"
#include "src/clump_scene.hpp"
#include "src/dilated_polyhedron_scene.hpp"
#include "src/level_set_scene.hpp"
#include "src/poly_superquadric_scene.hpp"

namespace kdem::testing {
namespace {

constexpr double pi = 3.14159265358979323846;

std::vector<std::array<double, 3>> rows_of(const test::CoreMesh& mesh) {
  std::vector<std::array<double, 3>> points;
  for (const Vec3& p : mesh.points)
    points.push_back({p.x, p.y, p.z});
  return points;
}

// The level-set box every test meets: half-widths 2, 1.5 and 1 mm, grid spacing and points'
// spacing as given.
constexpr double box_a = 2e-3, box_b = 1.5e-3, box_c = 1e-3;
ShapeConfig level_set_box(double spacing, double point_spacing) {
  return level_set_shape_config("box", rows_of(test::box_mesh(box_a, box_b, box_c)),
                                test::box_mesh(box_a, box_b, box_c).triangles, spacing,
                                point_spacing);
}
double box_equivalent_radius() {
  return std::cbrt(3 * 8 * box_a * box_b * box_c / (4 * pi));
}

ClumpElementParameters sphere_element(double radius, Vec3d position) {
  ClumpElementParameters e;
  e.sphere = true;
  e.half_axes = {radius, radius, radius};
  e.position = position;
  return e;
}

double series(double a, double b) {
  return a * b / (a + b);
}

// A body of another family to set on the box: its shape, the height of its lowest point below
// its centroid, and the Hertz radius of its contact with the box.
struct Partner {
  std::string name;
  ShapeConfig shape;
  double lowest = 0;
  double hertz_radius = 0;
};

std::vector<Partner> partners() {
  const double r = 0.6e-3, w = 0.5e-3, dilation = 0.2e-3;
  const double box = box_equivalent_radius();
  // A dilated cube: core (2w)^3, its faces swept by the dilation, quarter cylinders along its
  // 12 edges and a sphere at its corners.
  const double dilated_volume = 8 * w * w * w + 6 * 4 * w * w * dilation +
                                3 * pi * 2 * w * dilation * dilation +
                                4.0 / 3.0 * pi * dilation * dilation * dilation;
  const test::CoreMesh cube = test::box_mesh(w, w, w);
  return {
      {"superquadric sphere", superquadric_shape_config("sq", {r, r, r}, 2, 2), r, series(r, box)},
      {"poly-superquadric sphere",
       poly_superquadric_shape_config("poly", {r, r, r}, {r, r, r}, 2, 2), r, series(r, box)},
      {"clump of two spheres",
       clump_shape_config("clump",
                          {sphere_element(r, {-0.5e-3, 0, 0}), sphere_element(r, {0.5e-3, 0, 0})}),
       r, series(r, box)},
      {"dilated cube",
       dilated_polyhedron_shape_config("dilated", rows_of(cube), cube.triangles, dilation),
       w + dilation, series(std::cbrt(3 * dilated_volume / (4 * pi)), box)},
  };
}

// Hertz (the engine's law, Eqs. 5.17 to 5.22): the overlap that carries force f.
double hertz_overlap(double force, double e_star, double radius) {
  return std::pow(force / (4.0 / 3.0 * e_star * std::sqrt(radius)), 2.0 / 3.0);
}

// At rest on the box (which rests on a plane), each body sinks into the box's top face by the
// Hertz overlap of the force it rests with: the pair's contacts (the body's lowest point found
// in the box's grid, exact for a box's face, and the box's points inside the body) give one
// contact of the body's lowest point. Stated: 1 % of the overlap, as for a body on a wall (what
// the damped settling leaves of the motion is far below it).
TEST(LevelSetMixed, EachFamilyRestsOnALevelSetBoxAtTheHertzOverlap) {
  const MaterialConfig stone = material("stone", 2500, 1e8, 0.3, 0.3, 0.5);
  const double e_star = effective_youngs(stone, stone);
  for (const Partner& partner : partners()) {
    SceneConfig scene = empty_scene(1e-6, {stone});
    scene.gravity = {0, 0, -9.81};
    scene.shapes.push_back(level_set_box(0.2e-3, 0.25e-3));
    scene.shapes.push_back(partner.shape);
    scene.walls.push_back(plane_wall("stone", {0, 0, 0}, {0, 0, 1}));
    Engine engine(scene);
    engine.add_particles({shaped_particle(1, {0, 0, box_c + 1e-5}, Quat{1, 0, 0, 0}),
                          shaped_particle(2, {0.2e-3, 0.1e-3, 2 * box_c + partner.lowest + 1e-5},
                                          Quat{1, 0, 0, 0})});
    for (int k = 0; k < 40000; ++k)
      engine.step();
    const ParticleSnapshot s = engine.snapshot();
    double pair_force = 0;
    for (const ContactForceRecord& c : engine.contact_forces())
      if (c.wall < 0)
        pair_force = std::fabs(c.force[2]);
    ASSERT_GT(pair_force, 0) << partner.name;
    const double overlap = hertz_overlap(pair_force, e_star, partner.hertz_radius);
    const double gap = s.position[5] - s.position[2];
    EXPECT_NEAR(gap, box_c + partner.lowest - overlap, 0.01 * overlap)
        << partner.name << ": overlap " << overlap;
    EXPECT_LT(std::fabs(s.velocity[5]), 1e-6) << partner.name;
    EXPECT_EQ(engine.narrow_phase_totals().failures, 0) << partner.name;
  }
}

// A corner pressed into the box's face between its points (spacing 0.5 mm; the corner's
// footprint, microns wide, holds none of them) is found all the same: a blocky superquadric's
// deepest point by its support point, a dilated tetrahedron's by its core vertex, each in the
// box's grid, which is exact there. One step from rest, the force is Hertz's at that overlap.
// Stated: 1e-4 relative, the dilated body's volume being computed to 1e-4 (its equivalent radius
// to a third of that); the step moves the bodies by 1e-16 m.
TEST(LevelSetMixed, CornersBetweenTheLevelSetPointsAreFound) {
  const MaterialConfig glass = material("glass", 2500, 1e8, 0.3, 1.0, 0.0);
  const double e_star = effective_youngs(glass, glass), box = box_equivalent_radius();
  const double overlap = 2e-6;
  const Quat tilted = normalized(Quat{0.9, 0.3, 0.25, 0.1});
  const Mat3 rotation = rotation_matrix(tilted);
  const Vec3 down{0, 0, -1};
  // The blocky superquadric's lowest point: its support point along -z.
  const SuperquadricShape blocky = make_superquadric(0.8e-3, 0.6e-3, 0.5e-3, 8, 8);
  const double blocky_radius = std::cbrt(3 * superquadric_volume(blocky) / (4 * pi));
  const double sq_lowest =
      (rotation * superquadric_support_point(blocky, transpose_times(rotation, down))).z;
  // The dilated regular tetrahedron's: its lowest core vertex, less the dilation. Its volume by
  // Steiner's formula: V + S r + M r^2 + 4/3 pi r^3, M the sum over edges of the length times
  // half the exterior dihedral angle (pi - acos(1/3)).
  const double dilation = 0.1e-3, circumradius = 1e-3;
  const test::CoreMesh tetrahedron = test::tetrahedron_mesh(circumradius);
  double vertex_lowest = 0;
  for (const Vec3& v : tetrahedron.points)
    vertex_lowest = std::min(vertex_lowest, (rotation * v).z);
  const double edge = circumradius * std::sqrt(8.0 / 3.0);
  const double tetra_volume = edge * edge * edge / (6 * std::sqrt(2.0)) +
                              std::sqrt(3.0) * edge * edge * dilation +
                              3 * edge * (pi - std::acos(1.0 / 3.0)) * dilation * dilation +
                              4.0 / 3.0 * pi * dilation * dilation * dilation;
  struct Case {
    std::string name;
    ShapeConfig shape;
    double centre_height, hertz_radius;
  };
  const std::vector<Case> cases = {
      {"blocky superquadric", superquadric_shape_config("blocky", {0.8e-3, 0.6e-3, 0.5e-3}, 8, 8),
       box_c - sq_lowest - overlap, series(blocky_radius, box)},
      {"dilated tetrahedron",
       dilated_polyhedron_shape_config("tetra", rows_of(tetrahedron), tetrahedron.triangles,
                                       dilation),
       box_c - (vertex_lowest - dilation) - overlap,
       series(std::cbrt(3 * tetra_volume / (4 * pi)), box)},
  };
  for (const Case& c : cases) {
    SceneConfig scene = empty_scene(1e-9, {glass});
    scene.shapes.push_back(level_set_box(0.2e-3, 0.5e-3));
    scene.shapes.push_back(c.shape);
    Engine engine(scene);
    engine.add_particles({shaped_particle(1, {0, 0, 0}, Quat{1, 0, 0, 0}),
                          shaped_particle(2, {0.3e-3, 0.2e-3, c.centre_height}, tilted)});
    engine.step();
    const std::vector<ContactForceRecord> records = engine.contact_forces();
    ASSERT_EQ(records.size(), 1u) << c.name;
    const double expected = 4.0 / 3.0 * e_star * std::sqrt(c.hertz_radius) * std::pow(overlap, 1.5);
    EXPECT_NEAR(std::fabs(records[0].force[2]), expected, 1e-4 * expected) << c.name;
    EXPECT_NEAR(records[0].force[0], 0, 1e-9 * expected) << c.name;
    EXPECT_NEAR(records[0].force[1], 0, 1e-9 * expected) << c.name;
  }
}

// Elastic, frictionless collisions of each family with a level-set tetrahedron at assorted
// orientations and spins: the kinetic energy is kept within 1 % (as for two level-set bodies;
// the patches' deepest points jump between surface points as the bodies turn), 2 % for the
// clump, whose sphere element meets the tetrahedron's sharp edge between two of its points: the
// contact starts only once the overlap reaches the sag of the edge's points, l^2 / 8 r (8 um
// here), and returns more than it took (measured: +1.3 % in the first trial).
TEST(LevelSetMixed, ElasticCollisionsKeepTheirEnergy) {
  for (const Partner& partner : partners()) {
    for (int trial = 0; trial < 3; ++trial) {
      SceneConfig scene = elastic_scene();
      scene.shapes.push_back(
          level_set_shape_config("tetrahedron", rows_of(test::tetrahedron_mesh(2.5e-3)),
                                 test::tetrahedron_mesh(2.5e-3).triangles, 0.2e-3, 0.2e-3));
      scene.shapes.push_back(partner.shape);
      Engine engine(scene);
      const double angle = 0.9 * trial + 0.4;
      const Quat qa{std::cos(angle), std::sin(angle) * 0.6, std::sin(angle) * 0.8, 0};
      const Quat qb{std::cos(2 * angle), 0, std::sin(2 * angle) * 0.6, std::sin(2 * angle) * 0.8};
      engine.add_particles({shaped_particle(1, {0, 0, 0}, qa, {0.2, 0, 0}, {0, 0, 20}),
                            shaped_particle(2, {4.5e-3, 0.4e-3 * trial, 0.2e-3}, qb, {-0.8, 0, 0},
                                            {0, 20.0 * trial, 10})});
      const Collision c = collide(engine, 200000);
      ASSERT_GT(c.pair_contacts, 0) << partner.name << " " << trial;
      RecordProperty("energy_change_" + std::to_string(trial),
                     std::to_string((c.after - c.before) / c.before));
      const double tolerance = partner.name.rfind("clump", 0) == 0 ? 0.02 : 0.01;
      EXPECT_NEAR(c.after, c.before, tolerance * c.before) << partner.name << " " << trial;
      EXPECT_EQ(engine.narrow_phase_totals().failures, 0) << partner.name;
    }
  }
}

} // namespace
} // namespace kdem::testing
