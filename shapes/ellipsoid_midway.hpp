#pragma once
// Midway point of two ellipsoids (superquadrics with n1 = n2 = 2) as the root of one scalar
// function: the reduction of Perram & Wertheim (J. Comput. Phys. 58 (1985) 409) applied to the
// midway-point conditions of superquadric_contact.hpp. Host and device code.
//
// An ellipsoid's shape function is F(x) = (x - c)^T A (x - c) - 1 with A = R diag(a^-2, b^-2,
// c^-2) R^T and gradient 2 A (x - c) (its conditioning factor 0.5^(n - 2) is 1). With mu =
// lambda^2 the condition grad F_i + mu grad F_j = 0 is linear in X; with d = c_j - c_i and
// M = A_i + mu A_j (symmetric positive definite for mu > 0):
//   u_j = X - c_j = -M^-1 A_i d,   u_i = X - c_i = u_j + d,
// and F_i = F_j becomes phi(mu) = u_i^T A_i u_i - u_j^T A_j u_j = 0. Differentiating M u_j =
// -A_i d and using A_i u_i = -mu A_j u_j:
//   phi'(mu) = 2 (1 + mu) z^T M^-1 z > 0,   z = A_j u_j,
// and phi(0) = -d^T A_j d < 0, phi -> d^T A_i d > 0: one root, found by Newton on mu inside a
// bracket. An iteration is one LDL^T of the 3 x 3 M and two solves with it, where the general
// solver factors a 4 x 4 Jacobian and evaluates both shape functions with their Hessians.
#include "small_solve.hpp"
#include "superquadric.hpp"

namespace kdem {
namespace narrow_phase {

KOKKOS_INLINE_FUNCTION bool is_ellipsoid(const SuperquadricShape& s) {
  return s.n1_integer == 2 && s.n2_integer == 2 && s.conditioning == 1.0;
}

struct SymmetricMatrix3 {
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
};

KOKKOS_INLINE_FUNCTION Vec3 times(const SymmetricMatrix3& m, Vec3 v) {
  return {m.xx * v.x + m.xy * v.y + m.xz * v.z, m.xy * v.x + m.yy * v.y + m.yz * v.z,
          m.xz * v.x + m.yz * v.y + m.zz * v.z};
}

// Entry (p, q) of R diag(w) R^T.
KOKKOS_INLINE_FUNCTION double rotated_diagonal_entry(const Mat3& r, Vec3 w, int p, int q) {
  return r.m[p][0] * w.x * r.m[q][0] + r.m[p][1] * w.y * r.m[q][1] + r.m[p][2] * w.z * r.m[q][2];
}

// A = R diag(a^-2, b^-2, c^-2) R^T: the quadratic form of the posed ellipsoid.
KOKKOS_INLINE_FUNCTION SymmetricMatrix3 ellipsoid_form(const PosedSuperquadric& body) {
  const Mat3& r = body.rotation;
  const SuperquadricShape& s = body.shape;
  const Vec3 w{s.inv_a * s.inv_a, s.inv_b * s.inv_b, s.inv_c * s.inv_c};
  return {rotated_diagonal_entry(r, w, 0, 0), rotated_diagonal_entry(r, w, 1, 1),
          rotated_diagonal_entry(r, w, 2, 2), rotated_diagonal_entry(r, w, 0, 1),
          rotated_diagonal_entry(r, w, 0, 2), rotated_diagonal_entry(r, w, 1, 2)};
}

// L D L^T of a symmetric positive definite 3 x 3 matrix (no pivoting, no roots).
struct SymmetricFactor {
  double d0 = 0, d1 = 0, d2 = 0;
  double l10 = 0, l20 = 0, l21 = 0;

  // False where a pivot is not positive (not positive definite to rounding).
  KOKKOS_INLINE_FUNCTION bool factor(const SymmetricMatrix3& m) {
    d0 = m.xx;
    if (!(d0 > 0))
      return false;
    l10 = m.xy / d0;
    l20 = m.xz / d0;
    d1 = m.yy - l10 * m.xy;
    if (!(d1 > 0))
      return false;
    l21 = (m.yz - l20 * m.xy) / d1;
    d2 = m.zz - l20 * m.xz - l21 * l21 * d1;
    return d2 > 0;
  }

  KOKKOS_INLINE_FUNCTION Vec3 solve(Vec3 b) const {
    const double y1 = b.y - l10 * b.x;
    const double y2 = b.z - l20 * b.x - l21 * y1;
    const double x2 = y2 / d2;
    const double x1 = y1 / d1 - l21 * x2;
    const double x0 = b.x / d0 - l10 * x1 - l20 * x2;
    return {x0, x1, x2};
  }
};

// mu of two spheres of the equivalent radii: lambda^2 = |grad F_i| / |grad F_j| = r_j / r_i at
// their midway point; the start where no warm start is known.
KOKKOS_INLINE_FUNCTION double ellipsoid_cold_start(const PosedSuperquadric& i,
                                                   const PosedSuperquadric& j) {
  return j.equivalent_radius() / i.equivalent_radius();
}

constexpr double ellipsoid_step_factor = 8; // a Newton step changes mu by at most this factor

// The next mu: Newton's (rising where phi < 0), kept within a factor of the current one and
// inside the bracket (lo, hi) known so far (hi = 0: none above), one end of which is the current
// mu; the bracket's geometric midpoint where Newton leaves it.
KOKKOS_INLINE_FUNCTION double next_multiplier(double mu, double phi, double slope, double lo,
                                              double hi) {
  const double newton = mu - phi / slope;
  double next = slope > 0 && kdem::is_finite(newton)
                    ? newton
                    : (phi < 0 ? ellipsoid_step_factor * mu : mu / ellipsoid_step_factor);
  next = math::clamp(next, mu / ellipsoid_step_factor, mu * ellipsoid_step_factor);
  const bool above_known = hi > 0;
  if (next > lo && (!above_known || next < hi))
    return next;
  if (!(lo > 0))
    return mu / ellipsoid_step_factor;
  if (!above_known)
    return mu * ellipsoid_step_factor;
  return math::sqrt(lo * hi);
}

struct EllipsoidMidway {
  Vec3 point;            // X, m
  double multiplier = 0; // lambda = sqrt(mu)
  ShapeFunction fi, fj;  // F of each body at X, world gradients, body-frame Hessians
};

// F at a point u from the centre, with world gradient 2 A u (given as A u) and the body-frame
// Hessian 2 diag(a^-2, b^-2, c^-2), as superquadric_local gives them for n1 = n2 = 2.
KOKKOS_INLINE_FUNCTION ShapeFunction ellipsoid_function(const SuperquadricShape& s, Vec3 u,
                                                        Vec3 a_u) {
  ShapeFunction f;
  f.value = dot(u, a_u) - 1.0;
  f.gradient = 2.0 * a_u;
  f.hessian.m[0][0] = 2.0 * s.inv_a * s.inv_a;
  f.hessian.m[1][1] = 2.0 * s.inv_b * s.inv_b;
  f.hessian.m[2][2] = 2.0 * s.inv_c * s.inv_c;
  return f;
}

// The start of Newton: from a warm start (`start` with `start_multiplier` > 0: the midway point
// expected at this step), the mu for which that point is stationary along the gradients,
// |grad F_i| / |grad F_j| there (grad F_i = -mu grad F_j at the root), which is as close to the
// root as the point is; else the stored multiplier squared; else two spheres' mu.
KOKKOS_INLINE_FUNCTION double
ellipsoid_start(const PosedSuperquadric& i, const PosedSuperquadric& j, const SymmetricMatrix3& a_i,
                const SymmetricMatrix3& a_j, Vec3 start, double start_multiplier) {
  if (!(start_multiplier > 0))
    return ellipsoid_cold_start(i, j);
  const double along_i = norm(times(a_i, start - i.centre)),
               along_j = norm(times(a_j, start - j.centre));
  const double mu = along_i / along_j;
  if (mu > 0 && kdem::is_finite(mu))
    return mu;
  return start_multiplier * start_multiplier;
}

// Solves phi(mu) = 0 from the start of ellipsoid_start until the gap between the level sets
// through X, |F_i - F_j| / (|grad F_i| + |grad F_j|), is at most gap_tolerance (in m); gives X
// and lambda = sqrt(mu), the unknowns of the general midway problem, and counts Newton steps.
// False when a factorisation or value is not finite or max_iterations do not reach the tolerance.
KOKKOS_INLINE_FUNCTION bool ellipsoid_midway(const PosedSuperquadric& i, const PosedSuperquadric& j,
                                             Vec3 start, double start_multiplier,
                                             double gap_tolerance, int max_iterations,
                                             EllipsoidMidway& found, int& iterations) {
  const SymmetricMatrix3 a_i = ellipsoid_form(i), a_j = ellipsoid_form(j);
  const Vec3 d = j.centre - i.centre;
  const Vec3 a_i_d = times(a_i, d);
  double mu = ellipsoid_start(i, j, a_i, a_j, start, start_multiplier);
  double lo = 0, hi = 0; // bracket of the root; hi = 0: none known above
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
    const SymmetricMatrix3 m{a_i.xx + mu * a_j.xx, a_i.yy + mu * a_j.yy, a_i.zz + mu * a_j.zz,
                             a_i.xy + mu * a_j.xy, a_i.xz + mu * a_j.xz, a_i.yz + mu * a_j.yz};
    SymmetricFactor factor;
    if (!factor.factor(m))
      return false;
    const Vec3 u_j = -factor.solve(a_i_d), u_i = u_j + d;
    const Vec3 a_i_u_i = times(a_i, u_i), z = times(a_j, u_j);
    const double phi = dot(u_i, a_i_u_i) - dot(u_j, z);
    // |grad F_i| + |grad F_j| >= (|grad F_i|^2 + |grad F_j|^2)^(1/2): a test without roots that
    // is at least as strict as the gap's.
    const double gradients2 = 4.0 * (norm2(a_i_u_i) + norm2(z));
    if (!(kdem::is_finite(phi) && gradients2 > 0 && kdem::is_finite(gradients2)))
      return false;
    if (phi * phi <= gap_tolerance * gap_tolerance * gradients2) {
      found.point = i.centre + u_i;
      found.multiplier = math::sqrt(mu);
      found.fi = ellipsoid_function(i.shape, u_i, a_i_u_i);
      found.fj = ellipsoid_function(j.shape, u_j, z);
      return true;
    }
    if (iteration == max_iterations)
      return false;
    ++iterations;
    if (phi < 0)
      lo = mu;
    else
      hi = mu;
    const double slope = 2.0 * (1.0 + mu) * dot(z, factor.solve(z));
    mu = next_multiplier(mu, phi, slope, lo, hi);
  }
  return false;
}

} // namespace narrow_phase
} // namespace kdem
