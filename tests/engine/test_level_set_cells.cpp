// The cells a level-set body's surface points are sorted into, and the tests that skip points by
// them: a box query visits every point in the box (against a brute-force scan), the culled
// points-in-grid test (the cells under the other body's box) and the points beyond a plane (the
// cells that reach below it) find exactly what testing every point finds, two bodies whose boxes
// are apart have no point inside
// the other, and a chosen point count is met within 1 %.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "dilated_test_support.hpp"
#include "geometry_test_support.hpp"
#include "shapes/level_set_build.hpp"
#include "shapes/oriented_box.hpp"
#include "src/core_builders.hpp"

namespace kdem::testing {
namespace {

LevelSetOptions options_of(double spacing, double point_spacing) {
  LevelSetOptions options;
  options.spacing = spacing;
  options.point_spacing = point_spacing;
  return options;
}

test::CoreMesh sphere_mesh(double radius, int nodes) {
  const TriangleMesh sphere = fibonacci_sphere(nodes);
  test::CoreMesh mesh;
  for (const auto& p : sphere.points)
    mesh.points.push_back(radius * Vec3{p[0], p[1], p[2]});
  mesh.triangles = sphere.triangles;
  return mesh;
}

// A rod (long box) and a ball: a rod's box is much tighter than its bounding sphere.
LevelSetBody rod() {
  const test::CoreMesh mesh = test::box_mesh(0.5, 0.08, 0.06);
  return build_level_set(mesh.points, mesh.triangles, options_of(0.02, 0.02));
}
LevelSetBody ball() {
  const test::CoreMesh mesh = sphere_mesh(0.2, 600);
  return build_level_set(mesh.points, mesh.triangles, options_of(0.02, 0.03));
}

bool in_box(Vec3 x, Vec3 lo, Vec3 hi) {
  return x.x >= lo.x && x.y >= lo.y && x.z >= lo.z && x.x <= hi.x && x.y <= hi.y && x.z <= hi.z;
}

RelativePose random_pose(std::mt19937_64& rng, double reach) {
  const Vec3 offset{uniform(rng, -reach, reach), uniform(rng, -reach, reach),
                    uniform(rng, -reach, reach)};
  return RelativePose{rotation_matrix(random_rotation(rng)), offset};
}

struct Found {
  int point;
  double overlap;
  Vec3 normal;
};
struct Collected {
  std::vector<Found> found;
  void add(const FeatureContact& c) { found.push_back({c.feature_b - 1, c.overlap, c.normal}); }
};

// Every point of b tested, as points_inside would without its cells.
std::vector<Found> every_point_inside(const LevelSetBodyView& a, const LevelSetBodyView& b,
                                      const RelativePose& pose) {
  std::vector<Found> found;
  for (int q = 0; q < b.point_count; ++q) {
    const Vec3 x = pose.point(b.points[q]);
    LevelSetSample s;
    if (a.sample(x, s) && s.value < 0)
      found.push_back({q, -s.value, -1.0 * level_set::outward(s, x)});
  }
  return found;
}

// The points are sorted by cell: each lies in the cell whose run holds it, the runs cover every
// point once, and the body's box holds every point and the mesh.
TEST(LevelSetCells, PointsAreSortedIntoTheirCells) {
  for (const LevelSetBody& body : {rod(), ball()}) {
    const LevelSetPointCells& c = body.cells;
    ASSERT_EQ(body.cell_first.size(), std::size_t(c.count()) + 1);
    EXPECT_EQ(body.cell_first.front(), 0);
    EXPECT_EQ(body.cell_first.back(), int(body.surface_points.size()));
    EXPECT_GT(c.count(), 8);
    for (int cell = 0; cell < c.count(); ++cell) {
      ASSERT_LE(body.cell_first[std::size_t(cell)], body.cell_first[std::size_t(cell) + 1]);
      for (int q = body.cell_first[std::size_t(cell)]; q < body.cell_first[std::size_t(cell) + 1];
           ++q) {
        const Vec3 x = body.surface_points[std::size_t(q)];
        ASSERT_EQ(c.cell_of(x), cell) << "point " << q;
        ASSERT_TRUE(in_box(x, c.lo, c.hi)) << "point " << q;
      }
    }
  }
  // The rod's box is its mesh's box, exactly.
  const LevelSetBody r = rod();
  EXPECT_EQ(r.cells.hi.x, 0.5);
  EXPECT_EQ(r.cells.lo.y, -0.08);
  EXPECT_EQ(r.cells.hi.z, 0.06);
}

// 2000 random boxes, from a point's size to wider than the body, some beyond it: each query
// visits every point in its box (brute-force scan), none twice, and on average far fewer than
// all of them for the small boxes.
TEST(LevelSetCells, BoxQueriesVisitEveryPointInTheBox) {
  std::mt19937_64 rng(17);
  for (const LevelSetBody& body : {rod(), ball()}) {
    const LevelSetBodyView view = view_of(body);
    long long visited_small = 0, inside_small = 0, small_queries = 0;
    for (int trial = 0; trial < 2000; ++trial) {
      const Vec3 centre{uniform(rng, -0.7, 0.7), uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3)};
      const double half = log_uniform(rng, 1e-3, 0.8);
      const Vec3 lo = centre - Vec3{half, half, half}, hi = centre + Vec3{half, half, half};
      std::vector<int> visited;
      view.for_points_in_box(lo, hi, [&](int q) { visited.push_back(q); });
      const std::set<int> unique(visited.begin(), visited.end());
      ASSERT_EQ(unique.size(), visited.size()) << "trial " << trial;
      int inside = 0;
      for (int q = 0; q < view.point_count; ++q)
        if (in_box(view.points[q], lo, hi)) {
          ++inside;
          ASSERT_EQ(unique.count(q), 1u) << "trial " << trial << ", point " << q;
        }
      if (half < 0.05) {
        ++small_queries;
        visited_small += long(visited.size());
        inside_small += inside;
      }
    }
    ASSERT_GT(small_queries, 100);
    EXPECT_LT(double(visited_small) / small_queries, 0.1 * view.point_count)
        << "points visited per small query, of " << view.point_count;
    EXPECT_GE(visited_small, inside_small);
  }
}

void expect_same(const std::vector<Found>& found, const std::vector<Found>& every, int trial) {
  ASSERT_EQ(found.size(), every.size()) << "trial " << trial;
  for (std::size_t k = 0; k < every.size(); ++k) {
    ASSERT_EQ(found[k].point, every[k].point) << "trial " << trial;
    ASSERT_EQ(found[k].overlap, every[k].overlap) << "trial " << trial;
    ASSERT_EQ(found[k].normal.x, every[k].normal.x) << "trial " << trial;
    ASSERT_EQ(found[k].normal.z, every[k].normal.z) << "trial " << trial;
  }
}

// The points of a body beyond a plane (wall contacts), through the cells that reach below it,
// against testing every point: 3000 planes of random normals (a third along an axis, where a row
// of cells lies level) through points in and around the rod and the ball: the same points in the
// same order, with the same overlaps bit for bit; at least 500 planes cut the body and miss more
// than half its points, and there far fewer points are visited than the body has.
TEST(LevelSetCells, PlaneQueryFindsWhatEveryPointFinds) {
  std::mt19937_64 rng(29);
  struct Beyond {
    std::vector<Found> found;
    void add(const FeatureContact& c) { found.push_back({c.feature_a - 1, c.overlap, c.normal}); }
  };
  for (const LevelSetBody& body : {rod(), ball()}) {
    const LevelSetBodyView view = view_of(body);
    int cutting = 0;
    long long visited_cutting = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      Vec3 n = random_unit(rng);
      if (trial % 3 == 0) {
        const int axis = trial / 3 % 3;
        n = Vec3{axis == 0 ? 1.0 : 0.0, axis == 1 ? 1.0 : 0.0, axis == 2 ? 1.0 : 0.0};
        n = (trial / 9 % 2 == 0 ? 1.0 : -1.0) * n;
      }
      const Vec3 origin{uniform(rng, -0.6, 0.6), uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3)};
      std::vector<Found> every;
      for (int q = 0; q < view.point_count; ++q) {
        const double height = dot(view.points[q] - origin, n);
        if (height < 0)
          every.push_back({q, -height, n});
      }
      Beyond culled;
      points_beyond_plane(view, origin, n, culled);
      expect_same(culled.found, every, trial);
      int visited = 0;
      view.for_points_below_plane(origin, n, [&](int) { ++visited; });
      if (!every.empty() && 2 * every.size() < std::size_t(view.point_count)) {
        ++cutting;
        visited_cutting += visited;
      }
    }
    EXPECT_GE(cutting, 500);
    EXPECT_LT(double(visited_cutting) / cutting, 0.6 * view.point_count)
        << "points visited per cutting plane, of " << view.point_count;
  }
}

// Random poses of the rod and the ball against a rod and against a ball, overlapping or not: the
// points inside the other's grid, through the cells under its box, are exactly those that
// testing every point finds, in the same order, with the same overlaps and normals bit for bit.
// At least 100 of the 2000 poses touch.
TEST(LevelSetCells, CulledPointsInsideFindWhatEveryPointFinds) {
  std::mt19937_64 rng(23);
  const LevelSetBody r = rod(), b = ball();
  const LevelSetBodyView rod_view = view_of(r), ball_view = view_of(b);
  int touching = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const LevelSetBodyView& a = trial % 2 == 0 ? rod_view : ball_view;
    const LevelSetBodyView& points_of = trial % 4 < 2 ? rod_view : ball_view;
    const RelativePose pose = random_pose(rng, 0.6);
    const std::vector<Found> every = every_point_inside(a, points_of, pose);
    touching += every.empty() ? 0 : 1;
    Collected under_box;
    points_inside(a, points_of, pose, under_box);
    expect_same(under_box.found, every, trial);
  }
  EXPECT_GE(touching, 100);
}

// Two rods posed at random within each other's bounding spheres: wherever their boxes are apart
// (separating-axis test), no point of either is inside the other's grid; the boxes part many
// pairs whose bounding spheres overlap (at least a fifth here), which is what the box test buys.
TEST(LevelSetCells, BodiesWhoseBoxesAreApartHaveNoPointInside) {
  std::mt19937_64 rng(29);
  const LevelSetBody r = rod();
  const LevelSetBodyView view = view_of(r);
  const auto box_of = [&](const Mat3& rotation, Vec3 origin) {
    return OrientedBox{origin + rotation * r.cells.centre(), rotation, r.cells.half_extent()};
  };
  int apart = 0, spheres_overlap = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const RelativePose pose = random_pose(rng, 0.6);
    if (!(norm(pose.translation) < 2 * view.reach))
      continue;
    ++spheres_overlap;
    int axis = -1;
    if (oriented_boxes_overlap(box_of(identity3(), Vec3{}), box_of(pose.rotation, pose.translation),
                               axis))
      continue;
    ++apart;
    const RelativePose inverse{transpose(pose.rotation),
                               -1.0 * transpose_times(pose.rotation, pose.translation)};
    ASSERT_TRUE(every_point_inside(view, view, pose).empty()) << "trial " << trial;
    ASSERT_TRUE(every_point_inside(view, view, inverse).empty()) << "trial " << trial;
  }
  EXPECT_GE(5 * apart, spheres_overlap) << apart << " of " << spheres_overlap;
}

// A point count instead of a spacing: the count is met within 1 % on a box and a sphere, from a
// few hundred to a few thousand points, and the points keep the spacing chosen for it.
TEST(LevelSetCells, PointCountIsMetWithinOnePercent) {
  const test::CoreMesh box = test::box_mesh(0.5, 0.3, 0.2);
  const test::CoreMesh sphere = sphere_mesh(0.4, 800);
  for (const test::CoreMesh* mesh : {&box, &sphere})
    for (int count : {300, 1000, 4000}) {
      LevelSetOptions options = options_of(0.05, 0);
      options.point_count = count;
      const LevelSetBody body = build_level_set(mesh->points, mesh->triangles, options);
      const int made = int(body.surface_points.size());
      EXPECT_LE(std::abs(made - count), count / 100) << "asked " << count << ", made " << made;
      double closest = 1e300;
      for (std::size_t a = 0; a < body.surface_points.size(); a += 7)
        for (std::size_t b = 0; b < body.surface_points.size(); ++b)
          if (a != b)
            closest = std::min(closest, norm(body.surface_points[a] - body.surface_points[b]));
      EXPECT_GE(closest, body.point_spacing);
      EXPECT_LT(closest, 2 * body.point_spacing);
    }
}

} // namespace
} // namespace kdem::testing
