// Oriented boxes, the families' bounding-box trait and the pair broad phase's separating-axis
// test: closed forms of touching boxes, a box turned about one axis, a body box off its body's
// centre, and the test's sufficiency (a pair it reports apart has no common sampled point).
#include <gtest/gtest.h>

#include <cmath>
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

bool inside(const OrientedBox& b, Vec3 x) {
  const Vec3 local = transpose(b.rotation) * (x - b.centre);
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

} // namespace
} // namespace kdem
