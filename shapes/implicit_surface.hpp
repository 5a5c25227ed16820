#pragma once
// The surface concept that the implicit-surface numerics (superquadric_contact.hpp: the
// midway-point system, the closest-point system, surface points along a line, curvatures,
// separation bounds) are written against, so that every convex body given by an inside-outside
// function F (F < 0 inside, F = 0 on the surface, convex) reuses them: a superquadric
// (PosedSuperquadric), and later a poly-superquadric octant or a clump element.
//
// A posed surface S provides, callable on the device:
//   Vec3 centre; Mat3 rotation;                       pose: body frame to world
//   Vec3 to_local(Vec3 x), to_world(Vec3 x_local)     frame changes
//   template <bool H> ShapeFunction local(Vec3 x_local)
//                                                     F, gradient and (H) Hessian, body frame
//   template <bool H> ShapeFunction evaluate(Vec3 x)  the same in the world frame
//   template <bool H> ShapeFunction evaluate_with_body_hessian(Vec3 x)
//                                                     world gradient, body-frame Hessian
//   Mat3 world_hessian(const Mat3& body)              R H R^T
//   double value(Vec3 x)                              F alone
//   double smallest_length()                          the length unit of the solves (smallest
//                                                     semi-axis or element size), m
//   double reach()                                    an upper bound on |x - centre| over the
//                                                     body, m
//   double equivalent_radius()                        radius of the sphere the homotopy and the
//                                                     first guess start from, m
// and, for the wall numerics (surface_wall.hpp):
//   Vec3 support_local(Vec3 direction_local)          the body point furthest along a body-frame
//                                                     direction (any length; zero: the centre)
//   BodyBox local_box()                               a body-frame box that contains the body
#include <type_traits>

#include "mat3.hpp"

namespace kdem {

// Value, gradient and (optionally) Hessian of the inside-outside function F at one point.
struct ShapeFunction {
  double value = 0;
  Vec3 gradient;
  Mat3 hessian;
};

// A box in a body frame, lo <= x <= hi component by component.
struct BodyBox {
  Vec3 lo, hi;
};

// Mean curvature of the level set through a point, from the gradient g and Hessian H of any
// function with that level set (Goldman, CAGD 22 (2005) 632, Eq. 4.1):
//   kappa_H = |g^T H g - |g|^2 tr H| / (2 |g|^3).
// Invariant under scaling the function, so the conditioning factor does not matter.
KOKKOS_INLINE_FUNCTION double mean_curvature(const ShapeFunction& f) {
  const double g2 = norm2(f.gradient);
  if (!(g2 > 0))
    return 0;
  const double gHg = dot(f.gradient, f.hessian * f.gradient);
  return math::fabs(gHg - g2 * trace(f.hessian)) / (2.0 * g2 * math::sqrt(g2));
}

// Gaussian curvature of the level set (Goldman 2005, Eq. 4.2): g^T adj(H) g / |g|^4.
KOKKOS_INLINE_FUNCTION double gaussian_curvature(const ShapeFunction& f) {
  const double g2 = norm2(f.gradient);
  if (!(g2 > 0))
    return 0;
  const Mat3& h = f.hessian;
  Mat3 adj; // adjugate (transposed cofactor matrix) of the symmetric Hessian
  adj.m[0][0] = h.m[1][1] * h.m[2][2] - h.m[1][2] * h.m[2][1];
  adj.m[1][1] = h.m[0][0] * h.m[2][2] - h.m[0][2] * h.m[2][0];
  adj.m[2][2] = h.m[0][0] * h.m[1][1] - h.m[0][1] * h.m[1][0];
  adj.m[0][1] = adj.m[1][0] = h.m[0][2] * h.m[2][1] - h.m[0][1] * h.m[2][2];
  adj.m[0][2] = adj.m[2][0] = h.m[0][1] * h.m[1][2] - h.m[0][2] * h.m[1][1];
  adj.m[1][2] = adj.m[2][1] = h.m[0][2] * h.m[1][0] - h.m[0][0] * h.m[1][2];
  return dot(f.gradient, adj * f.gradient) / (g2 * g2);
}

// True when S has the members above that the numerics call by name (a compile-time check of
// a new family's surface type).
template <class S, class = void> struct is_implicit_surface : std::false_type {};
template <class S>
struct is_implicit_surface<
    S, std::void_t<decltype(std::declval<const S&>().to_local(Vec3{})),
                   decltype(std::declval<const S&>().to_world(Vec3{})),
                   decltype(std::declval<const S&>().template local<true>(Vec3{})),
                   decltype(std::declval<const S&>().template evaluate<true>(Vec3{})),
                   decltype(std::declval<const S&>().smallest_length()),
                   decltype(std::declval<const S&>().reach()),
                   decltype(std::declval<const S&>().equivalent_radius()),
                   decltype(std::declval<const S&>().centre),
                   decltype(std::declval<const S&>().rotation)>> : std::true_type {};

// True when S also has what the wall numerics call: support point and body box.
template <class S, class = void> struct is_wall_surface : std::false_type {};
template <class S>
struct is_wall_surface<S, std::void_t<decltype(std::declval<const S&>().support_local(Vec3{})),
                                      decltype(std::declval<const S&>().local_box())>>
    : std::bool_constant<is_implicit_surface<S>::value> {};

} // namespace kdem
