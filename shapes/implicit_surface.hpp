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
#include <type_traits>

#include "vec3.hpp"

namespace kdem {

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

} // namespace kdem
