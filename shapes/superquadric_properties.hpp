#pragma once
// Properties of a superquadric shape template (volume, principal inertia, bounding sphere),
// computed once per template on the host, and the oriented-bounding-box pre-filter of the broad
// phase (book Sect. 2.2.1), which is host and device code.
#include <algorithm>
#include <cmath>

#include "superquadric.hpp"

namespace kdem {

// B(p, q) = Gamma(p) Gamma(q) / Gamma(p + q), through log-gamma so that no Gamma overflows.
inline double beta_function(double p, double q) {
  return std::exp(std::lgamma(p) + std::lgamma(q) - std::lgamma(p + q));
}

// Closed forms of Jaklic, Leonardis & Solina, "Segmentation and Recovery of Superquadrics" (2000),
// Ch. 2, with eps1 = 2 / n1 (profile along z) and eps2 = 2 / n2 (xy cross-section); book Eq. 2.3.
inline double superquadric_volume(const SuperquadricShape& s) {
  const double e1 = 2.0 / s.n1, e2 = 2.0 / s.n2;
  return 2.0 * s.a * s.b * s.c * e1 * e2 * beta_function(0.5 * e1 + 1.0, e1) *
         beta_function(0.5 * e2, 0.5 * e2);
}

// Second moments of the body's volume, (integral of x^2, y^2, z^2 dV) in m^5; same source.
inline Vec3 superquadric_second_moments(const SuperquadricShape& s) {
  const double e1 = 2.0 / s.n1, e2 = 2.0 / s.n2;
  const double common = 0.5 * s.a * s.b * s.c * e1 * e2;
  const double in_section =
      common * beta_function(1.5 * e2, 0.5 * e2) * beta_function(0.5 * e1, 2.0 * e1 + 1.0);
  const double along_axis =
      common * 4.0 * beta_function(0.5 * e2, 0.5 * e2 + 1.0) * beta_function(1.5 * e1, e1 + 1.0);
  return {s.a * s.a * in_section, s.b * s.b * in_section, s.c * s.c * along_axis};
}

// Principal moments of inertia (kg m^2) about the body x, y, z axes; book Eqs. 2.4-2.6.
inline Vec3 superquadric_principal_inertia(const SuperquadricShape& s, double density) {
  const Vec3 m = superquadric_second_moments(s);
  return density * Vec3{m.y + m.z, m.x + m.z, m.x + m.y};
}

// max over t in [0, 1] of A t^e + B (1 - t)^e with A, B >= 0 and e = 2 / n, n >= 2. For e < 1 the
// function is concave in t and its stationary point gives (A^k + B^k)^(1/k), k = n / (n - 2); for
// n = 2 it is linear and the maximum is max(A, B), the limit k -> infinity.
inline double largest_power_combination(double A, double B, double n) {
  const double larger = std::max(A, B), smaller = std::min(A, B);
  if (n <= 2.0 || smaller <= 0.0)
    return larger;
  const double k = n / (n - 2.0);
  return larger * std::pow(1.0 + std::pow(smaller / larger, k), 1.0 / k);
}

// Relative inflation of the bounding radius: covers the rounding of the closed form (~1e-15) with a
// wide margin and costs nothing in the neighbour search.
constexpr double bounding_radius_safety = 1e-9;

// Exact bounding-sphere radius max |X| over the surface. With the surface in angles (eta, omega),
//   X = (a cos^e1(eta) cos^e2(omega), b cos^e1(eta) sin^e2(omega), c sin^e1(eta)),  e = 2 / n,
// |X|^2 = cos^(2 e1)(eta) (a^2 cos^(2 e2)(omega) + b^2 sin^(2 e2)(omega)) + c^2 sin^(2 e1)(eta).
// The maximum over omega does not depend on eta, and both maxima have the form of
// largest_power_combination with t = cos^2.
inline double superquadric_bounding_radius(const SuperquadricShape& s) {
  const double in_section = largest_power_combination(s.a * s.a, s.b * s.b, s.n2);
  const double squared = largest_power_combination(in_section, s.c * s.c, s.n1);
  return std::sqrt(squared) * (1.0 + bounding_radius_safety);
}

// Oriented bounding boxes: half-extents (a, b, c) along the body axes, the columns of
// PosedSuperquadric::rotation. The separating-axis test (Eberly 2002; Gottschalk et al. 1996)
// numbers its 15 axes as: 0-2 the body axes A_k of i, 3-5 the body axes B_l of j, and
// 6 + 3 k + l the cross product A_k x B_l.
constexpr int obb_axis_count = 15;

// Cross products with |A_k x B_l|^2 below this (axes within 1e-6 rad of parallel) are not tested:
// rounding makes their direction meaningless, and the face axes decide parallel pairs.
constexpr double obb_min_cross_length2 = 1e-12;

// Absolute tolerance of every comparison, relative to the pair's size: an axis separates only when
// the gap exceeds it, so rounding can report a touching pair as overlapping but never the reverse.
constexpr double obb_relative_margin = 1e-12;

// Pair geometry in the frame of box i: rotation[k][l] = A_k . B_l, offset = centre_j - centre_i.
struct ObbPair {
  double rotation[3][3];
  double abs_rotation[3][3];
  double offset[3];
  double extent_i[3], extent_j[3];
  double margin;
};

KOKKOS_INLINE_FUNCTION ObbPair make_obb_pair(const PosedSuperquadric& i,
                                             const PosedSuperquadric& j) {
  ObbPair p;
  const Vec3 d = j.centre - i.centre;
  for (int k = 0; k < 3; ++k) {
    const Vec3 axis_i = column(i.rotation, k);
    p.offset[k] = dot(axis_i, d);
    for (int l = 0; l < 3; ++l) {
      p.rotation[k][l] = dot(axis_i, column(j.rotation, l));
      p.abs_rotation[k][l] = math::fabs(p.rotation[k][l]);
    }
  }
  p.extent_i[0] = i.shape.a, p.extent_i[1] = i.shape.b, p.extent_i[2] = i.shape.c;
  p.extent_j[0] = j.shape.a, p.extent_j[1] = j.shape.b, p.extent_j[2] = j.shape.c;
  const double size =
      norm(d) + i.shape.a + i.shape.b + i.shape.c + j.shape.a + j.shape.b + j.shape.c;
  p.margin = obb_relative_margin * size;
  return p;
}

// Whether the projections of the two boxes on one numbered axis are disjoint.
KOKKOS_INLINE_FUNCTION bool obb_separated_along(const ObbPair& p, int axis) {
  const double(*r)[3] = p.rotation;
  const double(*abs_r)[3] = p.abs_rotation;
  const double* t = p.offset;
  const double* ei = p.extent_i;
  const double* ej = p.extent_j;
  double distance, reach;
  if (axis < 3) {
    const int k = axis;
    distance = math::fabs(t[k]);
    reach = ei[k] + ej[0] * abs_r[k][0] + ej[1] * abs_r[k][1] + ej[2] * abs_r[k][2];
  } else if (axis < 6) {
    const int l = axis - 3;
    distance = math::fabs(t[0] * r[0][l] + t[1] * r[1][l] + t[2] * r[2][l]);
    reach = ei[0] * abs_r[0][l] + ei[1] * abs_r[1][l] + ei[2] * abs_r[2][l] + ej[l];
  } else {
    // L = A_k x B_l = r[k1][l] A_k2 - r[k2][l] A_k1 for the cyclic order (k, k1, k2); the
    // projections of B_l1 and B_l2 on L are A_k . (B_l x B_l1) = A_k . B_l2 and the like.
    const int k = (axis - 6) / 3, l = (axis - 6) % 3;
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3, l1 = (l + 1) % 3, l2 = (l + 2) % 3;
    if (r[k1][l] * r[k1][l] + r[k2][l] * r[k2][l] < obb_min_cross_length2)
      return false;
    distance = math::fabs(t[k2] * r[k1][l] - t[k1] * r[k2][l]);
    reach = ei[k1] * abs_r[k2][l] + ei[k2] * abs_r[k1][l] + ej[l1] * abs_r[k][l2] +
            ej[l2] * abs_r[k][l1];
  }
  return distance > reach + p.margin;
}

// Separating-axis test of the bounding boxes of i and j. separating_axis is in/out: on input the
// axis that separated the pair last time (or -1), tested first; on output the axis that separates
// them now, or -1 when the boxes overlap.
KOKKOS_INLINE_FUNCTION bool bounding_boxes_overlap(const PosedSuperquadric& i,
                                                   const PosedSuperquadric& j,
                                                   int& separating_axis) {
  const ObbPair pair = make_obb_pair(i, j);
  const int previous = separating_axis;
  if (previous >= 0 && previous < obb_axis_count && obb_separated_along(pair, previous))
    return false;
  for (int axis = 0; axis < obb_axis_count; ++axis)
    if (axis != previous && obb_separated_along(pair, axis)) {
      separating_axis = axis;
      return false;
    }
  separating_axis = -1;
  return true;
}

// max over the bounding box of unit_direction . (x - centre): how far the box reaches along a
// direction, e.g. towards a plane.
KOKKOS_INLINE_FUNCTION double bounding_box_support(const PosedSuperquadric& s,
                                                   Vec3 unit_direction) {
  return s.shape.a * math::fabs(dot(column(s.rotation, 0), unit_direction)) +
         s.shape.b * math::fabs(dot(column(s.rotation, 1), unit_direction)) +
         s.shape.c * math::fabs(dot(column(s.rotation, 2), unit_direction));
}

} // namespace kdem
