// Level-set bodies against the curved and meshed walls (kernels/level_set/walls.hpp, book 5.3),
// through the engine, one step from rest: a box's corners beyond the inside of a cylinder, a
// mesh ridge's edge and a mesh pyramid's tip pressed into the box's bottom face, each against
// the overlap its closed form gives and the Hertz force of that overlap.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "dilated_test_support.hpp"
#include "mesh_test_support.hpp"
#include "scene_builders.hpp"
#include "shapes/level_set_build.hpp"
#include "src/level_set_scene.hpp"

namespace kdem::testing {
namespace {

constexpr double pi = 3.14159265358979323846;

// The box every test presses: half-widths 2, 1.5 and 1 mm, grid spacing 0.2 mm, points 0.5 mm
// apart (their seed is the builder's default, as in the engine).
constexpr double box_a = 2e-3, box_b = 1.5e-3, box_c = 1e-3;
constexpr double grid_spacing = 0.2e-3, point_spacing = 0.5e-3;
// The closed-form overlap of every test: 2 um, a thousandth of the box's size.
constexpr double overlap = 2e-6;

ShapeConfig level_set_box() {
  const test::CoreMesh mesh = test::box_mesh(box_a, box_b, box_c);
  std::vector<std::array<double, 3>> points;
  for (const Vec3& p : mesh.points)
    points.push_back({p.x, p.y, p.z});
  return level_set_shape_config("box", points, mesh.triangles, grid_spacing, point_spacing);
}
double box_equivalent_radius() {
  return std::cbrt(3 * 8 * box_a * box_b * box_c / (4 * pi));
}

// The box's own surface points, as the engine builds them (its mesh is in its principal frame).
std::vector<Vec3> box_points() {
  const test::CoreMesh mesh = test::box_mesh(box_a, box_b, box_c);
  LevelSetOptions options;
  options.spacing = grid_spacing;
  options.point_spacing = point_spacing;
  return build_level_set(mesh.points, mesh.triangles, options).surface_points;
}

const MaterialConfig glass = material("glass", 2500, 1e8, 0.3, 1.0, 0.0);

double hertz_force(double depth) {
  const double e_star = effective_youngs(glass, glass);
  return 4.0 / 3.0 * e_star * std::sqrt(box_equivalent_radius()) * std::pow(depth, 1.5);
}

// One step (1 ns: the box moves by 1e-16 m) of the box at rest at `centre`; the wall contacts'
// forces.
std::vector<ContactForceRecord> forces_after_one_step(const WallConfig& wall, Vec3d centre) {
  SceneConfig scene = empty_scene(1e-9, {glass});
  scene.shapes.push_back(level_set_box());
  scene.walls.push_back(wall);
  Engine engine(scene);
  engine.add_particles({shaped_particle(1, centre, Quat{1, 0, 0, 0})});
  engine.step();
  return engine.contact_forces();
}

double magnitude(const ContactForceRecord& r) {
  return std::sqrt(r.force[0] * r.force[0] + r.force[1] * r.force[1] + r.force[2] * r.force[2]);
}

// Inside a cylinder of radius 3 mm (axis z), the box's centre off the axis along x so that its
// two vertical edges at x = +a, y = +-b (corners and edge points) lie `overlap` beyond the wall:
// rho = sqrt((d + a)^2 + b^2) = R + overlap. Every other point is more than 50 um inside. Two
// contacts (the edges' normals differ by 60 degrees, beyond the averaging angle), each the Hertz
// force of that overlap pointing to the axis from its edge; the element's record is their sum,
// 2 F (d + a) / rho along -x, none along y (one contact alone would push along y by F b / rho).
// Stated: 1e-6 relative (the overlap is a difference of millimetres, exact to 1e-13 of it).
TEST(LevelSetWalls, CornersBeyondACylinderAtTheirClosedFormOverlap) {
  const double radius = 3e-3;
  const double rho = radius + overlap;
  const double x = std::sqrt(rho * rho - box_b * box_b); // of the edges
  WallConfig wall;
  wall.kind = WallConfig::Kind::Cylinder;
  wall.name = "cylinder";
  wall.material = "glass";
  wall.base_center = {0, 0, -0.01};
  wall.axis_direction = {0, 0, 1};
  wall.radius = radius;
  wall.length = 0.02;
  const std::vector<ContactForceRecord> records = forces_after_one_step(wall, {x - box_a, 0, 0});
  ASSERT_EQ(records.size(), 1u);
  const double each = hertz_force(overlap);
  EXPECT_EQ(records[0].wall, 0);
  EXPECT_NEAR(records[0].force[0], -2 * each * x / rho, 1e-6 * each);
  EXPECT_NEAR(records[0].force[1], 0, 1e-9 * each);
  EXPECT_NEAR(records[0].force[2], 0, 1e-9 * each);
}

// A mesh ridge (two 45-degree slopes meeting along the x axis at z = 0) under the box's bottom
// face, which lies `overlap` below the ridge: the ridge's edge points inside the box's grid find
// the box's value there, exact near a face (the box's distance is affine there), so one contact
// of that overlap pushes the box straight up. The box is shifted sideways so that none of its
// points lies within twice `overlap` of the ridge's line (the first of a few shifts that
// clears them), so no point of the box is beyond a slope. Stated: 1e-6 relative.
TEST(LevelSetWalls, MeshRidgeEdgeInsideTheFaceAtItsClosedFormOverlap) {
  const std::vector<Vec3> points = box_points();
  const auto clear = [&](double shift) {
    return std::none_of(points.begin(), points.end(), [&](const Vec3& p) {
      return p.z < -box_c + 1e-12 && std::fabs(p.y + shift) <= 2 * overlap;
    });
  };
  double shift = 0;
  for (double tried : {0.1e-3, 0.13e-3, 0.17e-3, 0.23e-3, 0.29e-3})
    if (shift == 0 && clear(tried))
      shift = tried;
  ASSERT_NE(shift, 0) << "every shift tried has a point on the ridge";
  const double half = 5e-3;
  const Vec3d west_top{-half, 0, 0}, east_top{half, 0, 0};
  const std::vector<Triangle> ridge = {
      {west_top, Vec3d{half, -half, -half}, east_top},
      {west_top, Vec3d{-half, -half, -half}, Vec3d{half, -half, -half}},
      {west_top, east_top, Vec3d{half, half, -half}},
      {west_top, Vec3d{half, half, -half}, Vec3d{-half, half, -half}},
  };
  const MeshFolder folder;
  const std::vector<ContactForceRecord> records = forces_after_one_step(
      mesh_wall("glass", folder.write("ridge", ridge)), {0, shift, box_c - overlap});
  ASSERT_EQ(records.size(), 1u);
  const double expected = hertz_force(overlap);
  EXPECT_NEAR(records[0].force[2], expected, 1e-6 * expected);
  EXPECT_NEAR(records[0].force[0], 0, 1e-9 * expected);
  EXPECT_NEAR(records[0].force[1], 0, 1e-9 * expected);
}

// A mesh pyramid (four 45-degree faces meeting at a tip at the origin) under the box's bottom
// face, `overlap` above the tip: the tip, a vertex of all four triangles and owned by one, finds
// the box's value there, exact near a face: one contact of that overlap pushes the box straight
// up. No point of the box lies within `overlap` of the tip's vertical (checked). Stated: 1e-6.
TEST(LevelSetWalls, MeshPyramidTipInsideTheFaceAtItsClosedFormOverlap) {
  // The box is shifted sideways so that the tip lies away from its face's symmetry lines.
  const Vec3d shift{0.3e-3, -0.2e-3, 0};
  for (const Vec3& p : box_points())
    ASSERT_FALSE(p.z < -box_c + 1e-12 && std::hypot(p.x + shift[0], p.y + shift[1]) <= 2 * overlap)
        << "a point on the tip";
  const double half = 5e-3;
  const Vec3d tip{0, 0, 0};
  const auto base = [&](double x, double y) { return Vec3d{x * half, y * half, -half}; };
  const std::vector<Triangle> pyramid = {
      {tip, base(-1, -1), base(1, -1)},
      {tip, base(1, -1), base(1, 1)},
      {tip, base(1, 1), base(-1, 1)},
      {tip, base(-1, 1), base(-1, -1)},
  };
  const MeshFolder folder;
  const std::vector<ContactForceRecord> records = forces_after_one_step(
      mesh_wall("glass", folder.write("pyramid", pyramid)), {shift[0], shift[1], box_c - overlap});
  ASSERT_EQ(records.size(), 1u);
  const double expected = hertz_force(overlap);
  EXPECT_NEAR(records[0].force[2], expected, 1e-6 * expected);
  EXPECT_NEAR(records[0].force[0], 0, 1e-9 * expected);
  EXPECT_NEAR(records[0].force[1], 0, 1e-9 * expected);
}

} // namespace
} // namespace kdem::testing
