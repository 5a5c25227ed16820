// Geometry kernels against closed forms and brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shapes/sphere.hpp"
#include "shapes/wall_geometry.hpp"

namespace kdem {
namespace {

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * ((rng() >> 11) * 0x1.0p-53);
}

// Brute force: the closest of 200 x 200 barycentric samples of the triangle. The sample spacing
// is 1/200 of an edge, so the true distance is within about one spacing of the sampled one.
double sampled_distance(Vec3 a, Vec3 b, Vec3 c, Vec3 p) {
  double best = 1e300;
  const int n = 200;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 q = a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a);
      best = std::min(best, norm(p - q));
    }
  return best;
}

TEST(TriangleQuery, ClosestPointMatchesBruteForce) {
  std::mt19937_64 rng(42);
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0.3, 0.8, 0};
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p{uniform(rng, -1, 2), uniform(rng, -1, 2), uniform(rng, -1, 1)};
    const SurfaceQuery q = triangle_query(a, b, c, p);
    const double brute = sampled_distance(a, b, c, p);
    EXPECT_LE(q.signed_distance, brute + 1e-12);     // never farther than a sample
    EXPECT_GE(q.signed_distance, brute - 1.0 / 200); // within one sample spacing
  }
}

TEST(TriangleQuery, FeaturesAreClassified) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_EQ(triangle_query(a, b, c, {0.2, 0.2, 1}).feature, 0);  // face
  EXPECT_EQ(triangle_query(a, b, c, {0.5, -1, 0.3}).feature, 1); // edge ab
  EXPECT_EQ(triangle_query(a, b, c, {1, 1, 0.3}).feature, 2);    // edge bc
  EXPECT_EQ(triangle_query(a, b, c, {-1, 0.5, 0.3}).feature, 3); // edge ca
  EXPECT_EQ(triangle_query(a, b, c, {-1, -1, 0}).feature, 4);    // vertex a
  EXPECT_EQ(triangle_query(a, b, c, {2, -0.5, 0}).feature, 5);   // vertex b
  EXPECT_EQ(triangle_query(a, b, c, {-0.5, 2, 0}).feature, 6);   // vertex c
  const SurfaceQuery face = triangle_query(a, b, c, {0.2, 0.2, -0.5});
  EXPECT_NEAR(face.signed_distance, 0.5, 1e-15);
  EXPECT_NEAR(face.free_normal.z, -1.0, 1e-15); // points from the surface to the centre
}

TEST(SphereSphere, OverlapNormalAndPointAreExact) {
  const ContactGeometry g = sphere_sphere({0, 0, 0.0015}, 0.001, {0, 0, 0}, 0.0006);
  ASSERT_TRUE(g.touching);
  EXPECT_NEAR(g.overlap, 0.0001, 1e-18);
  EXPECT_DOUBLE_EQ(g.normal.z, 1.0);
  EXPECT_NEAR(g.point.z, 0.0006 - 0.00005, 1e-18); // middle of the overlap
  EXPECT_FALSE(sphere_sphere({0, 0, 0.0016}, 0.001, {0, 0, 0}, 0.0006).touching);
}

TEST(Quaternion, RotationVectorIsExactAcrossTheSeriesSwitch) {
  // The small-angle series and the trigonometric form agree at the switch (1e-3 rad) and both
  // give a unit quaternion that rotates by the angle.
  for (double angle : {1e-12, 1e-6, 0.999e-3, 1.001e-3, 0.1, 3.0}) {
    const Vec3 axis{0.6, 0.0, 0.8};
    const Quat q = quat_from_rotation_vector(angle * axis);
    EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0, 4.5e-16); // two ulps
    // The angle is the rotation vector's norm, within an ulp or two of `angle` (an ulp is 4.4e-16
    // at 3 rad; fused multiply-adds round the norm differently), which moves the half angle's
    // sine and cosine by at most half of that each: 4.5e-16 allows two ulps.
    EXPECT_NEAR(q.w, std::cos(0.5 * angle), 4.5e-16);
    EXPECT_NEAR(q.x, 0.6 * std::sin(0.5 * angle), 4.5e-16);
    const Vec3 rotated = rotate(q, Vec3{0, 1, 0}); // perpendicular to the axis
    EXPECT_NEAR(dot(rotated, Vec3{0, 1, 0}), std::cos(angle), 1e-15);
  }
}

TEST(CylinderInside, DistanceFromTheAxis) {
  double along = 0;
  const SurfaceQuery q =
      cylinder_inside_query({0, 0, 0.1}, {0, 0, 1}, 0.03, {0.01, 0.0, 0.5}, along);
  EXPECT_NEAR(along, 0.4, 1e-16);
  EXPECT_NEAR(q.signed_distance, 0.02, 1e-16);
  EXPECT_NEAR(q.free_normal.x, -1.0, 1e-16);
  EXPECT_NEAR(q.point.x, 0.03, 1e-16);
}

} // namespace
} // namespace kdem
