// Level-set bodies (book chapter 5): the trilinear value and gradient (Eqs. 5.12 to 5.16, run on
// the device) against affine fields, where they are exact, and against a sphere's distance,
// where their error is second order in the spacing; the signed-distance grids of meshes against
// closed forms; mass properties against closed forms; the surface points' spacing, place and
// coverage; and the builder's refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "dilated_test_support.hpp"
#include "geometry_test_support.hpp"
#include "shapes/level_set_build.hpp"
#include "src/core_builders.hpp"
#include "src/host_copy.hpp"

namespace kdem::testing {
namespace {

struct Interpolated {
  int inside = 0;
  LevelSetSample sample;
};

struct InterpolateOnGrid {
  LevelSetGrid grid;
  DeviceView<double*> values;
  KOKKOS_INLINE_FUNCTION Interpolated operator()(Vec3 p) const {
    Interpolated r;
    r.inside = interpolate_level_set(grid, values.data(), p, r.sample) ? 1 : 0;
    return r;
  }
};

std::vector<Interpolated> interpolate_on_device(const LevelSetGrid& grid,
                                                const std::vector<double>& values,
                                                const std::vector<Vec3>& points) {
  return run_on_device<Interpolated>(points,
                                     InterpolateOnGrid{grid, upload<double>("values", values)});
}

template <class Field> std::vector<double> sampled(const LevelSetGrid& grid, Field field) {
  std::vector<double> values(std::size_t(grid.nodes()));
  for (int k = 0; k < grid.nz; ++k)
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        values[std::size_t(grid.index(i, j, k))] = field(grid.node(i, j, k));
  return values;
}

// Uniform points in the grid's box, with its corners and the midpoints of its far faces (the
// last cell along each axis holds its far face).
std::vector<Vec3> points_in(const LevelSetGrid& grid, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Vec3 size = grid.far_corner() - grid.origin;
  std::vector<Vec3> points;
  for (int c = 0; c < 8; ++c)
    points.push_back(grid.origin +
                     Vec3{(c & 1) * size.x, ((c >> 1) & 1) * size.y, ((c >> 2) & 1) * size.z});
  points.push_back(grid.origin + Vec3{size.x, 0.5 * size.y, 0.5 * size.z});
  points.push_back(grid.origin + Vec3{0.5 * size.x, size.y, 0.5 * size.z});
  points.push_back(grid.origin + Vec3{0.5 * size.x, 0.5 * size.y, size.z});
  while (int(points.size()) < count)
    points.push_back(grid.origin +
                     Vec3{unit(random) * size.x, unit(random) * size.y, unit(random) * size.z});
  return points;
}

LevelSetGrid test_grid(double spacing, int nx, int ny, int nz) {
  LevelSetGrid grid;
  grid.origin = Vec3{-0.3, 0.11, -0.52};
  grid.spacing = spacing;
  grid.nx = nx, grid.ny = ny, grid.nz = nz;
  return grid;
}

// A trilinear form reproduces an affine field exactly; only rounding remains (relative 1e-13
// of the field's size over the box).
TEST(LevelSetInterpolation, ExactForAffineFields) {
  const LevelSetGrid grid = test_grid(0.07, 5, 4, 7);
  const Vec3 slope{0.3, -1.7, 0.9};
  const double offset = 0.21;
  const auto field = [&](Vec3 p) { return offset + dot(slope, p); };
  const std::vector<Vec3> points = points_in(grid, 2000, 3);
  const auto results = interpolate_on_device(grid, sampled(grid, field), points);
  for (std::size_t c = 0; c < points.size(); ++c) {
    ASSERT_EQ(results[c].inside, 1) << "point " << c;
    EXPECT_NEAR(results[c].sample.value, field(points[c]), 1e-13) << "point " << c;
    EXPECT_LT(norm(results[c].sample.gradient - slope), 1e-12) << "point " << c;
  }
}

// Points beyond the box by a hair, on any side, and NaN are outside; nothing is read for them.
TEST(LevelSetInterpolation, PointsOutsideTheBoxAreOutside) {
  const LevelSetGrid grid = test_grid(0.05, 4, 6, 5);
  const Vec3 size = grid.far_corner() - grid.origin;
  const Vec3 mid = grid.origin + 0.5 * size;
  const double hair = 1e-9;
  std::vector<Vec3> points = {
      Vec3{grid.origin.x - hair, mid.y, mid.z}, Vec3{grid.far_corner().x + hair, mid.y, mid.z},
      Vec3{mid.x, grid.origin.y - hair, mid.z}, Vec3{mid.x, grid.far_corner().y + hair, mid.z},
      Vec3{mid.x, mid.y, grid.origin.z - hair}, Vec3{mid.x, mid.y, grid.far_corner().z + hair},
      Vec3{std::nan(""), mid.y, mid.z},         Vec3{mid.x, mid.y, 1e300}};
  const auto results =
      interpolate_on_device(grid, std::vector<double>(std::size_t(grid.nodes()), 1.0), points);
  for (std::size_t c = 0; c < points.size(); ++c)
    EXPECT_EQ(results[c].inside, 0) << "point " << c;
}

// The distance to a sphere of radius R sampled at spacing h: trilinear interpolation errs by at
// most h^2 / 8 times the sum of |second derivatives| over the cell, which for |x| - R is at most
// 2 / r at distance r from the centre; the points lie at r >= R / 2 and their cells at r >= R / 2 -
// sqrt(3) h. Halving h must divide the largest error by about 4 (second order).
TEST(LevelSetInterpolation, SecondOrderOnASphereDistance) {
  const double radius = 1.0;
  double previous = 0;
  for (double h : {0.1, 0.05, 0.025}) {
    const int n = int(std::ceil(4.0 * radius / h)) + 1;
    LevelSetGrid grid;
    grid.spacing = h;
    grid.nx = grid.ny = grid.nz = n;
    grid.origin = Vec3{-2.0 * radius, -2.0 * radius, -2.0 * radius};
    const auto field = [&](Vec3 p) { return norm(p) - radius; };
    std::vector<Vec3> points;
    std::mt19937 random(11);
    std::uniform_real_distribution<double> uniform(-1.5 * radius, 1.5 * radius);
    while (points.size() < 3000) {
      const Vec3 p{uniform(random), uniform(random), uniform(random)};
      if (norm(p) >= 0.5 * radius && norm(p) <= 1.5 * radius)
        points.push_back(p);
    }
    const auto results = interpolate_on_device(grid, sampled(grid, field), points);
    double worst = 0;
    for (std::size_t c = 0; c < points.size(); ++c) {
      ASSERT_EQ(results[c].inside, 1);
      worst = std::max(worst, std::fabs(results[c].sample.value - field(points[c])));
    }
    const double bound = h * h / 8.0 * 2.0 / (0.5 * radius - std::sqrt(3.0) * h);
    EXPECT_LE(worst, bound) << "h " << h;
    if (previous > 0) {
      EXPECT_NEAR(previous / worst, 4.0, 1.0) << "h " << h;
    }
    previous = worst;
  }
}

LevelSetBody body_of(const test::CoreMesh& mesh, double spacing, double point_spacing,
                     int padding = 2) {
  LevelSetOptions options;
  options.spacing = spacing;
  options.point_spacing = point_spacing;
  options.padding = padding;
  return build_level_set(mesh.points, mesh.triangles, options);
}

double box_distance(Vec3 p, Vec3 half) {
  const Vec3 q{std::fabs(p.x) - half.x, std::fabs(p.y) - half.y, std::fabs(p.z) - half.z};
  const Vec3 out{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
  return norm(out) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
}

// The grid of a box holds the box's exact signed distance at every node (the closest-feature
// distance is exact for a polyhedron; rounding of 1e-15 m on a 1 m box). The padding leaves at
// least `padding` cells outside on every side, so every boundary node is outside by that much.
TEST(LevelSetBuild, BoxGridHoldsItsExactSignedDistance) {
  const Vec3 half{0.5, 0.3, 0.2};
  const LevelSetBody body = body_of(test::box_mesh(half.x, half.y, half.z), 0.045, 0.05, 3);
  const LevelSetGrid& g = body.grid;
  ASSERT_EQ(std::size_t(g.nodes()), body.values.size());
  double inside = 0;
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const double value = body.values[std::size_t(g.index(i, j, k))];
        ASSERT_NEAR(value, box_distance(g.node(i, j, k), half), 1e-14)
            << "node " << i << " " << j << " " << k;
        inside += value < 0 ? 1 : 0;
        if (i == 0 || j == 0 || k == 0 || i == g.nx - 1 || j == g.ny - 1 || k == g.nz - 1) {
          EXPECT_GE(value, 3 * g.spacing * (1 - 1e-12));
        }
      }
  EXPECT_GT(inside, 0);
  EXPECT_EQ(g.nx, int(std::ceil(1.0 / 0.045)) + 7);
}

// A Fibonacci sphere mesh (vertices on the sphere of radius R) lies between the sphere and the
// planes of its faces, so its signed distance differs from |x| - R by at most the largest sag
// R - (distance of a face's plane from the centre), measured here from the mesh.
TEST(LevelSetBuild, SphereMeshGridWithinItsSag) {
  const double radius = 0.01;
  const TriangleMesh sphere = fibonacci_sphere(800);
  test::CoreMesh mesh;
  for (const auto& p : sphere.points)
    mesh.points.push_back(radius * Vec3{p[0], p[1], p[2]});
  mesh.triangles = sphere.triangles;
  double sag = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.points[t[0]], b = mesh.points[t[1]], c = mesh.points[t[2]];
    const Vec3 n = (1.0 / norm(cross(b - a, c - a))) * cross(b - a, c - a);
    sag = std::max(sag, radius - std::fabs(dot(n, a)));
  }
  const LevelSetBody body = body_of(mesh, radius / 10, radius / 8);
  const LevelSetGrid& g = body.grid;
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const double value = body.values[std::size_t(g.index(i, j, k))];
        ASSERT_LE(std::fabs(value - (norm(g.node(i, j, k)) - radius)), sag * (1 + 1e-9));
      }
  EXPECT_LT(sag, 0.01 * radius); // the mesh is fine enough that the check means something
  // Interpolated on the device at random points near the surface (within the grid, which holds
  // the mesh's box and 2 cells more): the sag plus the trilinear
  // error bound of the test above, with the cells at r >= R / 2 - sqrt(3) h.
  std::vector<Vec3> points;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(-1.15 * radius, 1.15 * radius);
  while (points.size() < 2000) {
    const Vec3 p{uniform(random), uniform(random), uniform(random)};
    if (norm(p) >= 0.7 * radius && norm(p) <= 1.15 * radius)
      points.push_back(p);
  }
  const auto results = interpolate_on_device(g, body.values, points);
  const double h = g.spacing;
  const double bound = sag + h * h / 8.0 * 2.0 / (0.7 * radius - std::sqrt(3.0) * h);
  for (std::size_t c = 0; c < points.size(); ++c) {
    ASSERT_EQ(results[c].inside, 1);
    EXPECT_LE(std::fabs(results[c].sample.value - (norm(points[c]) - radius)), bound);
  }
}

// Mass properties of the mesh's interior are exact (to rounding, 1e-12 relative): a box, and a
// regular tetrahedron of edge a (volume a^3 / (6 sqrt 2), inertia per density V a^2 / 20 about
// any axis through the centroid).
TEST(LevelSetBuild, MassPropertiesOfTheInteriorAreExact) {
  const Vec3 half{0.5, 0.3, 0.2};
  const LevelSetBody box = body_of(test::box_mesh(half.x, half.y, half.z), 0.1, 0.1);
  const double volume = 8 * half.x * half.y * half.z;
  EXPECT_NEAR(box.mass.volume, volume, 1e-15);
  EXPECT_LT(norm(box.mass.centroid), 1e-15);
  EXPECT_NEAR(box.mass.inertia_per_density.m[0][0],
              volume * (4 * half.y * half.y + 4 * half.z * half.z) / 12, 1e-15);
  EXPECT_NEAR(box.mass.inertia_per_density.m[2][2],
              volume * (4 * half.x * half.x + 4 * half.y * half.y) / 12, 1e-15);
  EXPECT_NEAR(box.mass.inertia_per_density.m[0][1], 0, 1e-15);
  EXPECT_NEAR(box.bounding_radius, norm(half) + std::sqrt(3.0) * 0.1, 1e-15);

  const double r = 0.02;
  const LevelSetBody tet = body_of(test::tetrahedron_mesh(r), r / 10, r / 5);
  const double edge = r * std::sqrt(8.0 / 3.0);
  const double tet_volume = edge * edge * edge / (6 * std::sqrt(2.0));
  EXPECT_NEAR(tet.mass.volume, tet_volume, 1e-12 * tet_volume);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(tet.mass.principal_inertia_per_density[a], tet_volume * edge * edge / 20,
                1e-12 * tet_volume * edge * edge);
}

// Surface points: on the surface (distance 0 to rounding), no two closer than the spacing
// (checked pair by pair), every corner kept (offered first, as the sharpest), and no gap: every one
// of 20000 uniform points on the surface lies within 1.5 spacings of a kept point. (A maximal
// Poisson set leaves none beyond one spacing; the finite candidate count leaves a little more.)
TEST(LevelSetBuild, SurfacePointsAreSpacedAndCoverTheSurface) {
  const Vec3 half{0.5, 0.3, 0.2};
  const test::CoreMesh mesh = test::box_mesh(half.x, half.y, half.z);
  const double spacing = 0.06;
  const LevelSetBody body = body_of(mesh, 0.05, spacing);
  const std::vector<Vec3>& points = body.surface_points;
  ASSERT_GT(points.size(), 100u);
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner{c & 1 ? half.x : -half.x, c & 2 ? half.y : -half.y, c & 4 ? half.z : -half.z};
    const bool kept = std::any_of(points.begin(), points.end(),
                                  [&](const Vec3& p) { return norm(p - corner) <= 1e-15; });
    EXPECT_TRUE(kept) << "corner " << c;
  }
  for (std::size_t a = 0; a < points.size(); ++a) {
    EXPECT_NEAR(box_distance(points[a], half), 0, 1e-15) << "point " << a;
    for (std::size_t b = a + 1; b < points.size(); ++b)
      ASSERT_GE(norm(points[a] - points[b]), spacing) << a << " " << b;
  }
  std::mt19937 random(9);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> face(0, 5);
  double widest = 0;
  for (int s = 0; s < 20000; ++s) {
    const int f = face(random);
    Vec3 probe{unit(random) * half.x, unit(random) * half.y, unit(random) * half.z};
    const double side = f % 2 ? 1.0 : -1.0;
    probe = f / 2 == 0 ? Vec3{side * half.x, probe.y, probe.z}
                       : (f / 2 == 1 ? Vec3{probe.x, side * half.y, probe.z}
                                     : Vec3{probe.x, probe.y, side * half.z});
    double nearest = 1e300;
    for (const Vec3& p : points)
      nearest = std::min(nearest, norm(p - probe));
    widest = std::max(widest, nearest);
  }
  EXPECT_LE(widest, 1.5 * spacing);
}

// Wrong options and meshes are refused with what is wrong.
TEST(LevelSetBuild, RefusesBadInput) {
  const test::CoreMesh box = test::box_mesh(0.5, 0.3, 0.2);
  const auto refusal = [&](const test::CoreMesh& mesh, LevelSetOptions options) -> std::string {
    try {
      build_level_set(mesh.points, mesh.triangles, options);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  LevelSetOptions good;
  good.spacing = 0.05;
  good.point_spacing = 0.05;
  LevelSetOptions o = good;
  o.spacing = 0;
  EXPECT_NE(refusal(box, o).find("grid spacing must be positive"), std::string::npos);
  o = good;
  o.point_spacing = -1;
  EXPECT_NE(refusal(box, o).find("surface-point spacing must be positive"), std::string::npos);
  o = good;
  o.padding = 0;
  EXPECT_NE(refusal(box, o).find("padding must be at least 1"), std::string::npos);
  o = good;
  o.spacing = 1e-4;
  EXPECT_NE(refusal(box, o).find("allowed"), std::string::npos);
  test::CoreMesh open = box;
  open.triangles.pop_back();
  EXPECT_NE(refusal(open, good).find("closed surface"), std::string::npos) << refusal(open, good);
}

} // namespace
} // namespace kdem::testing
