// The generic convex narrow phase: GJK distances against closed forms (spheres, boxes, a
// superquadric and a plane), and a dilated core against convex bodies through it, checked
// against the dedicated methods on the same pairs: a sphere given by its support against the
// sphere's closed-form contacts with the core, and a dilated tiny core (a sphere) against the
// exact sphere-superquadric closest point. Tolerances are stated where they are set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "dilated_test_support.hpp"
#include "shapes/dilated_convex_contact.hpp"
#include "shapes/dilated_polyhedron_properties.hpp"
#include "shapes/superquadric_contact.hpp"

namespace kdem::testing {
namespace {

struct SphereBody {
  Vec3 centre;
  double radius = 0;
  Vec3 operator()(Vec3 d) const { return centre + (radius / norm(d)) * d; }
};

struct BoxBody { // axis-aligned, half-widths h about c
  Vec3 c, h;
  Vec3 operator()(Vec3 d) const {
    return c + Vec3{d.x >= 0 ? h.x : -h.x, d.y >= 0 ? h.y : -h.y, d.z >= 0 ? h.z : -h.z};
  }
};

double box_gap(double ca, double ha, double cb, double hb) {
  return std::max(0.0, std::fabs(ca - cb) - ha - hb);
}

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Vec3 v{g(rng), g(rng), g(rng)};
  return (1.0 / norm(v)) * v;
}

Quat random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g;
  double q[4] = {g(rng), g(rng), g(rng), g(rng)};
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return Quat{q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

TEST(ConvexDistance, SpheresAndBoxesMatchTheirClosedForms) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3, 3), size(0.2, 1.5);
  const ConvexDistanceControls controls{1e-12, 64};
  int apart = 0;
  for (int k = 0; k < 500; ++k) {
    const SphereBody a{Vec3{u(rng), u(rng), u(rng)}, size(rng)};
    const SphereBody b{Vec3{u(rng), u(rng), u(rng)}, size(rng)};
    const ConvexDistance d = convex_distance(a, b, a.centre - b.centre, controls);
    const double exact = norm(a.centre - b.centre) - a.radius - b.radius;
    ASSERT_EQ(d.status, 0) << k;
    EXPECT_EQ(d.intersecting, exact < 0) << k;
    if (exact > 1e-6) {
      ++apart;
      // Stated tolerance 1e-9: the loop stops once |v| is within 1e-12 of the distance, and a
      // sphere's support is exact; the closest points lie on the spheres.
      EXPECT_NEAR(d.distance, exact, 1e-9) << k;
      EXPECT_NEAR(norm(d.point_a - a.centre), a.radius, 1e-9);
      EXPECT_NEAR(norm(d.point_a - d.point_b), d.distance, 1e-9);
    }
  }
  EXPECT_GT(apart, 100);
  for (int k = 0; k < 500; ++k) {
    const BoxBody a{Vec3{u(rng), u(rng), u(rng)}, Vec3{size(rng), size(rng), size(rng)}};
    const BoxBody b{Vec3{u(rng), u(rng), u(rng)}, Vec3{size(rng), size(rng), size(rng)}};
    const ConvexDistance d = convex_distance(a, b, a.c - b.c, controls);
    const double gx = box_gap(a.c.x, a.h.x, b.c.x, b.h.x), gy = box_gap(a.c.y, a.h.y, b.c.y, b.h.y),
                 gz = box_gap(a.c.z, a.h.z, b.c.z, b.h.z);
    const double exact = std::sqrt(gx * gx + gy * gy + gz * gz);
    ASSERT_EQ(d.status, 0) << k;
    EXPECT_EQ(d.intersecting, exact == 0) << k;
    if (exact > 0)
      EXPECT_NEAR(d.distance, exact, 1e-10) << k; // polytopes: exact up to rounding
  }
}

TEST(ConvexDistance, SuperquadricToAPlaneTriangleIsItsSupportHeight) {
  // A large triangle under a superquadric: the distance is the height of the superquadric's
  // support point along the triangle's normal (closed form), whatever its orientation. GJK meets
  // a curved body by a sequence of support points; stated tolerance 1e-9 of its size.
  std::mt19937 rng(5);
  const SuperquadricShape shapes[3] = {make_superquadric(1.0, 0.7, 0.5, 2, 2),
                                       make_superquadric(1.0, 0.8, 0.6, 4, 3),
                                       make_superquadric(0.9, 0.9, 0.5, 10, 8)};
  for (const SuperquadricShape& shape : shapes)
    for (int k = 0; k < 100; ++k) {
      const PosedSuperquadric body{shape, Vec3{0, 0, 2.0}, rotation_matrix(random_rotation(rng))};
      const SupportInFrame<PosedSuperquadric> support{body, body.rotation, body.centre};
      TriangleSupport triangle{{Vec3{-20, -20, 0}, Vec3{30, -10, 0}, Vec3{0, 30, 0}}};
      const ConvexDistance d =
          convex_distance(support, triangle, body.centre, ConvexDistanceControls{1e-12, 64});
      const double exact = support(Vec3{0, 0, -1}).z;
      ASSERT_EQ(d.status, 0);
      ASSERT_FALSE(d.intersecting);
      EXPECT_NEAR(d.distance, exact, 1e-9) << shape.n1 << " " << k;
      EXPECT_NEAR(d.point_b.z, 0, 1e-12);
    }
}

// Contacts of a sphere with the core by its closed form and as a support; same features,
// overlaps and normals.
struct Worst {
  double normal = 0, point = 0;
};

void expect_same_contacts(const DilatedCore& core, Vec3 centre, double radius, Worst& worst) {
  test::ContactList by_sphere, by_support;
  const ConeSlack slack;
  ASSERT_TRUE(dilated_sphere_contacts(core, centre, radius, slack, by_sphere));
  const SphereBody sphere{centre, radius};
  const DilatedConvexTally t = dilated_convex_contacts(
      core, sphere, centre, radius, ConvexDistanceControls{1e-13, 64}, slack, by_support);
  EXPECT_EQ(t.unconverged, 0);
  EXPECT_EQ(t.deep, 0);
  ASSERT_EQ(by_sphere.contacts.size(), by_support.contacts.size())
      << centre.x << " " << centre.y << " " << centre.z;
  const auto order = [](const FeatureContact& p, const FeatureContact& q) {
    return p.feature_a < q.feature_a;
  };
  std::sort(by_sphere.contacts.begin(), by_sphere.contacts.end(), order);
  std::sort(by_support.contacts.begin(), by_support.contacts.end(), order);
  for (size_t c = 0; c < by_sphere.contacts.size(); ++c) {
    const FeatureContact &s = by_sphere.contacts[c], &g = by_support.contacts[c];
    EXPECT_EQ(s.feature_a, g.feature_a);
    // Face contacts come from the support point: exact. At an edge or a vertex GJK's closest
    // point carries its tangential error, sqrt(2 R tol) = 4.5e-7 for R = 1 and tol = 1e-13,
    // magnified in the normal by R / d (d: the core point's distance to the body, down to a
    // fraction of the dilation): stated 1e-4 on the normal and 1e-5 on the point. The distance,
    // and so the overlap, within the tolerance where GJK converges; where rounding stops |v|
    // from decreasing first it stops there (measured up to 1.7e-9 with -O3): 1e-8 stated.
    EXPECT_NEAR(s.overlap, g.overlap, 1e-8);
    worst.normal = std::max(worst.normal, norm(s.normal - g.normal));
    worst.point = std::max(worst.point, norm(s.point - g.point));
  }
}

TEST(DilatedConvex, SphereAsASupportMatchesTheSphereMethod) {
  // Random spheres outside a box and a concave U prism, within reach of their dilated surface
  // but not crossing the core: each local minimum found once, as by the closed form.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1), size(0.05, 1.0);
  const DilatedCore cores[2] = {test::core_of(test::box_mesh(1.0, 0.7, 0.4), 0.2),
                                test::core_of(test::u_prism_mesh(1.0, 1.0), 0.2)};
  Worst worst;
  for (const DilatedCore& core : cores) {
    int touching = 0;
    for (int k = 0; k < 2000; ++k) {
      const Vec3 centre{2.5 * u(rng), 2.5 * u(rng), 2.5 * u(rng)};
      const double radius = size(rng);
      const double gap = core_distance(core, centre).signed_distance - radius;
      if (!(gap > 1e-6))
        continue; // crossing the core: the deep rule, tested below
      expect_same_contacts(core, centre, radius, worst);
      touching += gap < core.dilation() ? 1 : 0;
    }
    EXPECT_GT(touching, 50);
  }
  RecordProperty("worst_normal_difference", std::to_string(worst.normal));
  RecordProperty("worst_point_difference", std::to_string(worst.point));
  EXPECT_LT(worst.normal, 1e-4);
  EXPECT_LT(worst.point, 1e-5);
}

TEST(DilatedConvex, DilatedTinyCoreMatchesTheSphereSuperquadricMethod) {
  // A tetrahedron of circumradius 1e-7 dilated by R is a sphere of radius R to 1e-7; its contacts
  // with a superquadric through GJK against the exact sphere-superquadric closest point. Stated
  // agreement: overlap to 1e-6 R, normal to 1e-3 (the tiny core's corners and GJK's tolerance).
  std::mt19937 rng(9);
  const double R = 0.3;
  const DilatedCore tiny = test::core_of(test::tetrahedron_mesh(1e-7), R);
  const SuperquadricShape shapes[3] = {make_superquadric(1.0, 0.7, 0.5, 2, 2),
                                       make_superquadric(1.0, 0.8, 0.6, 4, 3),
                                       make_superquadric(0.9, 0.9, 0.5, 8, 6)};
  double worst_overlap = 0, worst_normal = 0;
  int compared = 0;
  for (const SuperquadricShape& shape : shapes)
    for (int k = 0; k < 200; ++k) {
      const PosedSuperquadric body{shape, Vec3{}, rotation_matrix(random_rotation(rng))};
      const Vec3 direction = random_unit(rng);
      const Vec3 surface =
          body.to_world(body.support_local(transpose_times(body.rotation, direction)));
      const Vec3 centre = surface + (R - 0.02 * R * (k % 5)) * direction;
      const NarrowPhaseResult exact =
          sphere_superquadric_contact(centre, R, body, MidwayState{}, NarrowPhaseControls{});
      test::ContactList found;
      const SupportInFrame<PosedSuperquadric> support{body, body.rotation, body.centre - centre};
      dilated_convex_contacts(tiny, support, body.centre - centre, body.reach(),
                              ConvexDistanceControls{1e-12, 64}, ConeSlack{}, found);
      ASSERT_EQ(exact.status, 0);
      if (!exact.geometry.touching || exact.geometry.overlap < 1e-6 * R) {
        EXPECT_TRUE(found.contacts.empty() || found.deepest() < 2e-6 * R);
        continue;
      }
      ASSERT_GE(found.contacts.size(), 1u);
      const FeatureContact& c = *std::max_element(
          found.contacts.begin(), found.contacts.end(),
          [](const FeatureContact& p, const FeatureContact& q) { return p.overlap < q.overlap; });
      // found: normal from the superquadric towards the core; exact: towards the sphere.
      worst_overlap = std::max(worst_overlap, std::fabs(c.overlap - exact.geometry.overlap));
      worst_normal = std::max(worst_normal, norm(c.normal - exact.geometry.normal));
      ++compared;
    }
  RecordProperty("compared", std::to_string(compared));
  RecordProperty("worst_overlap_difference_over_R", std::to_string(worst_overlap / R));
  RecordProperty("worst_normal_difference", std::to_string(worst_normal));
  EXPECT_GT(compared, 400);
  EXPECT_LT(worst_overlap, 1e-6 * R);
  EXPECT_LT(worst_normal, 1e-3);
}

TEST(DilatedConvex, EllipsoidInTheNotchOfAConcaveCoreTouchesBothWalls) {
  // The U prism's notch spans x in [1, 2] above y = 1; an ellipsoid of half-width 0.47 along x
  // centred in it overlaps each side wall's dilated surface (r = 0.1) by 0.07.
  const DilatedCore core = test::core_of(test::u_prism_mesh(1.0, 1.0), 0.1);
  const PosedSuperquadric body{make_superquadric(0.47, 0.3, 0.3, 2, 2), Vec3{1.5, 1.6, 0.5},
                               identity3()};
  const SupportInFrame<PosedSuperquadric> support{body, identity3(), body.centre};
  test::ContactList found;
  const DilatedConvexTally t =
      dilated_convex_contacts(core, support, body.centre, body.reach(),
                              ConvexDistanceControls{1e-12, 64}, ConeSlack{}, found);
  EXPECT_EQ(t.deep, 0);
  ASSERT_EQ(found.contacts.size(), 2u);
  for (const FeatureContact& c : found.contacts) {
    EXPECT_NEAR(c.overlap, 0.07, 1e-12);            // face contacts: from the support point, exact
    EXPECT_NEAR(std::fabs(c.normal.x), 1.0, 1e-12); // towards the wall it touches
  }
  EXPECT_NEAR(found.contacts[0].normal.x + found.contacts[1].normal.x, 0, 1e-12);
}

TEST(DilatedConvex, CrossingAFaceContinuesItsContact) {
  // A cube-like superquadric lowered onto the top face of a box and through it: while outside the
  // core the overlap is r - gap; once it crosses the face, r + depth below the plane, with the
  // face's normal, from the same support point: the overlap is continuous through the crossing,
  // never NaN, and each step down adds its length to it (stated 1e-9: rounding of the heights).
  const double r = 0.1;
  const DilatedCore core = test::core_of(test::box_mesh(1.0, 1.0, 0.5), r);
  const SuperquadricShape shape = make_superquadric(0.3, 0.3, 0.3, 6, 6);
  double previous = -1;
  for (int k = 0; k <= 40; ++k) {
    const double bottom = 0.5 + 0.05 - 0.005 * k; // from 0.05 above the face to 0.15 below
    const PosedSuperquadric body{shape, Vec3{0.2, -0.1, bottom + 0.3}, identity3()};
    const SupportInFrame<PosedSuperquadric> support{body, identity3(), body.centre};
    test::ContactList found;
    const DilatedConvexTally t =
        dilated_convex_contacts(core, support, body.centre, body.reach(),
                                ConvexDistanceControls{1e-12, 64}, ConeSlack{}, found);
    ASSERT_FALSE(found.contacts.empty()) << k;
    if (std::fabs(bottom - 0.5) > 1e-9)
      EXPECT_EQ(t.deep > 0, bottom < 0.5) << k;
    const double expected = r + 0.5 - bottom;
    for (const FeatureContact& c : found.contacts) {
      ASSERT_TRUE(std::isfinite(c.overlap) && std::isfinite(c.point.x)) << k;
      EXPECT_NEAR(c.overlap, expected, 1e-9) << k;
      EXPECT_NEAR(c.normal.z, -1.0, 1e-9) << k; // from the body down into the core
    }
    if (previous > 0)
      EXPECT_NEAR(found.deepest() - previous, 0.005, 1e-9) << k;
    previous = found.deepest();
  }
}

TEST(DilatedConvex, FlatFaceOnFlatFaceGivesOneContact) {
  // A nearly flat-faced superquadric (n = 20) resting parallel on the box's top face, made of
  // two triangles split on the diagonal y = x: its lowest point over one triangle gives one
  // contact, exactly r - gap along the face's normal (closed form: the support point); centred
  // on the diagonal, both triangles claim it (two equal contacts, weighted one half each by the
  // averaging), never neither.
  const double r = 0.1, gap = 0.04;
  const DilatedCore core = test::core_of(test::box_mesh(1.0, 1.0, 0.5), r);
  for (const double x : {0.0, 0.3}) {
    const PosedSuperquadric body{make_superquadric(0.4, 0.4, 0.2, 20, 20),
                                 Vec3{x, -0.1 * x, 0.7 + gap}, identity3()};
    const SupportInFrame<PosedSuperquadric> support{body, identity3(), body.centre};
    test::ContactList found;
    const DilatedConvexTally t =
        dilated_convex_contacts(core, support, body.centre, body.reach(),
                                ConvexDistanceControls{1e-12, 64}, ConeSlack{}, found);
    EXPECT_EQ(t.unconverged, 0);
    EXPECT_EQ(found.contacts.size(), x == 0 ? 2u : 1u) << x;
    for (const FeatureContact& c : found.contacts) {
      EXPECT_NEAR(c.overlap, r - gap, 1e-14);
      EXPECT_EQ(c.normal.z, -1.0);
    }
  }
}

} // namespace
} // namespace kdem::testing
