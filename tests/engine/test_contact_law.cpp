// The tangential parts of the Hertz-Mindlin law against closed forms: the stored spring turned
// onto a new tangent plane keeps its length, and the Coulomb cap holds the tangential force at
// mu F_n exactly when the spring's force exceeds it, and leaves it alone below.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact_test_support.hpp"
#include "kernels/contact_law.hpp"

namespace kdem {
namespace {

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  const Vec3 v{gauss(rng), gauss(rng), gauss(rng)};
  return (1.0 / norm(v)) * v;
}

// Length and direction: the result lies in the plane (its normal part is the projection's
// rounding, a few ulps of |a|, scaled up with the rest by |a| / |projection|: 1e-15 |a| times
// that), has the old length to 1e-15 (one root and a few products), and points along the
// projection (cross product at rounding).
TEST(ContactLaw, SpringTurnedOntoTheTangentPlaneKeepsItsLength) {
  std::mt19937_64 rng(7);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 n = random_unit(rng);
    const Vec3 a = (1e-6 * (1 + k % 7)) * random_unit(rng);
    const Vec3 turned = rotate_onto_plane(a, n);
    const Vec3 projected = a - dot(a, n) * n;
    ASSERT_GT(norm(projected), 1e-12 * norm(a)) << k; // a generic direction
    const double scale = norm(a) / norm(projected);
    EXPECT_LT(std::fabs(dot(turned, n)), 1e-15 * norm(a) * scale) << k;
    EXPECT_NEAR(norm(turned), norm(a), 1e-15 * norm(a)) << k;
    EXPECT_LT(norm(cross(turned, projected)), 1e-15 * norm(turned) * norm(projected)) << k;
  }
}

TEST(ContactLaw, ZeroSpringAndSpringAlongTheNormalGiveNoSpring) {
  const Vec3 n{0, 0, 1};
  EXPECT_EQ(norm(rotate_onto_plane(Vec3{}, n)), 0.0);
  EXPECT_EQ(norm(rotate_onto_plane(Vec3{0, 0, 3e-6}, n)), 0.0); // no direction left in the plane
  // 1e-9 rad off the normal: still a direction (the cut is 1e-12 rad), turned to full length.
  const Vec3 tilted{1e-9 * 3e-6, 0, 3e-6};
  EXPECT_NEAR(norm(rotate_onto_plane(tilted, n)), norm(tilted), 1e-15 * norm(tilted));
  EXPECT_GT(rotate_onto_plane(tilted, n).x, 0.0);
}

ContactInput resting_contact(double overlap) {
  ContactInput in;
  in.geometry.touching = true;
  in.geometry.overlap = overlap;
  in.geometry.normal = Vec3{0, 0, 1};
  in.effective_radius = 1e-3;
  in.effective_mass = 1e-5;
  return in; // no relative motion: no damping, the spring alone
}

// F_n = 4/3 E* sqrt(R*) d^1.5, S_t = 8 G* sqrt(R* d); with the spring s along x the tangential
// force is -S_t s below mu F_n, and -mu F_n along x (the spring cut to mu F_n / S_t) above.
TEST(ContactLaw, CoulombCapHoldsTheTangentialForceAtMuTimesTheNormalForce) {
  const PairCoefficients c = testing::glass_pair();
  const double overlap = 1e-6;
  const ContactInput in = resting_contact(overlap);
  const double normal_force =
      4.0 / 3.0 * c.effective_youngs * std::sqrt(1e-3) * std::pow(overlap, 1.5);
  const double stiffness = 8 * c.effective_shear * std::sqrt(1e-3 * overlap);
  const double sticking_limit = c.friction * normal_force / stiffness; // spring length at the cap
  for (const double fraction : {0.5, 0.999, 1.001, 3.0}) {
    ContactHistory history{Vec3{fraction * sticking_limit, 0, 0}, Vec3{}};
    const ContactOutput out = hertz_mindlin<false>(c, in, 1e-7, history);
    EXPECT_NEAR(out.normal_force, normal_force, 1e-14 * normal_force);
    const double tangential = out.force_on_i.x;
    if (fraction < 1) {
      EXPECT_NEAR(tangential, -stiffness * fraction * sticking_limit, 1e-14 * normal_force)
          << fraction;
      EXPECT_NEAR(history.tangential_spring.x, fraction * sticking_limit, 1e-14 * sticking_limit);
    } else {
      EXPECT_NEAR(tangential, -c.friction * normal_force, 1e-14 * normal_force) << fraction;
      EXPECT_NEAR(history.tangential_spring.x, sticking_limit, 1e-14 * sticking_limit) << fraction;
    }
    EXPECT_EQ(out.force_on_i.y, 0.0);
  }
}

} // namespace
} // namespace kdem
