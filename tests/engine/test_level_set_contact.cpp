// Level-set contacts (book chapter 5): surface points of one body in the other's grid against
// closed forms (flat faces pressed together, where the grid's value is exact; spheres, where it
// errs by the mesh's sag and the trilinear error), a sphere against a level-set body (small ones
// through the grid, large ones through the points), and through the whole engine: a box resting
// on a plane carries its weight, elastic collisions keep their energy, a concave body lands on
// both legs, and an open mesh is refused with the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "collision_test_support.hpp"
#include "dilated_test_support.hpp"
#include "kernels/level_set/pairs.hpp"
#include "kernels/level_set/patches.hpp"
#include "scene_builders.hpp"
#include "shapes/level_set_build.hpp"
#include "src/core_builders.hpp"
#include "src/level_set_scene.hpp"

namespace kdem::testing {
namespace {

LevelSetBody body_of(const test::CoreMesh& mesh, double spacing, double point_spacing) {
  LevelSetOptions options;
  options.spacing = spacing;
  options.point_spacing = point_spacing;
  return build_level_set(mesh.points, mesh.triangles, options);
}

test::CoreMesh sphere_mesh(double radius, int nodes) {
  const TriangleMesh sphere = fibonacci_sphere(nodes);
  test::CoreMesh mesh;
  for (const auto& p : sphere.points)
    mesh.points.push_back(radius * Vec3{p[0], p[1], p[2]});
  mesh.triangles = sphere.triangles;
  return mesh;
}

// Every contact found, unmerged.
struct AllContacts {
  std::vector<FeatureContact> contacts;
  void add(const FeatureContact& c) { contacts.push_back(c); }
  const FeatureContact& deepest() const {
    return *std::max_element(contacts.begin(), contacts.end(),
                             [](const auto& a, const auto& b) { return a.overlap < b.overlap; });
  }
};

RelativePose shifted(Vec3 offset) {
  return RelativePose{identity3(), offset};
}

// Box B's bottom face pressed into box A's top face by delta (B above A, shifted sideways so
// that its face lies within A's): A's value is the exact distance to its top face there (the
// signed distance of a box is affine near a face, and trilinear interpolation is exact for an
// affine field), so every point of B's bottom face finds overlap delta and the normal -z (from B
// towards A), to rounding, and a point of B's side edges (whose own points are closer) delta
// less its height above that face. A's corners poke into nothing.
TEST(LevelSetContact, FlatFacesPressedTogetherFindTheExactOverlap) {
  const Vec3 half{2e-3, 1.5e-3, 1e-3};
  const LevelSetBody a = body_of(test::box_mesh(half.x, half.y, half.z), 0.2e-3, 0.25e-3);
  const LevelSetBody b = body_of(test::box_mesh(1e-3, 0.8e-3, 0.5e-3), 0.2e-3, 0.25e-3);
  for (double delta : {1e-6, 2e-5, 1.5e-4}) {
    AllContacts found;
    points_inside(view_of(a), view_of(b), shifted({0.3e-3, -0.2e-3, half.z + 0.5e-3 - delta}),
                  found);
    ASSERT_GT(found.contacts.size(), 20u) << delta;
    for (const FeatureContact& c : found.contacts) {
      const double height = b.surface_points[std::size_t(c.feature_b - 1)].z + 0.5e-3;
      EXPECT_NEAR(c.overlap, delta - height, 1e-12 * half.x) << delta;
      EXPECT_LT(norm(c.normal - Vec3{0, 0, -1}), 1e-12) << delta;
      EXPECT_NEAR(c.point.z, half.z - 0.5 * (delta - height), 1e-12 * half.x) << delta;
    }
  }
}

// Two spheres of radius R as level sets (Fibonacci meshes of 2000 nodes, grid spacing R / 10):
// B's deepest point in A's grid gives the overlap 2R - d within the mesh's sag, the trilinear
// error h^2 / (8 (R - overlap - sqrt 3 h)) x 2 and the points' spacing l: the deepest point lies
// within l of the line of centres, where the overlap falls by at most l^2 / R. Its normal lies
// within an angle of l / R of the line. Beyond 2R plus that error, nothing.
TEST(LevelSetContact, SpheresFindTheirOverlapWithinTheStatedError) {
  const double radius = 1e-3, h = radius / 10, spacing = radius / 10;
  const test::CoreMesh mesh = sphere_mesh(radius, 2000);
  const LevelSetBody a = body_of(mesh, h, spacing), b = body_of(mesh, h, spacing);
  double sag = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 p = mesh.points[t[0]], q = mesh.points[t[1]], r = mesh.points[t[2]];
    const Vec3 n = (1.0 / norm(cross(q - p, r - p))) * cross(q - p, r - p);
    sag = std::max(sag, radius - std::fabs(dot(n, p)));
  }
  const Vec3 direction = (1.0 / std::sqrt(1.0 + 0.09 + 0.04)) * Vec3{1, 0.3, -0.2};
  for (double overlap : {0.002 * radius, 0.02 * radius, 0.1 * radius, 0.3 * radius}) {
    AllContacts found;
    points_inside(view_of(a), view_of(b), shifted((2 * radius - overlap) * direction), found);
    const double trilinear = h * h / 8 * 2 / (radius - overlap - std::sqrt(3.0) * h);
    const double bound = 2 * sag + trilinear + spacing * spacing / radius;
    if (found.contacts.empty()) { // allowed only where the overlap is within the error
      EXPECT_LT(overlap, bound);
      continue;
    }
    const FeatureContact& deepest = found.deepest();
    RecordProperty("overlap_error_" + std::to_string(overlap / radius),
                   std::to_string((deepest.overlap - overlap) / bound));
    EXPECT_NEAR(deepest.overlap, overlap, bound) << overlap;
    EXPECT_LT(norm(deepest.normal + direction), 2 * spacing / radius) << overlap;
  }
  AllContacts apart;
  points_inside(view_of(a), view_of(b),
                shifted((2 * radius + 2 * sag + h * h / radius) * direction), apart);
  EXPECT_TRUE(apart.contacts.empty());
}

// A sphere against a level-set box, its centre in the box's grid: over a face, overlap
// r - distance exactly (the box's value is exact there, at the centre and at the sphere's
// deepest point), normal the face's; a sphere far smaller than the points' spacing is found all
// the same. A sphere too large for its centre to
// lie in the grid is found through the box's points: its deepest point, a corner, gives the
// exact overlap (the corners are always points).
TEST(LevelSetContact, SpheresSmallAndLargeAgainstABox) {
  const Vec3 half{2e-3, 1.5e-3, 1e-3};
  const LevelSetBody box = body_of(test::box_mesh(half.x, half.y, half.z), 0.2e-3, 0.25e-3);
  for (double r : {0.01e-3, 0.3e-3}) {
    AllContacts found;
    const double overlap = 0.2 * r;
    sphere_level_set_contacts(view_of(box), Vec3{0.4e-3, 0.1e-3, half.z + r - overlap}, r, found);
    ASSERT_FALSE(found.contacts.empty()) << r;
    EXPECT_NEAR(found.deepest().overlap, overlap, 1e-12 * half.x) << r;
    EXPECT_LT(norm(found.deepest().normal - Vec3{0, 0, 1}), 1e-12) << r;
    for (const FeatureContact& c : found.contacts) // the box's points inside: shallower
      EXPECT_LE(c.overlap, overlap + 1e-12 * half.x) << r;
  }
  const double big = 20e-3, overlap = 0.05e-3;
  const Vec3 corner = half;
  const Vec3 out = (1.0 / norm(half)) * half;
  AllContacts found;
  sphere_level_set_contacts(view_of(box), corner + (big - overlap) * out, big, found);
  ASSERT_FALSE(found.contacts.empty());
  EXPECT_NEAR(found.deepest().overlap, overlap, 1e-12 * big);
  EXPECT_LT(norm(found.deepest().normal - out), 1e-9);
}

// Patches are the connected regions of penetration: a box's bottom face (4 x 3 mm, wider than
// the link distance of half the equivalent radius, 1 mm) pressed into a plane is one patch,
// whose contact is its deepest point; the two legs of a U prism (1 mm apart, link 0.53 mm) are
// two, whatever the order of the points.
TEST(LevelSetContact, PatchesAreTheConnectedRegionsOfPenetration) {
  const LevelSetContactSettings settings;
  const LevelSetBody box = body_of(test::box_mesh(2e-3, 1.5e-3, 1e-3), 0.2e-3, 0.2e-3);
  const double box_radius = std::cbrt(3 * box.mass.volume / (4 * pi));
  LevelSetPatches<8> flat(settings, box_radius);
  // Tilted a little about y, so that one corner is deepest.
  const Vec3 n = (1.0 / std::sqrt(1 + 1e-4)) * Vec3{0.01, 0, 1};
  points_beyond_plane(view_of(box), Vec3{0, 0, -1e-3 + 5e-6}, n, flat);
  ASSERT_EQ(flat.count, 1);
  // A corner at x = -2 mm (the box's corners are its first 8 points, keys 1 to 8); the contact
  // point lies half the overlap from it along the normal.
  EXPECT_LE(flat.contact[0].feature_a, 8);
  EXPECT_NEAR(flat.contact[0].point.x, -2e-3, flat.contact[0].overlap);
  const test::CoreMesh u = test::u_prism_mesh(1e-3, 1e-3);
  const LevelSetBody prism = body_of(u, 0.1e-3, 0.1e-3);
  double top = -1;
  for (const Vec3& p : prism.surface_points)
    top = std::max(top, p.y);
  LevelSetPatches<8> legs(settings, std::cbrt(3 * prism.mass.volume / (4 * pi)));
  points_beyond_plane(view_of(prism), Vec3{0, top - 2e-6, 0}, Vec3{0, -1, 0}, legs);
  ASSERT_EQ(legs.count, 2);
  EXPECT_GT(std::fabs(legs.contact[0].point.x - legs.contact[1].point.x), 1e-3);
}

// ---- through the engine ----------------------------------------------------------------------

ShapeConfig level_set_shape(const std::string& name, const test::CoreMesh& mesh, double spacing) {
  std::vector<std::array<double, 3>> points;
  for (const Vec3& p : mesh.points)
    points.push_back({p.x, p.y, p.z});
  return level_set_shape_config(name, points, mesh.triangles, spacing, spacing);
}

TEST(LevelSetEngine, BoxRestingOnAPlaneCarriesItsWeight) {
  const double a = 2e-3, b = 1.5e-3, c = 1e-3, density = 2500;
  SceneConfig scene = empty_scene(1e-6, {material("stone", density, 1e8, 0.3, 0.3, 0.5)});
  scene.gravity = {0, 0, -9.81};
  scene.shapes.push_back(level_set_shape("box", test::box_mesh(a, b, c), 0.25e-3));
  scene.walls.push_back(plane_wall("stone", {0, 0, 0}, {0, 0, 1}));
  Engine engine(scene);
  engine.add_particles({shaped_particle(1, {0, 0, c + 1e-5}, Quat{1, 0, 0, 0})});
  for (int k = 0; k < 30000; ++k)
    engine.step();
  const ParticleSnapshot s = engine.snapshot();
  // At rest on its bottom face, whose points all sink by the same overlap: their patches share
  // the force (book Eq. 5.17's 1 / N_p), so the total is one Hertz contact of the body's
  // equivalent radius at that overlap.
  const double volume = 8 * a * b * c;
  const double weight = density * volume * 9.81;
  const double equivalent = std::cbrt(3 * volume / (4 * pi));
  const double e_star = 1e8 / (2 * (1 - 0.3 * 0.3));
  const double overlap = std::pow(weight / (4.0 / 3.0 * e_star * std::sqrt(equivalent)), 2.0 / 3.0);
  EXPECT_NEAR(s.position[2], c - overlap, 0.01 * overlap) << "overlap " << overlap;
  EXPECT_LT(std::fabs(s.velocity[2]), 1e-6);
  EXPECT_GE(engine.diagnostics().wall_contacts, 1);
}

TEST(LevelSetEngine, ElasticCollisionsKeepTheirEnergy) {
  // Pairs at assorted orientations thrown at each other with spin: a box and a tetrahedron (two
  // level-set bodies), and a sphere against the box. Stated tolerance: 1 % of the energy (measured:
  // at most 0.2 %). Each
  // patch's force follows its deepest point, which jumps between surface points as the bodies
  // turn; the jumps are of the overlap's change over a points' spacing, and the work they do is
  // not returned.
  for (int trial = 0; trial < 6; ++trial) {
    SceneConfig scene = elastic_scene();
    scene.shapes.push_back(level_set_shape("box", test::box_mesh(2e-3, 1.5e-3, 1e-3), 0.2e-3));
    scene.shapes.push_back(level_set_shape("tetrahedron", test::tetrahedron_mesh(2.5e-3), 0.2e-3));
    Engine engine(scene);
    const double angle = 0.7 * trial + 0.3;
    const Quat qa{std::cos(angle), std::sin(angle) * 0.6, std::sin(angle) * 0.8, 0};
    const Quat qb{std::cos(2 * angle), 0, std::sin(2 * angle) * 0.6, std::sin(2 * angle) * 0.8};
    ParticleInit other =
        shaped_particle(2, {7e-3, 0.3e-3 * trial, 0}, qb, {-0.5, 0, 0}, {0, 30.0 * trial, 10});
    if (trial >= 4) {
      other = sphere({7e-3, 0.4e-3 * trial - 1e-3, 0.2e-3}, 1.5e-3, {-0.5, 0, 0});
    }
    engine.add_particles({shaped_particle(1, {0, 0, 0}, qa, {0.2, 0, 0}, {0, 0, 20}), other});
    const Collision c = collide(engine, 200000);
    ASSERT_GT(c.pair_contacts, 0) << trial;
    RecordProperty("energy_change_" + std::to_string(trial),
                   std::to_string((c.after - c.before) / c.before));
    EXPECT_NEAR(c.after, c.before, 0.01 * c.before) << trial;
  }
}

TEST(LevelSetEngine, ConcaveBodyLandsOnBothLegs) {
  // The U prism upside down (legs down) falls flat onto a plane: both legs touch at once (a patch
  // each), and it bounces straight back up (elastic) with little spin: the legs' patches are
  // mirror images, up to the points' random placement on the faces (measured 0.06 rad/s).
  const double unit = 1e-3;
  SceneConfig scene = empty_scene(2e-7, {material("glass", 2500, 1e8, 0.3, 1.0, 0.0)});
  scene.shapes.push_back(level_set_shape("u", test::u_prism_mesh(unit, unit), 0.1e-3));
  scene.walls.push_back(plane_wall("glass", {0, 0, 0}, {0, 0, 1}));
  Engine engine(scene);
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
  EXPECT_GE(most, 2);
  EXPECT_NEAR(s.velocity[2], 0.3, 0.01);
  const double spin = std::fabs(s.angular_velocity[0]) + std::fabs(s.angular_velocity[1]) +
                      std::fabs(s.angular_velocity[2]);
  RecordProperty("spin_after_bounce", std::to_string(spin));
  EXPECT_LT(spin, 0.5);
}

TEST(LevelSetEngine, OpenMeshesAreRefusedWithTheReason) {
  test::CoreMesh open = test::box_mesh(1e-3, 1e-3, 1e-3);
  open.triangles.pop_back();
  SceneConfig scene = elastic_scene();
  scene.shapes.push_back(level_set_shape("open", open, 0.2e-3));
  try {
    Engine engine(scene);
    FAIL() << "an open mesh was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("shape 'open'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("closed surface"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace kdem::testing
