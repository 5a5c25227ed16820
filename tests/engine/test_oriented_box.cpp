// Oriented boxes, the families' bounding-box trait and the pair broad phase's separating-axis
// test: closed forms of touching boxes, a box turned about one axis, a body box off its body's
// centre, and the test's sufficiency (a pair it reports apart has no common sampled point); the
// gap it reports against closed forms and the exact distance between the boxes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "shapes/oriented_box.hpp"
#include "shapes/superquadric_properties.hpp"

namespace kdem {
namespace {

OrientedBox axis_box(Vec3 centre, Vec3 half_extent) {
  return OrientedBox{centre, identity3(), half_extent};
}

Mat3 turned_about_z(double angle) {
  return rotation_matrix(Quat{std::cos(angle / 2), 0, 0, std::sin(angle / 2)});
}

bool overlap(const OrientedBox& i, const OrientedBox& j) {
  int axis = -1;
  return oriented_boxes_overlap(i, j, axis);
}

// Gaps of 1e-9 of the box size: far above the test's margin of 1e-12, far below any scale.
constexpr double gap = 1e-9;

TEST(OrientedBox, FaceToFaceBoxesTouchAtTheSumOfTheirHalfExtents) {
  const OrientedBox i = axis_box({0, 0, 0}, {1, 2, 3});
  for (int k = 0; k < 3; ++k) {
    Vec3 along{};
    (k == 0 ? along.x : k == 1 ? along.y : along.z) = 1;
    const double reach = k == 0 ? 1 + 0.5 : k == 1 ? 2 + 1.5 : 3 + 0.25;
    const Vec3 half{0.5, 1.5, 0.25};
    EXPECT_TRUE(overlap(i, axis_box((reach - gap) * along, half))) << "axis " << k;
    EXPECT_FALSE(overlap(i, axis_box((reach + gap) * along, half))) << "axis " << k;
    EXPECT_FALSE(overlap(axis_box(-(reach + gap) * along, half), i)) << "axis " << k;
  }
}

TEST(OrientedBox, AnEdgeTurnedTowardsAFaceReachesHalfTheDiagonal) {
  // A unit cube turned by 45 degrees about z points its edge along x: reach h sqrt(2).
  const double h = 1, reach = h + h * std::sqrt(2.0);
  const OrientedBox fixed = axis_box({0, 0, 0}, {h, h, h});
  const OrientedBox near{{reach - gap, 0, 0}, turned_about_z(M_PI / 4), {h, h, h}};
  const OrientedBox far{{reach + gap, 0, 0}, turned_about_z(M_PI / 4), {h, h, h}};
  EXPECT_TRUE(overlap(fixed, near));
  EXPECT_FALSE(overlap(fixed, far));
  int axis = -1;
  oriented_boxes_overlap(fixed, far, axis);
  EXPECT_EQ(axis, 0) << "the face normal of the fixed box separates them";
}

TEST(OrientedBox, TheLastSeparatingAxisIsKeptWhileItStillSeparates) {
  const OrientedBox i = axis_box({0, 0, 0}, {1, 1, 1});
  const OrientedBox j{{0, 3, 0}, turned_about_z(0.3), {1, 1, 1}};
  int axis = -1;
  ASSERT_FALSE(oriented_boxes_overlap(i, j, axis));
  const int first = axis;
  ASSERT_GE(first, 0);
  EXPECT_FALSE(oriented_boxes_overlap(i, j, axis));
  EXPECT_EQ(axis, first);
  const OrientedBox touching{{0, 1.5, 0}, turned_about_z(0.3), {1, 1, 1}};
  EXPECT_TRUE(oriented_boxes_overlap(i, touching, axis));
  EXPECT_EQ(axis, -1);
}

// A posed body whose body box lies off its centre (as a poly-superquadric's does): the members
// of the surface concept that oriented_box_of does not read are never called.
struct OffCentreBody {
  Vec3 centre;
  Mat3 rotation;
  BodyBox box;
  KOKKOS_INLINE_FUNCTION Vec3 to_local(Vec3 x) const { return transpose(rotation) * (x - centre); }
  KOKKOS_INLINE_FUNCTION Vec3 to_world(Vec3 local) const { return centre + rotation * local; }
  template <bool H> KOKKOS_INLINE_FUNCTION ShapeFunction local(Vec3) const { return {}; }
  template <bool H> KOKKOS_INLINE_FUNCTION ShapeFunction evaluate(Vec3) const { return {}; }
  KOKKOS_INLINE_FUNCTION double smallest_length() const { return 0; }
  KOKKOS_INLINE_FUNCTION double reach() const { return 0; }
  KOKKOS_INLINE_FUNCTION double equivalent_radius() const { return 0; }
  KOKKOS_INLINE_FUNCTION Vec3 support_local(Vec3) const { return {}; }
  KOKKOS_INLINE_FUNCTION BodyBox local_box() const { return box; }
};

TEST(OrientedBox, ABodyBoxOffItsCentreIsPlacedByThePose) {
  const OffCentreBody body{{1, 2, 3}, turned_about_z(M_PI / 2), BodyBox{{0, -1, -1}, {2, 1, 1}}};
  const OrientedBox box = oriented_box_of(body);
  // Body x is world y after a quarter turn about z: the box centre (1, 0, 0) lands at (1, 3, 3).
  EXPECT_NEAR(box.centre.x, 1, 1e-15);
  EXPECT_NEAR(box.centre.y, 3, 1e-15);
  EXPECT_NEAR(box.centre.z, 3, 1e-15);
  EXPECT_EQ(box.half_extent.x, 1);
  EXPECT_EQ(box.half_extent.y, 1);
  EXPECT_EQ(box.half_extent.z, 1);
}

TEST(OrientedBox, ASuperquadricsBoxIsItsHalfAxesAboutItsCentre) {
  const SuperquadricShape shape = make_superquadric(1e-3, 2e-3, 3e-3, 4, 2);
  const PosedSuperquadric posed =
      pose_superquadric(shape, Vec3{0.1, 0.2, 0.3}, Quat{std::cos(0.2), std::sin(0.2), 0, 0});
  // The superquadric's own overload and the generic one from its body box agree bit for bit.
  for (const OrientedBox& box :
       {oriented_box_of(posed), oriented_box_of<PosedSuperquadric>(posed)}) {
    EXPECT_EQ(box.centre.x, 0.1);
    EXPECT_EQ(box.centre.y, 0.2);
    EXPECT_EQ(box.centre.z, 0.3);
    EXPECT_EQ(box.half_extent.x, 1e-3);
    EXPECT_EQ(box.half_extent.y, 2e-3);
    EXPECT_EQ(box.half_extent.z, 3e-3);
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        EXPECT_EQ(box.rotation.m[k][l], posed.rotation.m[k][l]);
  }
}

Vec3 box_point(const OrientedBox& b, Vec3 unit_cube_point) {
  const Vec3 local{b.half_extent.x * unit_cube_point.x, b.half_extent.y * unit_cube_point.y,
                   b.half_extent.z * unit_cube_point.z};
  return b.centre + b.rotation * local;
}

Vec3 box_local(const OrientedBox& b, Vec3 x) {
  return transpose_times(b.rotation, x - b.centre);
}

bool inside(const OrientedBox& b, Vec3 x) {
  const Vec3 local = box_local(b, x);
  return std::fabs(local.x) <= b.half_extent.x && std::fabs(local.y) <= b.half_extent.y &&
         std::fabs(local.z) <= b.half_extent.z;
}

TEST(OrientedBox, PairsReportedApartShareNoSampledPointAndBoxesHoldingACommonPointOverlap) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1, 1), size(0.2, 1.5);
  int apart = 0, sampled_overlaps = 0;
  for (int trial = 0; trial < 400; ++trial) {
    auto random_box = [&] {
      Quat q{unit(random), unit(random), unit(random), unit(random)};
      const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      q = Quat{q.w / n, q.x / n, q.y / n, q.z / n};
      return OrientedBox{Vec3{2 * unit(random), 2 * unit(random), 2 * unit(random)},
                         rotation_matrix(q), Vec3{size(random), size(random), size(random)}};
    };
    const OrientedBox i = random_box(), j = random_box();
    const bool reported = overlap(i, j);
    bool common = false;
    for (int s = 0; s < 2000 && !common; ++s)
      common = inside(j, box_point(i, {unit(random), unit(random), unit(random)}));
    if (common) {
      ++sampled_overlaps;
      EXPECT_TRUE(reported) << "trial " << trial << ": a point of both boxes, reported apart";
    }
    apart += reported ? 0 : 1;
  }
  // Both outcomes occur often enough for the check to mean something.
  EXPECT_GT(apart, 40);
  EXPECT_GT(sampled_overlaps, 40);
}

double gap_of(const OrientedBox& i, const OrientedBox& j, int& axis) {
  axis = -1;
  return oriented_boxes_gap(i, j, axis);
}

// The margin of the test is 1e-12 of the pair's size (|offset| plus the half-extents, at most 13
// here): the gap is the true one less at most 1.3e-11.
TEST(OrientedBoxGap, FaceToFaceBoxesAreApartByTheirGap) {
  const OrientedBox i = axis_box({0, 0, 0}, {1, 2, 3});
  const Vec3 half{0.5, 1.5, 0.25};
  for (double g : {1e-9, 1e-4, 0.3}) {
    int axis = -1;
    EXPECT_NEAR(gap_of(i, axis_box({1.5 + g, 0.2, -0.1}, half), axis), g, 2e-11) << g;
    EXPECT_EQ(axis, 0);
    EXPECT_NEAR(gap_of(i, axis_box({0.1, -(3.5 + g), 0}, half), axis), g, 2e-11) << g;
    EXPECT_EQ(axis, 1);
  }
  int axis = -1;
  EXPECT_EQ(gap_of(i, axis_box({1.5 - 1e-9, 0, 0}, half), axis), 0);
  EXPECT_EQ(axis, -1);
}

TEST(OrientedBoxGap, AnEdgeTurnedTowardsAFaceIsApartByTheDistanceToTheEdge) {
  const double h = 1, reach = h + h * std::sqrt(2.0), g = 0.25;
  const OrientedBox fixed = axis_box({0, 0, 0}, {h, h, h});
  int axis = -1;
  EXPECT_NEAR(gap_of(fixed, {{reach + g, 0, 0}, turned_about_z(M_PI / 4), {h, h, h}}, axis), g,
              2e-11);
}

// The point of the box nearest to x (x itself inside): clamped in the box frame.
double distance_to_box(const OrientedBox& b, Vec3 x) {
  const Vec3 local = box_local(b, x);
  const Vec3 nearest{std::clamp(local.x, -b.half_extent.x, b.half_extent.x),
                     std::clamp(local.y, -b.half_extent.y, b.half_extent.y),
                     std::clamp(local.z, -b.half_extent.z, b.half_extent.z)};
  return norm(local - nearest);
}

// The distance from box b to the segment p q: convex along the segment, so a golden-section
// search converges to its least value (to rounding after 200 sections).
double distance_to_segment(const OrientedBox& b, Vec3 p, Vec3 q) {
  auto at = [&](double s) { return distance_to_box(b, p + s * (q - p)); };
  const double shrink = 0.5 * (std::sqrt(5.0) - 1);
  double lo = 0, hi = 1;
  for (int k = 0; k < 200; ++k) {
    const double x1 = hi - shrink * (hi - lo), x2 = lo + shrink * (hi - lo);
    if (at(x1) < at(x2))
      hi = x2;
    else
      lo = x1;
  }
  return std::min({at(0), at(1), at(0.5 * (lo + hi))});
}

// The distance from the edges of a to box b.
double edges_to_box(const OrientedBox& a, const OrientedBox& b) {
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
    for (int s1 : {-1, 1})
      for (int s2 : {-1, 1}) {
        Vec3 lo, hi;
        const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        double corner[3];
        corner[k1] = s1, corner[k2] = s2, corner[k] = -1;
        lo = box_point(a, {corner[0], corner[1], corner[2]});
        corner[k] = 1;
        hi = box_point(a, {corner[0], corner[1], corner[2]});
        best = std::min(best, distance_to_segment(b, lo, hi));
      }
  return best;
}

// The exact distance between two disjoint boxes: the nearest points can be taken with one of
// them on an edge (or corner) of its box, so it is the least distance from an edge of either box
// to the other box.
double box_distance(const OrientedBox& a, const OrientedBox& b) {
  return std::min(edges_to_box(a, b), edges_to_box(b, a));
}

// Random box pairs, some separated only by a cross-product axis (whose length is below 1, so a
// gap left unnormalised would be too large): the gap never exceeds the exact distance (to its
// rounding, 1e-12 of the size), is positive exactly when the test reports the pair apart, and is
// not vacuous (most gaps are within a factor 3 of the distance).
TEST(OrientedBoxGap, TheGapIsALowerBoundOnTheDistanceBetweenTheBoxes) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1), size(0.2, 1.5), spread(1.0, 3.5);
  int separated = 0, by_cross_axis = 0, within_factor_3 = 0;
  for (int trial = 0; trial < 600; ++trial) {
    auto random_box = [&](Vec3 centre) {
      Quat q{unit(random), unit(random), unit(random), unit(random)};
      const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      q = Quat{q.w / n, q.x / n, q.y / n, q.z / n};
      return OrientedBox{centre, rotation_matrix(q),
                         Vec3{size(random), size(random), size(random)}};
    };
    const OrientedBox i = random_box({0, 0, 0});
    const Vec3 direction{unit(random), unit(random), unit(random)};
    const OrientedBox j = random_box((spread(random) / norm(direction)) * direction);
    int axis = -1;
    const double gap = gap_of(i, j, axis);
    EXPECT_EQ(gap > 0, !overlap(i, j)) << "trial " << trial;
    if (!(gap > 0))
      continue;
    ++separated;
    by_cross_axis += axis >= 6 ? 1 : 0;
    const double distance = box_distance(i, j);
    EXPECT_LE(gap, distance + 1e-12) << "trial " << trial << ", axis " << axis;
    within_factor_3 += gap >= distance / 3 ? 1 : 0;
  }
  EXPECT_GT(separated, 150);
  EXPECT_GT(by_cross_axis, 5);
  EXPECT_GT(within_factor_3, 0.8 * separated) << within_factor_3 << " of " << separated;
}

} // namespace
} // namespace kdem
