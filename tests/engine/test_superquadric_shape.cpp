// Superquadric shape function, mass properties, bounding sphere and bounding boxes against
// quadrature, brute force, finite differences and closed forms. Device functions run in a
// parallel_for over a View of cases and are checked on the host.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "kernels/types.hpp"
#include "shapes/sphere.hpp"
#include "shapes/superquadric.hpp"
#include "shapes/superquadric_properties.hpp"

#include "geometry_test_support.hpp"
#include "numeric_test_support.hpp"

namespace kdem {
namespace {

using namespace testing;

Vec3 unit_axis(int k) {
  return {k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0};
}

double max_abs(Vec3 v) {
  return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

double max_abs(const Mat3& m) {
  double largest = 0;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      largest = std::max(largest, std::fabs(m.m[r][k]));
  return largest;
}

// Shapes across the exponent range [2, 10], integer and not, n1 == n2 and not, aspect 0.2 to 5.
std::vector<SuperquadricShape> test_shapes() {
  return {make_superquadric(1, 1, 1, 2, 2),           make_superquadric(1, 0.7, 1.5, 4, 3),
          make_superquadric(0.8, 1.2, 0.5, 2.5, 3.7), make_superquadric(1, 0.2, 5, 3.7, 2.5),
          make_superquadric(1.3, 0.9, 0.6, 8, 8),     make_superquadric(0.5, 0.5, 2, 6, 2),
          make_superquadric(1, 1, 1, 10, 2),          make_superquadric(1, 2, 0.5, 4.2, 4.2),
          make_superquadric(0.3, 1, 0.7, 2, 10),      make_superquadric(5, 1, 0.2, 10, 10),
          make_superquadric(0.6, 0.4, 1.1, 3, 5.5)};
}

// ---------------------------------------------------------------------------------------------
// Volume and inertia

struct MassIntegrals {
  double volume = 0;
  Vec3 second_moments; // integrals of x^2, y^2, z^2 over the body
};

// Book Eqs. 2.3-2.6 over the octant with the digest's limits: z in [0, c], x in [0, x_m(z)] and
// the y integral done analytically (int dy = y_m, int y^2 dy = y_m^3 / 3); x = x_m(z) * xi.
MassIntegrals integrate_octants(const SuperquadricShape& s) {
  const std::vector<QuadratureNode> nodes = tanh_sinh_nodes(64, 3.5);
  MassIntegrals sum;
  for (const QuadratureNode& zn : nodes) {
    const double z = s.c * zn.x;
    const double remaining = std::max(0.0, 1.0 - std::pow(z / s.c, s.n1));
    const double x_max = s.a * std::pow(remaining, 1.0 / s.n1);
    for (const QuadratureNode& xn : nodes) {
      const double x = x_max * xn.x;
      const double base = std::pow(remaining, s.n2 / s.n1) - std::pow(x / s.a, s.n2);
      const double y_max = s.b * std::pow(std::max(0.0, base), 1.0 / s.n2);
      const double w = 8.0 * zn.weight * xn.weight * s.c * x_max;
      sum.volume += w * y_max;
      sum.second_moments += w * Vec3{x * x * y_max, y_max * y_max * y_max / 3.0, z * z * y_max};
    }
  }
  return sum;
}

TEST(SuperquadricShape, VolumeAndInertiaMatchQuadrature) {
  const double density = 2500;
  double worst = 0;
  for (const SuperquadricShape& s : test_shapes()) {
    const MassIntegrals q = integrate_octants(s);
    const Vec3 inertia = superquadric_principal_inertia(s, density);
    const Vec3 expected = density * Vec3{q.second_moments.y + q.second_moments.z,
                                         q.second_moments.x + q.second_moments.z,
                                         q.second_moments.x + q.second_moments.y};
    // Tanh-sinh with 449^2 nodes converges to ~1e-13 here; 1e-10 leaves room without hiding any
    // error in a Beta-function argument (those change the result at the 1e-2 level).
    const double tolerance = 1e-10;
    SCOPED_TRACE(::testing::Message() << "a,b,c = " << s.a << "," << s.b << "," << s.c
                                      << " n1,n2 = " << s.n1 << "," << s.n2);
    EXPECT_NEAR(superquadric_volume(s) / q.volume, 1.0, tolerance);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(inertia[k] / expected[k], 1.0, tolerance) << "axis " << k;
    worst = std::max({worst, std::fabs(superquadric_volume(s) / q.volume - 1),
                      std::fabs(inertia.x / expected.x - 1), std::fabs(inertia.y / expected.y - 1),
                      std::fabs(inertia.z / expected.z - 1)});
  }
  RecordProperty("worst_relative_error", scientific(worst));
}

TEST(SuperquadricShape, SphereAndEllipsoidMassPropertiesAreExact) {
  // lgamma/exp round to a few ulps: 1e-14 relative.
  const double tolerance = 1e-14, density = 2500;
  const double r = 0.7;
  const SuperquadricShape sphere = make_superquadric(r, r, r, 2, 2);
  const double mass = density * 4.0 / 3.0 * pi * r * r * r;
  EXPECT_NEAR(superquadric_volume(sphere) / (4.0 / 3.0 * pi * r * r * r), 1.0, tolerance);
  const Vec3 inertia = superquadric_principal_inertia(sphere, density);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(inertia[k] / (0.4 * mass * r * r), 1.0, tolerance);

  const double a = 0.3, b = 1.1, c = 2.0;
  const SuperquadricShape ellipsoid = make_superquadric(a, b, c, 2, 2);
  const double ellipsoid_mass = density * 4.0 / 3.0 * pi * a * b * c;
  EXPECT_NEAR(superquadric_volume(ellipsoid) / (4.0 / 3.0 * pi * a * b * c), 1.0, tolerance);
  const Vec3 ellipsoid_inertia = superquadric_principal_inertia(ellipsoid, density);
  EXPECT_NEAR(ellipsoid_inertia.x / (0.2 * ellipsoid_mass * (b * b + c * c)), 1.0, tolerance);
  EXPECT_NEAR(ellipsoid_inertia.y / (0.2 * ellipsoid_mass * (a * a + c * c)), 1.0, tolerance);
  EXPECT_NEAR(ellipsoid_inertia.z / (0.2 * ellipsoid_mass * (a * a + b * b)), 1.0, tolerance);
}

// ---------------------------------------------------------------------------------------------
// Bounding radius

// Surface point in the direction d from the centre: F is homogeneous of degree n1 along rays.
Vec3 radial_surface_point(const SuperquadricShape& s, Vec3 d) {
  const double section =
      std::pow(std::fabs(d.x / s.a), s.n2) + std::pow(std::fabs(d.y / s.b), s.n2);
  const double level = std::pow(section, s.n1 / s.n2) + std::pow(std::fabs(d.z / s.c), s.n1);
  return std::pow(level, -1.0 / s.n1) * d;
}

// Surface point at angles (eta, omega) of the octant x, y, z >= 0.
Vec3 angular_surface_point(const SuperquadricShape& s, double eta, double omega) {
  const double e1 = 2.0 / s.n1, e2 = 2.0 / s.n2;
  const double ring = std::pow(std::cos(eta), e1);
  return {s.a * ring * std::pow(std::cos(omega), e2), s.b * ring * std::pow(std::sin(omega), e2),
          s.c * std::pow(std::sin(eta), e1)};
}

TEST(SuperquadricShape, BoundingRadiusIsTheFarthestSurfacePoint) {
  std::mt19937_64 rng(7);
  double worst_gap = 0;
  for (const SuperquadricShape& s : test_shapes()) {
    const double radius = superquadric_bounding_radius(s);
    double farthest = 0;
    const int n = 600; // angular grid over the octant, spacing 2.6e-3 rad
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const Vec3 x = angular_surface_point(s, 0.5 * pi * i / n, 0.5 * pi * j / n);
        farthest = std::max(farthest, norm(x));
      }
    for (int trial = 0; trial < 200000; ++trial) {
      const Vec3 x = radial_surface_point(s, random_unit(rng));
      // The samples lie on the surface (conditioned F within rounding of its O(1) terms).
      ASSERT_NEAR(superquadric_local<false>(s, x).value, 0.0, 1e-13);
      farthest = std::max(farthest, norm(x));
    }
    EXPECT_GE(radius, farthest);
    // A grid this fine finds the maximum of the smooth |X| to ~1e-5 relative; a wrong maximiser
    // (such as the conservative sqrt(A^2 + c^2) of the n2 = 2 branch) is off by > 1e-2.
    EXPECT_LE(radius, farthest * (1 + 2e-5))
        << "n1,n2 = " << s.n1 << "," << s.n2 << " radius " << radius << " sampled " << farthest;
    worst_gap = std::max(worst_gap, radius / farthest - 1);
  }
  RecordProperty("worst_relative_gap", scientific(worst_gap));
}

TEST(SuperquadricShape, BoundingRadiusClosedFormCases) {
  // Only the stated safety factor separates these from the exact values.
  const double tolerance = 2 * bounding_radius_safety;
  const auto relative = [](double radius, double exact) { return radius / exact - 1; };
  EXPECT_NEAR(relative(superquadric_bounding_radius(make_superquadric(0.7, 0.7, 0.7, 2, 2)), 0.7),
              0, tolerance);
  EXPECT_NEAR(relative(superquadric_bounding_radius(make_superquadric(0.3, 1.1, 2, 2, 2)), 2), 0,
              tolerance);
  // Cylinder-like (n1 = 8, n2 = 2, a = b = c = 1): the rim at x = z = 2^(-1/8), |X| = 2^(3/8).
  EXPECT_NEAR(relative(superquadric_bounding_radius(make_superquadric(1, 1, 1, 8, 2)),
                       std::pow(2.0, 0.375)),
              0, tolerance);
  // Cube-like (n1 = n2 = 4): the corner x = y = z = 3^(-1/4), |X| = 3^(1/4).
  EXPECT_NEAR(
      relative(superquadric_bounding_radius(make_superquadric(1, 1, 1, 4, 4)), std::pow(3.0, 0.25)),
      0, tolerance);
}

// ---------------------------------------------------------------------------------------------
// Shape function: gradient and Hessian

struct EvaluationCase {
  PosedSuperquadric posed;
  Vec3 local_point;
  Vec3 world_point;
};

struct EvaluationResult {
  ShapeFunction local;
  ShapeFunction world;
  double local_value_only = 0; // superquadric_local<false>
  double world_value_only = 0; // PosedSuperquadric::value
  double mean = 0, gaussian = 0, world_mean = 0, world_gaussian = 0;
};

struct EvaluateShape {
  KOKKOS_INLINE_FUNCTION EvaluationResult operator()(const EvaluationCase& c) const {
    EvaluationResult r;
    r.local = superquadric_local(c.posed.shape, c.local_point);
    r.world = c.posed.evaluate(c.world_point);
    r.local_value_only = superquadric_local<false>(c.posed.shape, c.local_point).value;
    r.world_value_only = c.posed.value(c.world_point);
    r.mean = mean_curvature(r.local);
    r.gaussian = gaussian_curvature(r.local);
    r.world_mean = mean_curvature(r.world);
    r.world_gaussian = gaussian_curvature(r.world);
    return r;
  }
};

EvaluationCase make_case(const PosedSuperquadric& posed, Vec3 local) {
  return {posed, local, posed.to_world(local)};
}

std::vector<EvaluationResult> evaluate_on_device(const std::vector<EvaluationCase>& cases) {
  return run_on_device<EvaluationResult>(cases, EvaluateShape{});
}

// Surface point with section direction (alpha, beta) and height w = z / c.
Vec3 surface_point(const SuperquadricShape& s, double alpha, double beta, double w) {
  const double section = std::pow(alpha, s.n2) + std::pow(beta, s.n2);
  const double t = std::pow(1.0 - std::pow(w, s.n1), 1.0 / s.n1) / std::pow(section, 1.0 / s.n2);
  return {s.a * t * alpha, s.b * t * beta, s.c * w};
}

// Surface point above (x, y) = (u a, v b).
Vec3 surface_point_above(const SuperquadricShape& s, double u, double v) {
  const double section = std::pow(std::pow(u, s.n2) + std::pow(v, s.n2), s.n1 / s.n2);
  return {s.a * u, s.b * v, s.c * std::pow(1.0 - section, 1.0 / s.n1)};
}

// Points on, inside and outside the surface, generic and within 1e-3 of the coordinate planes and
// of the body z axis, in random octants.
std::vector<Vec3> probe_points(const SuperquadricShape& s, std::mt19937_64& rng) {
  const std::vector<Vec3> on_surface = {
      surface_point(s, 1, 0.8, 0.5),      surface_point(s, 0.3, 1, 0.8),
      surface_point(s, 1, 0.2, 0.2),      surface_point(s, 1e-3, 1, 0.4), // near x = 0
      surface_point(s, 1, 1e-3, 0.6),     surface_point(s, 1, 0.7, 1e-3), // near y = 0, z = 0
      surface_point_above(s, 1e-3, 2e-3),                                 // near the z axis
      surface_point_above(s, 3e-2, 1e-2)};
  std::vector<Vec3> points;
  for (const Vec3& p : on_surface)
    for (double scale : {1.0, 0.5, 0.9, 1.1, 2.0, 3.0}) {
      const double sx = rng() & 1 ? 1 : -1, sy = rng() & 1 ? 1 : -1, sz = rng() & 1 ? 1 : -1;
      points.push_back(scale * Vec3{sx * p.x, sy * p.y, sz * p.z});
    }
  return points;
}

// Finite-difference step: 1e-3 of the shape's size, and 1/200 of the distance to the nearest
// body coordinate plane, where the powers |x/a|^(n - k) stop being smooth (their fifth
// derivatives grow like n^5 / |x|^5).
double difference_step(const SuperquadricShape& s, Vec3 local) {
  double h = 1e-3 * std::min({s.a, s.b, s.c});
  for (int k = 0; k < 3; ++k)
    if (local[k] != 0)
      h = std::min(h, std::fabs(local[k]) / 200);
  return h;
}

// Fourth-order central difference of f along unit direction e: error h^4 f^(5) / 30.
template <class Function> auto five_point(Function f, Vec3 x, Vec3 e, double h) {
  return (1.0 / (12.0 * h)) *
         ((f(x - 2 * h * e) - f(x + 2 * h * e)) + 8.0 * (f(x + h * e) - f(x - h * e)));
}

Mat3 from_columns(Vec3 c0, Vec3 c1, Vec3 c2) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    m.m[r][0] = c0[r], m.m[r][1] = c1[r], m.m[r][2] = c2[r];
  return m;
}

struct DerivativeErrors {
  double gradient = 0, hessian = 0, symmetry = 0;
};

// Errors of gradient and Hessian against differences of the value and of the gradient, relative
// to the largest entry of each.
template <class Value, class Gradient>
DerivativeErrors derivative_errors(const ShapeFunction& f, Value value, Gradient gradient, Vec3 x,
                                   double h) {
  Vec3 fd_gradient;
  Vec3 columns[3];
  for (int k = 0; k < 3; ++k) {
    const double d = five_point(value, x, unit_axis(k), h);
    fd_gradient = fd_gradient + d * unit_axis(k);
    columns[k] = five_point(gradient, x, unit_axis(k), h);
  }
  const Mat3 fd_hessian = from_columns(columns[0], columns[1], columns[2]);
  DerivativeErrors e;
  e.gradient = max_abs(fd_gradient - f.gradient) / max_abs(f.gradient);
  e.hessian = max_abs_difference(fd_hessian, f.hessian) / max_abs(f.hessian);
  e.symmetry = max_abs_difference(f.hessian, transpose(f.hessian)) / max_abs(f.hessian);
  return e;
}

TEST(SuperquadricShape, GradientAndHessianMatchFiniteDifferences) {
  std::mt19937_64 rng(11);
  std::vector<EvaluationCase> cases;
  for (const SuperquadricShape& s : test_shapes()) {
    const PosedSuperquadric posed =
        pose_superquadric(s, Vec3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)},
                          random_rotation(rng));
    for (const Vec3& p : probe_points(s, rng))
      cases.push_back(make_case(posed, p));
  }
  const std::vector<EvaluationResult> results = evaluate_on_device(cases);

  DerivativeErrors worst_local, worst_world;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const PosedSuperquadric& posed = cases[c].posed;
    const SuperquadricShape& s = posed.shape;
    const Vec3 p = cases[c].local_point;
    const double h = difference_step(s, p);
    const DerivativeErrors local = derivative_errors(
        results[c].local, [&](Vec3 x) { return superquadric_local<false>(s, x).value; },
        [&](Vec3 x) { return superquadric_local<false>(s, x).gradient; }, p, h);
    const DerivativeErrors world = derivative_errors(
        results[c].world, [&](Vec3 x) { return posed.value(x); },
        [&](Vec3 x) { return posed.evaluate<false>(x).gradient; }, cases[c].world_point, h);
    // Truncation (h^4 f^(5) / 30 with h <= 1/200 of the distance to a plane) and rounding of F
    // (~1e-16 |F| / h) keep the differences within 2.4e-8 of the largest entry (measured); a
    // wrong factor or exponent in any entry is an O(1e-3) or larger error.
    const double tolerance = 1e-7;
    SCOPED_TRACE(::testing::Message() << "n1,n2 = " << s.n1 << "," << s.n2 << " point " << p.x
                                      << "," << p.y << "," << p.z);
    EXPECT_LT(local.gradient, tolerance);
    EXPECT_LT(local.hessian, tolerance);
    EXPECT_LT(world.gradient, tolerance);
    EXPECT_LT(world.hessian, tolerance);
    EXPECT_LT(world.symmetry, 1e-14); // R H R^T of a symmetric H: two 3x3 products' rounding
    EXPECT_EQ(local.symmetry, 0.0);   // the off-diagonal entries are assigned once
    // Values: the world value is the local one at the same point (rotation rounding, ~1e-16 of
    // the point, times |grad F| |x|), and the value-only paths agree to an ulp of the terms.
    const double value_scale = std::fabs(results[c].local.value) + s.conditioning;
    EXPECT_NEAR(results[c].world.value, results[c].local.value, 1e-13 * value_scale);
    EXPECT_NEAR(results[c].local_value_only, results[c].local.value, 1e-15 * value_scale);
    EXPECT_NEAR(results[c].world_value_only, results[c].world.value, 1e-15 * value_scale);
    worst_local.gradient = std::max(worst_local.gradient, local.gradient);
    worst_local.hessian = std::max(worst_local.hessian, local.hessian);
    worst_world.gradient = std::max(worst_world.gradient, world.gradient);
    worst_world.hessian = std::max(worst_world.hessian, world.hessian);
  }
  RecordProperty("worst_local_gradient", scientific(worst_local.gradient));
  RecordProperty("worst_local_hessian", scientific(worst_local.hessian));
  RecordProperty("worst_world_gradient", scientific(worst_world.gradient));
  RecordProperty("worst_world_hessian", scientific(worst_world.hessian));
}

// The digest's formulas (Sect. 2) written out with std::pow, conditioning included. Not valid on
// the body z axis, where S = 0 meets negative powers.
ShapeFunction digest_formulas(const SuperquadricShape& s, Vec3 x) {
  const double u = std::fabs(x.x / s.a), v = std::fabs(x.y / s.b), w = std::fabs(x.z / s.c);
  const double su = x.x < 0 ? -1 : 1, sv = x.y < 0 ? -1 : 1, sw = x.z < 0 ? -1 : 1;
  const double n1 = s.n1, n2 = s.n2, p = n1 / n2;
  const double k = std::pow(0.5, std::max(n1, n2) - 2);
  const double S = std::pow(u, n2) + std::pow(v, n2);
  ShapeFunction f;
  f.value = k * (std::pow(S, p) + std::pow(w, n1) - 1);
  f.gradient = Vec3{k * n1 / s.a * std::pow(S, p - 1) * std::pow(u, n2 - 1) * su,
                    k * n1 / s.b * std::pow(S, p - 1) * std::pow(v, n2 - 1) * sv,
                    k * n1 / s.c * std::pow(w, n1 - 1) * sw};
  const auto section_second = [&](double t, double length) {
    return k * n1 / (length * length) *
           ((n2 - 1) * std::pow(t, n2 - 2) * std::pow(S, p - 1) +
            (n1 - n2) * std::pow(t, 2 * n2 - 2) * std::pow(S, p - 2));
  };
  f.hessian.m[0][0] = section_second(u, s.a);
  f.hessian.m[1][1] = section_second(v, s.b);
  f.hessian.m[0][1] = f.hessian.m[1][0] = k * n1 * (n1 - n2) / (s.a * s.b) * su * sv *
                                          std::pow(u, n2 - 1) * std::pow(v, n2 - 1) *
                                          std::pow(S, p - 2);
  f.hessian.m[2][2] = k * n1 * (n1 - 1) / (s.c * s.c) * std::pow(w, n1 - 2);
  return f;
}

// The same shape with its integer fast paths switched off: every power through pow.
SuperquadricShape without_integer_paths(SuperquadricShape s) {
  s.n1_integer = s.n2_integer = s.ratio_minus_two_integer = -1;
  return s;
}

TEST(SuperquadricShape, IntegerFastPathsAndPowPathMatchTheFormulas) {
  std::mt19937_64 rng(5);
  std::vector<SuperquadricShape> shapes = test_shapes();
  const std::vector<std::pair<double, double>> integer_exponents = {{4, 4}, {8, 4}, {12, 4},
                                                                    {3, 3}, {6, 2}, {2, 4}};
  for (const auto& [n1, n2] : integer_exponents)
    shapes.push_back(make_superquadric(0.9, 1.3, 0.7, n1, n2));
  std::vector<EvaluationCase> cases;
  for (const SuperquadricShape& s : shapes)
    for (const Vec3& p : probe_points(s, rng)) {
      if (std::hypot(p.x / s.a, p.y / s.b) < 1e-2)
        continue; // the reference loses digits as S -> 0; the axis is tested separately
      cases.push_back(make_case(pose_superquadric(s, {}, {}), p));
      cases.push_back(make_case(pose_superquadric(without_integer_paths(s), {}, {}), p));
    }
  const std::vector<EvaluationResult> results = evaluate_on_device(cases);
  double worst = 0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const SuperquadricShape& s = cases[c].posed.shape;
    const ShapeFunction expected = digest_formulas(s, cases[c].local_point);
    const ShapeFunction& f = results[c].local;
    // Entry by entry, relative to the entry: pow and repeated products differ by a few ulps,
    // and S^(p - 2) S = S^(p - 1) adds a few more (measured 4e-15); 1e-13 is ~500 ulps and still
    // catches any wrong exponent or factor, which changes an entry by far more.
    const double tolerance = 1e-13;
    const auto relative = [&](double got, double want) {
      const double error = std::fabs(got - want) / std::max(std::fabs(want), 1e-300);
      worst = std::max(worst, got == want ? 0.0 : error);
      return got == want ? 0.0 : error;
    };
    SCOPED_TRACE(::testing::Message()
                 << "n1,n2 = " << s.n1 << "," << s.n2 << " integer paths " << (s.n1_integer >= 0)
                 << " point " << cases[c].local_point.x << "," << cases[c].local_point.y << ","
                 << cases[c].local_point.z);
    // F sums terms of size |F| + k: a few ulps of that.
    EXPECT_LT(std::fabs(f.value - expected.value), 1e-14 * (std::fabs(f.value) + s.conditioning));
    for (int k = 0; k < 3; ++k)
      EXPECT_LT(relative(f.gradient[k], expected.gradient[k]), tolerance) << "gradient " << k;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        EXPECT_LT(relative(f.hessian.m[r][k], expected.hessian.m[r][k]), tolerance)
            << "hessian " << r << k;
  }
  RecordProperty("worst_entry_error", scientific(worst));
}

TEST(SuperquadricShape, ValuesOnTheAxisAndThePlanesAreTheLimits) {
  std::vector<EvaluationCase> cases;
  std::vector<SuperquadricShape> shapes = test_shapes();
  shapes.push_back(make_superquadric(0.9, 1.3, 0.7, 8, 4));
  for (const SuperquadricShape& s : shapes)
    for (double scale : {0.5, 1.0, 2.0}) {
      const PosedSuperquadric posed = pose_superquadric(s, {}, {});
      cases.push_back(make_case(posed, scale * Vec3{0, 0, s.c}));                // z axis
      cases.push_back(make_case(posed, scale * Vec3{0, 0.6 * s.b, 0.5 * s.c}));  // x = 0
      cases.push_back(make_case(posed, scale * Vec3{-0.6 * s.a, 0, 0.5 * s.c})); // y = 0
      cases.push_back(make_case(posed, scale * Vec3{0.5 * s.a, -0.6 * s.b, 0})); // z = 0
      cases.push_back(make_case(posed, scale * Vec3{-0.9 * s.a, 0, 0}));         // x axis
    }
  const std::vector<EvaluationResult> results = evaluate_on_device(cases);
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const SuperquadricShape& s = cases[c].posed.shape;
    const Vec3 p = cases[c].local_point;
    const ShapeFunction& f = results[c].local;
    SCOPED_TRACE(::testing::Message() << "n1,n2 = " << s.n1 << "," << s.n2 << " point " << p.x
                                      << "," << p.y << "," << p.z);
    ShapeFunction expected;
    if (p.x == 0 && p.y == 0) {
      // On the z axis the section terms vanish in the limit (n1 > 2, or n1 == n2), and for
      // n1 = 2 < n2 the code's documented choice is 0 as well.
      const double k = s.conditioning, w = std::fabs(p.z / s.c);
      expected.value = k * (std::pow(w, s.n1) - 1);
      expected.gradient = Vec3{0, 0, k * s.n1 / s.c * std::pow(w, s.n1 - 1)};
      expected.hessian.m[2][2] = k * s.n1 * (s.n1 - 1) / (s.c * s.c) * std::pow(w, s.n1 - 2);
      if (s.n1 == 2 && s.n2 == 2) {
        expected.hessian.m[0][0] = k * 2 / (s.a * s.a);
        expected.hessian.m[1][1] = k * 2 / (s.b * s.b);
      }
    } else {
      expected = digest_formulas(s, p); // finite off the axis, exact zeros included
    }
    // Exact zeros must be exact; the rest agree to pow rounding.
    const auto close = [](double got, double want) {
      return want == 0 ? got == 0 : std::fabs(got / want - 1) < 1e-12;
    };
    EXPECT_TRUE(std::fabs(f.value - expected.value) < 1e-15 * std::max(1.0, std::fabs(f.value)));
    for (int k = 0; k < 3; ++k)
      EXPECT_TRUE(close(f.gradient[k], expected.gradient[k]))
          << "gradient " << k << ": " << f.gradient[k] << " vs " << expected.gradient[k];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        EXPECT_TRUE(close(f.hessian.m[r][k], expected.hessian.m[r][k]))
            << "hessian " << r << k << ": " << f.hessian.m[r][k] << " vs "
            << expected.hessian.m[r][k];
  }
}

// ---------------------------------------------------------------------------------------------
// Curvature

struct ExpectedCurvature {
  Vec3 point;
  double mean, gaussian;
};

// Ellipsoid: K = 1 / (a b c h^2)^2, H = |x^2 + y^2 + z^2 - a^2 - b^2 - c^2| / (2 (a b c)^2 h^3),
// h^2 = x^2/a^4 + y^2/b^4 + z^2/c^4.
ExpectedCurvature ellipsoid_curvature(double a, double b, double c, Vec3 x) {
  const double h2 =
      x.x * x.x / (a * a * a * a) + x.y * x.y / (b * b * b * b) + x.z * x.z / (c * c * c * c);
  const double abc2 = a * a * b * b * c * c;
  return {x, std::fabs(norm2(x) - a * a - b * b - c * c) / (2 * abc2 * h2 * std::sqrt(h2)),
          1.0 / (abc2 * h2 * h2)};
}

// Surface of revolution (n2 = 2, a = b) at radius r from the axis and height z: the meridian
// G(r, z) = (r/a)^n1 + (|z|/c)^n1 = 1 has plane curvature |G_rr G_z^2 + G_zz G_r^2| / |grad G|^3;
// the parallel's normal curvature is G_r / (r |grad G|).
ExpectedCurvature revolution_curvature(double a, double c, double n1, double phi, double w) {
  const double r = a * std::pow(1 - std::pow(w, n1), 1 / n1), z = c * w;
  const double gr = n1 / a * std::pow(r / a, n1 - 1), gz = n1 / c * std::pow(w, n1 - 1);
  const double grr = n1 * (n1 - 1) / (a * a) * std::pow(r / a, n1 - 2);
  const double gzz = n1 * (n1 - 1) / (c * c) * std::pow(w, n1 - 2);
  const double g = std::hypot(gr, gz);
  const double meridian = (grr * gz * gz + gzz * gr * gr) / (g * g * g);
  const double parallel = gr / (r * g);
  return {
      {r * std::cos(phi), r * std::sin(phi), z}, 0.5 * (meridian + parallel), meridian * parallel};
}

TEST(SuperquadricShape, CurvaturesMatchClosedForms) {
  std::mt19937_64 rng(3);
  std::vector<EvaluationCase> cases;
  std::vector<ExpectedCurvature> expected;
  const auto add = [&](const SuperquadricShape& s, const ExpectedCurvature& e) {
    cases.push_back(make_case(
        pose_superquadric(s, {uniform(rng, -1, 1), 0.3, -0.2}, random_rotation(rng)), e.point));
    expected.push_back(e);
  };
  const double r = 0.7;
  for (int i = 0; i < 20; ++i)
    add(make_superquadric(r, r, r, 2, 2), {r * random_unit(rng), 1 / r, 1 / (r * r)});
  const double a = 1, b = 0.7, c = 1.5;
  const SuperquadricShape ellipsoid = make_superquadric(a, b, c, 2, 2);
  // Ends of the semi-axes: principal curvatures a/b^2 and a/c^2 at (a, 0, 0), and the like.
  add(ellipsoid, {{a, 0, 0}, 0.5 * (a / (b * b) + a / (c * c)), a * a / (b * b * c * c)});
  add(ellipsoid, {{0, -b, 0}, 0.5 * (b / (a * a) + b / (c * c)), b * b / (a * a * c * c)});
  add(ellipsoid, {{0, 0, c}, 0.5 * (c / (a * a) + c / (b * b)), c * c / (a * a * b * b)});
  for (int i = 0; i < 20; ++i)
    add(ellipsoid, ellipsoid_curvature(a, b, c, radial_surface_point(ellipsoid, random_unit(rng))));
  for (double n1 : {3.7, 4.0, 8.0}) {
    const SuperquadricShape revolution = make_superquadric(0.6, 0.6, 1.4, n1, 2);
    for (double w : {0.0, 0.2, 0.5, 0.8, 0.95})
      add(revolution, revolution_curvature(0.6, 1.4, n1, uniform(rng, 0, 2 * pi), w));
  }
  // Centre of a face of a cube-like shape: flat to second order.
  add(make_superquadric(0.8, 0.5, 1.2, 4, 4), {{0, 0, -1.2}, 0, 0});
  add(make_superquadric(0.8, 0.5, 1.2, 5.5, 5.5), {{0.8, 0, 0}, 0, 0});

  const std::vector<EvaluationResult> results = evaluate_on_device(cases);
  double worst = 0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const ExpectedCurvature& e = expected[c];
    // Curvatures are rational in F's derivatives, exact to rounding: 1e-12 of the scale 1/r^k
    // (absolute, so that the flat cases with curvature 0 are held to the same bound).
    const double mean_scale = std::max(e.mean, 1.0), gaussian_scale = std::max(e.gaussian, 1.0);
    SCOPED_TRACE(::testing::Message() << "case " << c << " n1,n2 = " << cases[c].posed.shape.n1
                                      << "," << cases[c].posed.shape.n2);
    EXPECT_NEAR(results[c].mean, e.mean, 1e-12 * mean_scale);
    EXPECT_NEAR(results[c].gaussian, e.gaussian, 1e-12 * gaussian_scale);
    // Rotating the body rotates g and H together; the curvatures are invariant.
    EXPECT_NEAR(results[c].world_mean, e.mean, 1e-12 * mean_scale);
    EXPECT_NEAR(results[c].world_gaussian, e.gaussian, 1e-12 * gaussian_scale);
    worst = std::max({worst, std::fabs(results[c].mean - e.mean) / mean_scale,
                      std::fabs(results[c].gaussian - e.gaussian) / gaussian_scale,
                      std::fabs(results[c].world_mean - e.mean) / mean_scale,
                      std::fabs(results[c].world_gaussian - e.gaussian) / gaussian_scale});
  }
  RecordProperty("worst_curvature_error", scientific(worst));
}

// ---------------------------------------------------------------------------------------------
// Bounding boxes

struct BoxCase {
  PosedSuperquadric i, j;
  int hint = -1;
};

struct BoxResult {
  bool overlap = false;
  int axis = -1;
};

struct TestBoxes {
  KOKKOS_INLINE_FUNCTION BoxResult operator()(const BoxCase& c) const {
    BoxResult r;
    r.axis = c.hint;
    r.overlap = bounding_boxes_overlap(c.i, c.j, r.axis);
    return r;
  }
};

Vec3 extents(const SuperquadricShape& s) {
  return {s.a, s.b, s.c};
}

std::vector<Vec3> box_corners(const PosedSuperquadric& s) {
  std::vector<Vec3> corners;
  for (int m = 0; m < 8; ++m)
    corners.push_back(s.to_world({m & 1 ? s.shape.a : -s.shape.a, m & 2 ? s.shape.b : -s.shape.b,
                                  m & 4 ? s.shape.c : -s.shape.c}));
  return corners;
}

// Nearest point of the box of s, its extents scaled by shrink.
Vec3 project_on_box(const PosedSuperquadric& s, Vec3 x, double shrink) {
  const Vec3 local = s.to_local(x), e = shrink * extents(s.shape);
  return s.to_world({std::clamp(local.x, -e.x, e.x), std::clamp(local.y, -e.y, e.y),
                     std::clamp(local.z, -e.z, e.z)});
}

bool inside_box(const PosedSuperquadric& s, Vec3 x, double shrink) {
  const Vec3 local = s.to_local(x), e = shrink * extents(s.shape);
  return std::fabs(local.x) <= e.x && std::fabs(local.y) <= e.y && std::fabs(local.z) <= e.z;
}

// Gap between the corner projections of the two boxes on direction d (> 0: disjoint).
double projection_gap(const PosedSuperquadric& i, const PosedSuperquadric& j, Vec3 d) {
  double min_i = 1e300, max_i = -1e300, min_j = 1e300, max_j = -1e300;
  for (const Vec3& x : box_corners(i))
    min_i = std::min(min_i, dot(d, x)), max_i = std::max(max_i, dot(d, x));
  for (const Vec3& x : box_corners(j))
    min_j = std::min(min_j, dot(d, x)), max_j = std::max(max_j, dot(d, x));
  return std::max(min_j - max_i, min_i - max_j);
}

Vec3 numbered_axis(const PosedSuperquadric& i, const PosedSuperquadric& j, int axis) {
  if (axis < 3)
    return column(i.rotation, axis);
  if (axis < 6)
    return column(j.rotation, axis - 3);
  return cross(column(i.rotation, (axis - 6) / 3), column(j.rotation, (axis - 6) % 3));
}

enum class BoxTruth { overlap, separated, undecided };

// Brute-force reference by alternating projections (von Neumann): between two convex sets they
// converge to a common point when the sets meet, else to a closest pair whose difference is a
// separating direction. Overlap is certified by a point inside both boxes shrunk by 5e-7;
// separation by a direction whose corner projections leave a gap of 1e-9 of the size.
BoxTruth brute_force_boxes(const PosedSuperquadric& i, const PosedSuperquadric& j) {
  const double shrink = 1 - 1e-6;
  Vec3 x = i.centre;
  for (int it = 0; it < 3000; ++it)
    x = project_on_box(i, project_on_box(j, x, shrink), shrink);
  if (inside_box(j, x, 1 - 0.5e-6))
    return BoxTruth::overlap;
  Vec3 p = i.centre;
  for (int it = 0; it < 3000; ++it)
    p = project_on_box(i, project_on_box(j, p, 1), 1);
  const Vec3 d = project_on_box(j, p, 1) - p;
  const double size = superquadric_bounding_radius(i.shape) + superquadric_bounding_radius(j.shape);
  if (norm(d) > 1e-9 * size && projection_gap(i, j, (1 / norm(d)) * d) > 1e-9 * size)
    return BoxTruth::separated;
  return BoxTruth::undecided;
}

// Whether the bodies meet: sampled surface points of one inside the other.
bool surfaces_intersect(const PosedSuperquadric& i, const PosedSuperquadric& j) {
  const int n = 24;
  for (int m = 0; m <= n; ++m)
    for (int q = 0; q < 2 * n; ++q) {
      const double polar = pi * m / n, azimuth = pi * q / n;
      const Vec3 d{std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                   std::cos(polar)};
      if (j.value(i.to_world(radial_surface_point(i.shape, d))) < 0 ||
          i.value(j.to_world(radial_surface_point(j.shape, d))) < 0)
        return true;
    }
  return false;
}

// Pairs at distances that cover overlap, near contact and clear separation. Kind n % 6: 0 generic
// orientations; 1 equal, 2 turned about a shared body axis, 3 a quarter turn about one (axes
// permuted), 4 turned by 1e-8 rad (all with degenerate cross products); 5 generic and farther
// apart than the sum of the box circumradii.
std::vector<BoxCase> random_box_pairs(std::mt19937_64& rng) {
  std::vector<BoxCase> pairs;
  for (int n = 0; n < 1200; ++n) {
    BoxCase c;
    c.i = pose_superquadric(random_shape_independent_axes(rng), {uniform(rng, -3, 3), 0.5, 1},
                            random_rotation(rng));
    const Quat orientation = random_rotation(rng);
    const int kind = n % 6;
    if (kind == 1 || kind == 2 || kind == 3 || kind == 4) {
      // Orientation derived from i's rotation: its columns, possibly turned about one of them.
      const Vec3 axis = column(c.i.rotation, n % 3);
      const double angle =
          kind == 1 ? 0 : (kind == 2 ? uniform(rng, 0, 2 * pi) : (kind == 3 ? 0.5 * pi : 1e-8));
      const Quat turn = quat_from_rotation_vector(angle * axis);
      PosedSuperquadric j;
      j.shape = random_shape_independent_axes(rng);
      j.rotation = rotation_matrix(turn) * c.i.rotation;
      const Vec3 dir = random_unit(rng);
      const double reach = norm(extents(c.i.shape)) + norm(extents(j.shape));
      j.centre = c.i.centre + uniform(rng, 0, 1.1 * reach) * dir;
      c.j = j;
    } else {
      const SuperquadricShape shape = random_shape_independent_axes(rng);
      const double reach = norm(extents(c.i.shape)) + norm(extents(shape));
      const double distance =
          kind == 5 ? uniform(rng, 1.001, 3) * reach : uniform(rng, 0, 1.1) * reach;
      c.j = pose_superquadric(shape, c.i.centre + distance * random_unit(rng), orientation);
    }
    pairs.push_back(c);
  }
  return pairs;
}

TEST(SuperquadricShape, BoundingBoxesOverlapMatchesBruteForce) {
  std::mt19937_64 rng(23);
  const std::vector<BoxCase> pairs = random_box_pairs(rng);
  std::vector<BoxCase> cases;
  for (const BoxCase& pair : pairs)
    for (int hint = -1; hint < obb_axis_count; ++hint)
      cases.push_back({pair.i, pair.j, hint});
  const std::vector<BoxResult> results = run_on_device<BoxResult>(cases, TestBoxes{});

  int overlapping = 0, separated = 0, undecided = 0, intersecting = 0;
  for (std::size_t n = 0; n < pairs.size(); ++n) {
    const PosedSuperquadric& i = pairs[n].i;
    const PosedSuperquadric& j = pairs[n].j;
    const BoxResult& cold = results[n * (obb_axis_count + 1)];
    const double size =
        superquadric_bounding_radius(i.shape) + superquadric_bounding_radius(j.shape);
    SCOPED_TRACE(::testing::Message() << "pair " << n << " kind " << n % 6);
    const BoxTruth truth = brute_force_boxes(i, j);
    if (truth == BoxTruth::overlap) {
      ++overlapping;
      EXPECT_TRUE(cold.overlap);
    } else if (truth == BoxTruth::separated) {
      ++separated;
      EXPECT_FALSE(cold.overlap);
    } else {
      ++undecided;
    }
    if (surfaces_intersect(i, j)) {
      ++intersecting;
      EXPECT_TRUE(cold.overlap) << "the bodies meet";
    }
    if (n % 6 == 5) {
      EXPECT_FALSE(cold.overlap) << "beyond the sum of the box circumradii";
    }
    EXPECT_EQ(cold.overlap, cold.axis == -1);
    for (int hint = -1; hint < obb_axis_count; ++hint) {
      const BoxResult& warm = results[n * (obb_axis_count + 1) + hint + 1];
      EXPECT_EQ(warm.overlap, cold.overlap) << "hint " << hint;
      if (warm.overlap) {
        EXPECT_EQ(warm.axis, -1);
        continue;
      }
      ASSERT_GE(warm.axis, 0);
      ASSERT_LT(warm.axis, obb_axis_count);
      // The reported axis separates the corners (to rounding of 1e-12 of the size).
      const Vec3 L = numbered_axis(i, j, warm.axis);
      EXPECT_GT(projection_gap(i, j, (1 / norm(L)) * L), -1e-12 * size) << "hint " << hint;
      if (hint == cold.axis) {
        EXPECT_EQ(warm.axis, hint) << "a separating hint is kept";
      }
    }
  }
  // The reference decides nearly every pair and each class is well populated.
  EXPECT_LT(undecided, int(pairs.size()) / 50);
  EXPECT_GT(overlapping, 200);
  EXPECT_GT(separated, 200);
  EXPECT_GT(intersecting, 100);
  RecordProperty("overlapping", overlapping);
  RecordProperty("separated", separated);
  RecordProperty("undecided", undecided);
  RecordProperty("intersecting", intersecting);
}

TEST(SuperquadricShape, BoundingBoxesWithParallelAxesAndTouchingFaces) {
  // Long boxes with parallel (rounded to ~1e-16) axes: their cross products are pure rounding and
  // must not separate overlapping pairs; faces touching to rounding count as overlapping, and a
  // gap of 1e-6 of the size separates.
  std::mt19937_64 rng(31);
  const SuperquadricShape long_i = make_superquadric(0.2, 0.3, 5, 4, 3);
  const SuperquadricShape long_j = make_superquadric(0.25, 0.2, 4, 2.5, 6);
  const Quat quarter_turn = quat_from_rotation_vector({0, 0, 0.5 * pi});
  std::vector<BoxCase> cases;
  std::vector<bool> expected;
  for (int n = 0; n < 50; ++n) {
    const Quat qi = random_rotation(rng);
    const PosedSuperquadric i = pose_superquadric(long_i, {uniform(rng, -9, 9), 2, 3}, qi);
    for (const Quat& qj : {qi, qi * quarter_turn}) {
      const PosedSuperquadric placed = pose_superquadric(long_j, {}, qj);
      const Vec3 j_extent_along_i0 = {bounding_box_support(placed, column(i.rotation, 0)), 0, 0};
      const auto add = [&](Vec3 local_offset, bool overlap) {
        cases.push_back({i, pose_superquadric(long_j, i.to_world(local_offset), qj), -1});
        expected.push_back(overlap);
      };
      add({0.1, -0.2, 8.9}, true);  // overlapping by 0.1 along the long axes
      add({0.1, -0.2, 9.1}, false); // 0.1 apart along the long axes
      const double touching = long_i.a + j_extent_along_i0.x;
      add({touching, 0.1, 2}, true);               // faces touching to rounding
      add({touching * (1 + 1e-6), 0.1, 2}, false); // faces 1e-6 apart
      add({touching * (1 - 1e-6), 0.1, -3}, true); // faces 1e-6 deep
    }
  }
  const std::vector<BoxResult> results = run_on_device<BoxResult>(cases, TestBoxes{});
  for (std::size_t n = 0; n < cases.size(); ++n)
    EXPECT_EQ(results[n].overlap, expected[n]) << "case " << n % 10 << " of rotation " << n / 10;
}

struct SupportCase {
  PosedSuperquadric posed;
  Vec3 direction;
};

struct BoxSupport {
  KOKKOS_INLINE_FUNCTION double operator()(const SupportCase& c) const {
    return bounding_box_support(c.posed, c.direction);
  }
};

TEST(SuperquadricShape, BoundingBoxSupportIsTheFarthestCorner) {
  std::mt19937_64 rng(13);
  std::vector<SupportCase> cases;
  for (int n = 0; n < 300; ++n)
    cases.push_back({pose_superquadric(random_shape_independent_axes(rng),
                                       {uniform(rng, -2, 2), 1, 0}, random_rotation(rng)),
                     random_unit(rng)});
  const std::vector<double> support = run_on_device<double>(cases, BoxSupport{});
  for (std::size_t n = 0; n < cases.size(); ++n) {
    const PosedSuperquadric& s = cases[n].posed;
    const Vec3 d = cases[n].direction;
    double corner_reach = -1e300;
    for (const Vec3& x : box_corners(s))
      corner_reach = std::max(corner_reach, dot(d, x - s.centre));
    // Same sum of three products, rounded differently: 1e-14 of the box size.
    EXPECT_NEAR(support[n], corner_reach, 1e-14 * norm(extents(s.shape)));
    double body_reach = -1e300;
    for (int m = 0; m < 2000; ++m) {
      const Vec3 x = s.to_world(radial_surface_point(s.shape, random_unit(rng)));
      body_reach = std::max(body_reach, dot(d, x - s.centre));
    }
    EXPECT_GE(support[n], body_reach - 1e-14); // the body lies in its box
  }
}

} // namespace
} // namespace kdem
