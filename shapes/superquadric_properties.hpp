#pragma once
// Properties of a superquadric shape template (volume, principal inertia, bounding sphere),
// computed once per template on the host, and the oriented-bounding-box pre-filter of the broad
// phase (book Sect. 2.2.1), which is host and device code.
#include <algorithm>
#include <cmath>

#include "oriented_box.hpp"
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

// A superquadric's body box is centred on it: half-extents (a, b, c) along its axes (what the
// generic oriented_box_of gives, without its centre offset).
KOKKOS_INLINE_FUNCTION OrientedBox oriented_box_of(const PosedSuperquadric& s) {
  return OrientedBox{s.centre, s.rotation, Vec3{s.shape.a, s.shape.b, s.shape.c}};
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
