#pragma once
// Poly-superquadric shape function (book Eqs. 3.17 to 3.25; Zhao & Zhao, IJNAMG 43 (2019) 2147):
// eight octant pieces of superquadrics that share the origin O0, the orientation and the
// blockiness n1, n2, each with its own semi-axes, taken in its own octant of the octant frame:
//   F(x, y, z) = F_k(x, y, z),  k = the octant of (x, y, z),
//   a_k = r_x+ for x >= 0, r_x- for x < 0 (likewise b_k with r_y+-, c_k with r_z+-),
// with F_k the superquadric function of superquadric.hpp. F is convex and C1 (its gradient is
// continuous across the octant planes; its Hessian jumps there where the governing exponent is 2),
// so the surface is tangent-continuous and the body convex.
//
// Octants are numbered by the signs of the local coordinates about O0, bit 0 for x < 0, bit 1 for
// y < 0, bit 2 for z < 0 (the book's k = 1..8 are 0, 1, 3, 2, 4, 5, 7, 6 here). The test is
// half-open (a coordinate >= 0, also -0.0, counts as positive), in the shape function, the
// support point and the contact's octant test alike, so that a point on an octant plane belongs to
// exactly one octant. Everything here is host and device code.
#include "superquadric.hpp"

namespace kdem {

constexpr int octant_count = 8;

struct PolySuperquadricShape {
  Vec3 plus{1, 1, 1};  // m, extents r_x+, r_y+, r_z+ from O0 along the octant frame's +x, +y, +z
  Vec3 minus{1, 1, 1}; // m, extents r_x-, r_y-, r_z- along -x, -y, -z
  // Derived by make_poly_superquadric; do not set by hand: the exponents and their derived values,
  // shared by the eight octants (its semi-axes are 1).
  SuperquadricShape exponents;
};

KOKKOS_INLINE_FUNCTION PolySuperquadricShape make_poly_superquadric(Vec3 plus, Vec3 minus,
                                                                    double n1, double n2) {
  PolySuperquadricShape s;
  s.plus = plus;
  s.minus = minus;
  s.exponents = make_superquadric(1, 1, 1, n1, n2);
  return s;
}

// The octant of a point (or direction) in the octant frame, half-open: see the header.
KOKKOS_INLINE_FUNCTION int octant_of(Vec3 local) {
  return (local.x < 0 ? 1 : 0) | (local.y < 0 ? 2 : 0) | (local.z < 0 ? 4 : 0);
}

// The signs (+1, -1) of the coordinates in an octant.
KOKKOS_INLINE_FUNCTION Vec3 octant_signs(int octant) {
  return {octant & 1 ? -1.0 : 1.0, octant & 2 ? -1.0 : 1.0, octant & 4 ? -1.0 : 1.0};
}

// The semi-axes (a_k, b_k, c_k) of octant k.
KOKKOS_INLINE_FUNCTION Vec3 octant_semi_axes(const PolySuperquadricShape& s, int octant) {
  return {octant & 1 ? s.minus.x : s.plus.x, octant & 2 ? s.minus.y : s.plus.y,
          octant & 4 ? s.minus.z : s.plus.z};
}

// The whole superquadric whose piece octant k is (the book's basic element k).
KOKKOS_INLINE_FUNCTION SuperquadricShape octant_shape(const PolySuperquadricShape& s, int octant) {
  const Vec3 axes = octant_semi_axes(s, octant);
  SuperquadricShape e = s.exponents;
  e.a = axes.x, e.b = axes.y, e.c = axes.z;
  e.inv_a = 1.0 / axes.x, e.inv_b = 1.0 / axes.y, e.inv_c = 1.0 / axes.z;
  return e;
}

template <bool WithHessian = true>
KOKKOS_INLINE_FUNCTION ShapeFunction poly_superquadric_local(const PolySuperquadricShape& s,
                                                             Vec3 p) {
  return superquadric_local<WithHessian>(octant_shape(s, octant_of(p)), p);
}

// The body point furthest along `direction` (octant frame): the support point of the octant the
// direction points into (the outward normal of octant k's piece points into octant k; a zero
// component gives a point on the shared plane, where the neighbouring pieces agree).
KOKKOS_INLINE_FUNCTION Vec3 poly_superquadric_support_point(const PolySuperquadricShape& s,
                                                            Vec3 direction) {
  return superquadric_support_point(octant_shape(s, octant_of(direction)), direction);
}

// The smallest half-width (r+ + r-) / 2 over the axes: the body's own size, which a thin side
// (the book's hemisphere cap) does not shrink.
KOKKOS_INLINE_FUNCTION double smallest_half_width(const PolySuperquadricShape& s) {
  return 0.5 *
         math::min(math::min(s.plus.x + s.minus.x, s.plus.y + s.minus.y), s.plus.z + s.minus.z);
}

KOKKOS_INLINE_FUNCTION double smallest_extent(const PolySuperquadricShape& s) {
  return math::min(math::min(math::min(s.plus.x, s.plus.y), math::min(s.plus.z, s.minus.x)),
                   math::min(s.minus.y, s.minus.z));
}

// The largest extent along each axis.
KOKKOS_INLINE_FUNCTION Vec3 largest_extents(const PolySuperquadricShape& s) {
  return {math::max(s.plus.x, s.minus.x), math::max(s.plus.y, s.minus.y),
          math::max(s.plus.z, s.minus.z)};
}

// A poly-superquadric placed in the world: its origin O0 and octant frame (which may differ from
// the particle's centroid and principal frame, see PolySuperquadricFamily). A surface of the
// concept of implicit_surface.hpp, with the piecewise F; element(k) is octant k's whole
// superquadric, posed alike.
struct PosedPolySuperquadric {
  PolySuperquadricShape shape;
  Vec3 centre;   // O0, world
  Mat3 rotation; // columns are the octant axes in world coordinates

  KOKKOS_INLINE_FUNCTION Vec3 to_local(Vec3 x) const {
    return transpose_times(rotation, x - centre);
  }
  KOKKOS_INLINE_FUNCTION Vec3 to_world(Vec3 local) const { return centre + rotation * local; }
  KOKKOS_INLINE_FUNCTION int octant_at(Vec3 x) const { return octant_of(to_local(x)); }
  KOKKOS_INLINE_FUNCTION PosedSuperquadric element(int octant) const {
    return PosedSuperquadric{octant_shape(shape, octant), centre, rotation};
  }

  template <bool WithHessian> KOKKOS_INLINE_FUNCTION ShapeFunction local(Vec3 x_local) const {
    return poly_superquadric_local<WithHessian>(shape, x_local);
  }
  KOKKOS_INLINE_FUNCTION double smallest_length() const { return smallest_extent(shape); }
  KOKKOS_INLINE_FUNCTION double reach() const { return norm(largest_extents(shape)); }
  KOKKOS_INLINE_FUNCTION double equivalent_radius() const {
    const Vec3 mean = 0.5 * (shape.plus + shape.minus);
    return math::cbrt(mean.x * mean.y * mean.z);
  }
  KOKKOS_INLINE_FUNCTION Vec3 support_local(Vec3 direction_local) const {
    return poly_superquadric_support_point(shape, direction_local);
  }
  KOKKOS_INLINE_FUNCTION BodyBox local_box() const { return BodyBox{-shape.minus, shape.plus}; }
  KOKKOS_INLINE_FUNCTION double value(Vec3 x) const {
    return poly_superquadric_local<false>(shape, to_local(x)).value;
  }
  template <bool WithHessian = true> KOKKOS_INLINE_FUNCTION ShapeFunction evaluate(Vec3 x) const {
    ShapeFunction world = evaluate_with_body_hessian<WithHessian>(x);
    if constexpr (WithHessian)
      world.hessian = world_hessian(world.hessian);
    return world;
  }
  template <bool WithHessian = true>
  KOKKOS_INLINE_FUNCTION ShapeFunction evaluate_with_body_hessian(Vec3 x) const {
    ShapeFunction f = poly_superquadric_local<WithHessian>(shape, to_local(x));
    f.gradient = rotation * f.gradient;
    return f;
  }
  // The body Hessian of every octant has the superquadric's zero (x, z) and (y, z) entries.
  KOKKOS_INLINE_FUNCTION Mat3 world_hessian(const Mat3& body) const {
    return PosedSuperquadric{shape.exponents, centre, rotation}.world_hessian(body);
  }
};

static_assert(is_wall_surface<PosedPolySuperquadric>::value,
              "a posed poly-superquadric is a surface of the concept of implicit_surface.hpp");

} // namespace kdem
