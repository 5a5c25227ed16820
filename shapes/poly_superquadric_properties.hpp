#pragma once
// Properties of a poly-superquadric shape template (volume, centroid, full inertia tensor and its
// principal frame, bounding sphere), computed once per template on the host. The book (Sect.
// 3.2.2) sums a background grid; the eight octant pieces have closed-form moments instead (Zhao &
// Zhao, IJNAMG 43 (2019) 2147; digest ch3 Sect. 2.3), exact and cheap.
#include <algorithm>
#include <cmath>

#include "poly_superquadric.hpp"
#include "superquadric_properties.hpp"
#include "symmetric_eigen.hpp"

namespace kdem {

// J(p, q, r) = integral of u^p v^q w^r over the unit octant piece u, v, w >= 0,
// (u^n2 + v^n2)^(n1/n2) + w^n1 <= 1:
//   J = B((p+1)/n2, (q+1)/n2) B((r+1)/n1, (p+q+2)/n1 + 1) / (n1 n2 (p+q+2)).
// Derivation (the Beta-function integrals of Jaklic, Leonardis & Solina 2000, Ch. 2): over the
// power disc u^n2 + v^n2 <= R^n2, s = u^n2, t = v^n2 give the Dirichlet integral
// R^(p+q+2) B((p+1)/n2, (q+1)/n2) / (n2 (p+q+2)); the disc of height w has R = (1 - w^n1)^(1/n1),
// and s = w^n1 turns the remaining integral of w^r R^(p+q+2) into B((r+1)/n1, (p+q+2)/n1 + 1) / n1.
// (The digest's formula is right: n1 = n2 = 2 gives J000 = pi/6, J100 = pi/16, J200 = pi/30,
// J110 = 1/15.)
inline double octant_moment(double p, double q, double r, double n1, double n2) {
  const double in_section = p + q + 2.0;
  return beta_function((p + 1.0) / n2, (q + 1.0) / n2) *
         beta_function((r + 1.0) / n1, in_section / n1 + 1.0) / (n1 * n2 * in_section);
}

struct PolySuperquadricMassProperties {
  double volume = 0;                  // m^3
  Vec3 centroid;                      // m, from O0, octant frame
  Mat3 inertia_per_density;           // m^5, about the centroid, octant frame, full tensor
  Vec3 principal_inertia_per_density; // m^5, ascending
  Mat3 principal_axes;                // columns: principal axes in the octant frame, det +1
};

// The piece in octant (sx, sy, sz) with semi-axes (a, b, c) has
//   integral of x^p y^q z^r = sx^p sy^q sz^r a^(p+1) b^(q+1) c^(r+1) J(p, q, r),
// so the sum over the eight pieces factorises per axis into
//   S0 = r+ + r-,  S1 = r+^2 - r-^2,  S2 = r+^3 + r-^3
// (digest Sect. 2.3). The products of inertia do not vanish when two axes are asymmetric
// (integral of xy is proportional to Sx1 Sy1), so the full tensor is kept and its principal frame
// returned: the principal axes may be tilted from the octant frame (by ~16 degrees for a pebble).
inline PolySuperquadricMassProperties
poly_superquadric_mass_properties(const PolySuperquadricShape& s) {
  const double n1 = s.exponents.n1, n2 = s.exponents.n2;
  const auto sums = [](double plus, double minus) {
    return Vec3{plus + minus, plus * plus - minus * minus,
                plus * plus * plus + minus * minus * minus};
  };
  const Vec3 sx = sums(s.plus.x, s.minus.x), sy = sums(s.plus.y, s.minus.y),
             sz = sums(s.plus.z, s.minus.z);
  // Moments of the body about O0: the exponents of x, y, z pick S0, S1 or S2 of each axis.
  const auto moment = [&](int p, int q, int r) {
    return octant_moment(p, q, r, n1, n2) * sx[p] * sy[q] * sz[r];
  };

  PolySuperquadricMassProperties props;
  props.volume = moment(0, 0, 0);
  props.centroid = (1.0 / props.volume) * Vec3{moment(1, 0, 0), moment(0, 1, 0), moment(0, 0, 1)};
  // Second moments about the centroid: M = [integral of x_i x_j] - V xbar xbar^T.
  Mat3 second;
  second.m[0][0] = moment(2, 0, 0), second.m[1][1] = moment(0, 2, 0);
  second.m[2][2] = moment(0, 0, 2);
  second.m[0][1] = second.m[1][0] = moment(1, 1, 0);
  second.m[0][2] = second.m[2][0] = moment(1, 0, 1);
  second.m[1][2] = second.m[2][1] = moment(0, 1, 1);
  const Vec3 c = props.centroid;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) // mirrored, so that the tensor is symmetric to the bit
      second.m[i][j] = second.m[j][i] = second.m[i][j] - props.volume * c[i] * c[j];
  // I = tr(M) 1 - M (I_xx = integral of y^2 + z^2, I_xy = -integral of x y).
  props.inertia_per_density = trace(second) * identity3() + (-1.0) * second;
  const SymmetricEigen principal = symmetric_eigen(props.inertia_per_density);
  props.principal_inertia_per_density = principal.values;
  props.principal_axes = principal.vectors;
  return props;
}

// Grid of sample directions per cube-face side in poly_superquadric_bounding_radius: the covering
// chord is d = sqrt(2) / n = 0.022, so the bound is at most d^2 / 2 = 2.4e-4 above the true radius,
// from 6 (n + 1)^2 = 25350 support points (about 2 ms).
constexpr int poly_superquadric_radius_directions = 64;

// A conservative radius of the sphere about `about` (octant frame, e.g. the centroid) that holds
// the body, tight to ~2.4e-4 relative. No closed form exists once the centre is off O0 (digest
// Sect. 2.5: the rim of a hemisphere sits at sqrt(c0^2 + r0^2) from its centroid).
//
// Bound: with h(u) the support function, f(u) = h(u) - u . c = max over the body of u . (X - c)
// and R = max |X - c|, attained at X*. For u* = (X* - c) / R and any unit sample u_s,
//   f(u_s) >= u_s . (X* - c) = R u_s . u* = R (1 - |u_s - u*|^2 / 2),
// so R <= max_s f(u_s) / (1 - d^2 / 2) when every unit vector is within chord d of a sample. This
// is second order in d (the first-order Lipschitz bound R <= max f / (1 - d) also holds, but needs
// a 100x denser grid for the same tightness).
// Samples: u = p / |p| for p on the grid of spacing h = 2 / n on each face of the cube [-1, 1]^3.
// The point p* = u* / max|u*_k| lies on a face, within h / sqrt(2) of a grid node there, and the
// radial projection p -> p / |p| of points outside the unit ball is the nearest-point projection
// onto the ball, which is 1-Lipschitz: d = h / sqrt(2) = sqrt(2) / n.
// The support points are exact (poly_superquadric_support_point, to rounding), and the result is
// inflated by (1 + 1e-9) like superquadric_bounding_radius.
inline double poly_superquadric_bounding_radius(const PolySuperquadricShape& s, Vec3 about) {
  const int n = poly_superquadric_radius_directions;
  double largest = 0;
  for (int face = 0; face < 6; ++face) {
    const int axis = face % 3;
    const double side = face < 3 ? 1.0 : -1.0;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const double first = -1.0 + 2.0 * i / n, second = -1.0 + 2.0 * j / n;
        const Vec3 p = axis == 0   ? Vec3{side, first, second}
                       : axis == 1 ? Vec3{second, side, first}
                                   : Vec3{first, second, side};
        const Vec3 u = (1.0 / norm(p)) * p;
        largest = std::max(largest, dot(u, poly_superquadric_support_point(s, u) - about));
      }
  }
  const double chord = std::sqrt(2.0) / n;
  return largest / (1.0 - 0.5 * chord * chord) * (1.0 + bounding_radius_safety);
}

} // namespace kdem
