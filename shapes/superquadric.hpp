#pragma once
// Superquadric shape function (Barr 1981; book Eq. 2.1) with its gradient and Hessian, in the
// body frame (principal axes, centroid at the origin) and posed in the world frame:
//   F(x, y, z) = (|x/a|^n2 + |y/b|^n2)^(n1/n2) + |z/c|^n1 - 1,   F < 0 inside.
// n2 shapes the xy cross-section, n1 the profile along z; n1, n2 >= 2 (below 2 the Hessian is
// singular on the surface). Everything here is host and device code.
//
// Conditioning: F and its derivatives are multiplied by 0.5^(max(n1, n2) - 2), as LIGGGHTS does
// (Podlozhnyuk et al., Comput. Part. Mech. 4 (2017) 101). The zero set is unchanged; the factor
// keeps |F| of order one a few semi-axes away from blocky shapes, where |x/a|^n is large.
// Integer exponents (the common n = 2, 4, 8, ...) use repeated multiplication instead of pow.
#include "implicit_surface.hpp"
#include "mat3.hpp"

namespace kdem {

struct SuperquadricShape {
  double a = 1, b = 1, c = 1; // m, semi-axes along body x, y, z
  double n1 = 2, n2 = 2;      // blockiness: n1 along z, n2 in the xy cross-section
  // Derived by make_superquadric; do not set by hand.
  double inv_a = 1, inv_b = 1, inv_c = 1;
  double exponent_ratio = 1; // p = n1 / n2
  double conditioning = 1;   // 0.5^(max(n1, n2) - 2)
  int n1_integer = 2;        // n1 when it is an integer, else -1
  int n2_integer = 2;
  int ratio_minus_two_integer = -1; // p - 2 when it is a non-negative integer, else -1
  bool equal_exponents = true;      // n1 == n2: F separates into three powers
};

KOKKOS_INLINE_FUNCTION int integer_or_minus_one(double n) {
  const double rounded = math::floor(n + 0.5);
  return (n == rounded && rounded >= 0 && rounded < 64) ? int(rounded) : -1;
}

KOKKOS_INLINE_FUNCTION SuperquadricShape make_superquadric(double a, double b, double c, double n1,
                                                           double n2) {
  SuperquadricShape s;
  s.a = a, s.b = b, s.c = c, s.n1 = n1, s.n2 = n2;
  s.inv_a = 1.0 / a, s.inv_b = 1.0 / b, s.inv_c = 1.0 / c;
  s.exponent_ratio = n1 / n2;
  s.conditioning = math::pow(0.5, math::max(n1, n2) - 2.0);
  s.n1_integer = integer_or_minus_one(n1);
  s.n2_integer = integer_or_minus_one(n2);
  s.ratio_minus_two_integer = integer_or_minus_one(s.exponent_ratio - 2.0);
  s.equal_exponents = n1 == n2;
  return s;
}

// t^k for t >= 0 and a small non-negative integer k: the powers of the common blockiness values
// (n - 2 for n = 2, 3, 4, 6, 8, 10) written out, the others by squaring. T: double, or the
// lanes of shapes/lanes.hpp (T{} + 1.0 is one in every lane).
template <class T> KOKKOS_INLINE_FUNCTION T integer_power(T t, int k) {
  switch (k) {
  case 0:
    return T{} + 1.0;
  case 1:
    return t;
  case 2:
    return t * t;
  case 4: {
    const T t2 = t * t;
    return t2 * t2;
  }
  case 6: {
    const T t2 = t * t;
    return t2 * t2 * t2;
  }
  case 8: {
    const T t2 = t * t, t4 = t2 * t2;
    return t4 * t4;
  }
  default:
    break;
  }
  T result = T{} + 1.0;
  while (k > 0) {
    if (k & 1)
      result *= t;
    t *= t;
    k >>= 1;
  }
  return result;
}

// t^(n - 2) for t >= 0 and n >= 2; n_integer is n or -1 (see SuperquadricShape).
KOKKOS_INLINE_FUNCTION double power_minus_two(double t, double n, int n_integer) {
  if (n_integer >= 2)
    return integer_power(t, n_integer - 2);
  return t > 0 ? math::pow(t, n - 2.0) : 0.0;
}

KOKKOS_INLINE_FUNCTION double sign_of(double x) {
  return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
}

// Below this, S = |x/a|^n2 + |y/b|^n2 counts as zero (the body's z axis): the terms with negative
// powers of S are multiplied by powers of |x/a|, |y/b| that vanish faster, and their limit is 0.
constexpr double superquadric_axis_threshold = 1e-100;

template <bool WithHessian = true>
KOKKOS_INLINE_FUNCTION ShapeFunction superquadric_local(const SuperquadricShape& s, Vec3 p) {
  // x / a and |x / a| (likewise y, z): the odd powers take their sign from the signed ones.
  const double xa = p.x * s.inv_a, yb = p.y * s.inv_b, zc = p.z * s.inv_c;
  const double u = math::fabs(xa), v = math::fabs(yb), w = math::fabs(zc);
  const double n1 = s.n1, n2 = s.n2, k = s.conditioning;

  const double u_m2 = power_minus_two(u, n2, s.n2_integer),
               v_m2 = power_minus_two(v, n2, s.n2_integer);
  const double u_m1 = u_m2 * xa, v_m1 = v_m2 * yb; // sign(x) |x / a|^(n2 - 1), likewise y
  const double w_m2 = power_minus_two(w, n1, s.n1_integer), w_m1 = w_m2 * zc;
  const double section = u_m1 * xa + v_m1 * yb; // S

  ShapeFunction f;
  // S^(p-1) and S^(p-2) (the latter only where it is multiplied by (n1 - n2) != 0).
  double s_p1 = 1, s_p2 = 0;
  if (!s.equal_exponents) {
    if (section > superquadric_axis_threshold) {
      s_p2 = s.ratio_minus_two_integer >= 0 ? integer_power(section, s.ratio_minus_two_integer)
                                            : math::pow(section, s.exponent_ratio - 2.0);
      s_p1 = s_p2 * section;
    } else {
      s_p1 = 0; // p > 1 or the limit along the axis; see superquadric_axis_threshold
    }
  }
  const double section_term = s.equal_exponents ? section : s_p1 * section;
  f.value = k * (section_term + w_m1 * zc - 1.0);
  f.gradient =
      Vec3{k * n1 * s.inv_a * s_p1 * u_m1, k * n1 * s.inv_b * s_p1 * v_m1, k * n1 * s.inv_c * w_m1};
  if constexpr (WithHessian) {
    const double cross = (n1 - n2) * s_p2;
    f.hessian.m[0][0] = k * n1 * s.inv_a * s.inv_a * ((n2 - 1) * u_m2 * s_p1 + cross * u_m1 * u_m1);
    f.hessian.m[1][1] = k * n1 * s.inv_b * s.inv_b * ((n2 - 1) * v_m2 * s_p1 + cross * v_m1 * v_m1);
    f.hessian.m[0][1] = f.hessian.m[1][0] = k * n1 * s.inv_a * s.inv_b * cross * u_m1 * v_m1;
    f.hessian.m[2][2] = k * n1 * (n1 - 1) * s.inv_c * s.inv_c * w_m2;
  }
  return f;
}

// --- Support point ------------------------------------------------------------------------------

// The point (p, q) >= 0 of the power circle p^n + q^n = 1 that maximises A p + B q, A, B >= 0,
// and that maximum (A^m + B^m)^(1/m), m = n / (n - 1) (Hoelder's equality case):
//   p = (A / reach)^(1 / (n - 1)),  q = (B / reach)^(1 / (n - 1)).
// With the weights scaled so that the larger is 1 (r_a, r_b), P_a = r_a^(1 / (n - 1)) and
// S = r_a P_a + r_b P_b = r_a^m + r_b^m, this is p = P_a S^(-1/n), q = P_b S^(-1/n) and
// reach = largest S S^(-1/n): two pow calls (one P is 1) where the formula above takes five, and
// none along an axis (S = 1).
struct PowerCircleSupport {
  double first = 0, second = 0;
  double reach = 0;
};

// r^(1 / (n - 1)) for 0 <= r <= 1; r = 1 (the larger weight) and r = 0 are exact.
KOKKOS_INLINE_FUNCTION double power_circle_root(double r, double inverse_n_minus_one) {
  if (r == 1.0 || r == 0.0)
    return r;
  return math::pow(r, inverse_n_minus_one);
}

KOKKOS_INLINE_FUNCTION PowerCircleSupport power_circle_support(double a_weight, double b_weight,
                                                               double n) {
  PowerCircleSupport support;
  const double largest = math::max(a_weight, b_weight);
  if (!(largest > 0))
    return support;
  const double ra = a_weight / largest, rb = b_weight / largest; // the larger is 1: no overflow
  if (n == 2.0) {
    const double length = math::sqrt(ra * ra + rb * rb);
    support.first = ra / length;
    support.second = rb / length;
    support.reach = largest * length;
    return support;
  }
  const double exponent = 1.0 / (n - 1.0);
  const double pa = power_circle_root(ra, exponent), pb = power_circle_root(rb, exponent);
  const double sum = ra * pa + rb * pb; // in [1, 2]
  const double shrink = sum == 1.0 ? 1.0 : math::pow(sum, -1.0 / n);
  support.first = pa * shrink;
  support.second = pb * shrink;
  support.reach = largest * sum * shrink;
  return support;
}

// The body-frame surface point whose outward normal is parallel to `direction` (any length),
// i.e. the point maximising direction . x over the particle (book Eqs. 2.11, 2.12; Podlozhnyuk et
// al. 2017). Written as two nested 2-D problems: with r = (|x/a|^n2 + |y/b|^n2)^(1/n2) the surface
// is r^n1 + |z/c|^n1 = 1, so the xy power circle is solved for (a|nx|, b|ny|) and its reach, with
// c|nz|, gives the profile. This is Eq. 2.11 with the roles of x and y symmetric: nx = 0
// (Eq. 2.12), |nx| < |ny| and directions along the axes need no separate branch. A zero direction
// gives the centre.
KOKKOS_INLINE_FUNCTION Vec3 superquadric_support_point(const SuperquadricShape& s, Vec3 direction) {
  const PowerCircleSupport section =
      power_circle_support(s.a * math::fabs(direction.x), s.b * math::fabs(direction.y), s.n2);
  const PowerCircleSupport profile =
      power_circle_support(section.reach, s.c * math::fabs(direction.z), s.n1);
  const double radial = profile.first;
  return {sign_of(direction.x) * s.a * radial * section.first,
          sign_of(direction.y) * s.b * radial * section.second,
          sign_of(direction.z) * s.c * profile.second};
}

// A superquadric placed in the world: centre and body-to-world rotation.
struct PosedSuperquadric {
  SuperquadricShape shape;
  Vec3 centre;
  Mat3 rotation; // columns are the body axes in world coordinates

  KOKKOS_INLINE_FUNCTION Vec3 to_local(Vec3 x) const {
    return transpose_times(rotation, x - centre);
  }
  KOKKOS_INLINE_FUNCTION Vec3 to_world(Vec3 local) const { return centre + rotation * local; }
  // The surface concept of the narrow-phase numerics (shapes/implicit_surface.hpp).
  template <bool WithHessian> KOKKOS_INLINE_FUNCTION ShapeFunction local(Vec3 x_local) const {
    return superquadric_local<WithHessian>(shape, x_local);
  }
  KOKKOS_INLINE_FUNCTION double smallest_length() const {
    return math::min(shape.a, math::min(shape.b, shape.c));
  }
  KOKKOS_INLINE_FUNCTION double reach() const {
    return math::sqrt(shape.a * shape.a + shape.b * shape.b + shape.c * shape.c);
  }
  KOKKOS_INLINE_FUNCTION double equivalent_radius() const {
    return math::cbrt(shape.a * shape.b * shape.c);
  }
  KOKKOS_INLINE_FUNCTION Vec3 support_local(Vec3 direction_local) const {
    return superquadric_support_point(shape, direction_local);
  }
  KOKKOS_INLINE_FUNCTION BodyBox local_box() const {
    return BodyBox{Vec3{-shape.a, -shape.b, -shape.c}, Vec3{shape.a, shape.b, shape.c}};
  }
  KOKKOS_INLINE_FUNCTION double value(Vec3 x) const {
    return superquadric_local<false>(shape, to_local(x)).value;
  }
  // Value, world gradient and (optionally) world Hessian R H R^T.
  template <bool WithHessian = true> KOKKOS_INLINE_FUNCTION ShapeFunction evaluate(Vec3 x) const {
    ShapeFunction world = evaluate_with_body_hessian<WithHessian>(x);
    if constexpr (WithHessian)
      world.hessian = world_hessian(world.hessian);
    return world;
  }
  // Value and world gradient, with the Hessian left in the body frame: solvers that may not need
  // it (a converged Newton iterate) turn it with world_hessian only when they do.
  template <bool WithHessian = true>
  KOKKOS_INLINE_FUNCTION ShapeFunction evaluate_with_body_hessian(Vec3 x) const {
    ShapeFunction f = superquadric_local<WithHessian>(shape, to_local(x));
    f.gradient = rotation * f.gradient;
    return f;
  }
  // R H R^T for a body-frame Hessian of superquadric_local, whose (x, z) and (y, z) entries are
  // zero: six entries of three products each instead of two full matrix products.
  KOKKOS_INLINE_FUNCTION Mat3 world_hessian(const Mat3& body) const {
    const Mat3& r = rotation;
    const double hxx = body.m[0][0], hyy = body.m[1][1], hzz = body.m[2][2], hxy = body.m[0][1];
    double tx[3], ty[3], tz[3]; // rows of H R^T: tx[b] = sum_k H(0, k) R(b, k), and so on
    for (int b = 0; b < 3; ++b) {
      tx[b] = hxx * r.m[b][0] + hxy * r.m[b][1];
      ty[b] = hxy * r.m[b][0] + hyy * r.m[b][1];
      tz[b] = hzz * r.m[b][2];
    }
    Mat3 world;
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b)
        world.m[a][b] = world.m[b][a] = r.m[a][0] * tx[b] + r.m[a][1] * ty[b] + r.m[a][2] * tz[b];
    return world;
  }
};

KOKKOS_INLINE_FUNCTION PosedSuperquadric pose_superquadric(const SuperquadricShape& shape,
                                                           Vec3 centre, Quat orientation) {
  return PosedSuperquadric{shape, centre, rotation_matrix(orientation)};
}

} // namespace kdem
