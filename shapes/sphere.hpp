#pragma once
// Sphere geometry: mass properties and sphere-sphere contact geometry.
#include "vec3.hpp"

namespace kdem {

constexpr double pi = 3.14159265358979323846;

KOKKOS_INLINE_FUNCTION double sphere_volume(double radius) {
  return 4.0 / 3.0 * pi * radius * radius * radius;
}

// Principal moment of inertia of a solid sphere of this mass and radius.
KOKKOS_INLINE_FUNCTION double sphere_inertia(double mass, double radius) {
  return 0.4 * mass * radius * radius;
}

// Contact geometry between two bodies i and j. `normal` is the unit vector from j towards i,
// so the normal force on i is +F_n normal. `point` lies midway in the overlap region.
struct ContactGeometry {
  bool touching = false;
  double overlap = 0; // m, > 0 when touching
  Vec3 normal;
  Vec3 point;
};

KOKKOS_INLINE_FUNCTION ContactGeometry sphere_sphere(Vec3 xi, double ri, Vec3 xj, double rj) {
  ContactGeometry g;
  const Vec3 d = xi - xj;
  const double dist2 = norm2(d);
  const double reach = ri + rj;
  if (dist2 >= reach * reach)
    return g;
  const double dist = math::sqrt(dist2);
  g.touching = true;
  g.overlap = reach - dist;
  g.normal = dist > 0 ? (1.0 / dist) * d : Vec3{0, 0, 1};
  g.point = xj + (rj - 0.5 * g.overlap) * g.normal;
  return g;
}

// Sphere against a wall surface: `surface_point` is the closest surface point to the centre and
// `signed_distance` the centre's distance from the surface, negative behind it; `free_normal` is
// the surface normal pointing to the free side.
KOKKOS_INLINE_FUNCTION ContactGeometry sphere_on_surface(Vec3 centre, double radius,
                                                         double signed_distance, Vec3 free_normal) {
  ContactGeometry g;
  if (signed_distance >= radius)
    return g;
  g.touching = true;
  g.overlap = radius - signed_distance;
  g.normal = free_normal;
  g.point = centre - (radius - 0.5 * g.overlap) * free_normal;
  return g;
}

} // namespace kdem
