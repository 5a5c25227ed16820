#pragma once
// Closest-point queries of wall primitives, in the wall's own frame. Host and device.
#include "math.hpp"
#include "vec3.hpp"

namespace kdem {

// Result of a closest-point query: the surface point nearest to a query point, the unit normal
// pointing to the side where particles live, and the signed distance of the query point
// along it (negative when the point has passed through the surface).
struct SurfaceQuery {
  Vec3 point;
  Vec3 free_normal;
  double signed_distance = 0;
  int feature = 0; // triangles: 0 face, 1..3 edges ab, bc, ca, 4..6 vertices a, b, c
};

// Infinite plane through `origin` with unit normal `normal` pointing to the free side.
KOKKOS_INLINE_FUNCTION SurfaceQuery plane_query(Vec3 origin, Vec3 normal, Vec3 p) {
  SurfaceQuery q;
  q.signed_distance = dot(p - origin, normal);
  q.point = p - q.signed_distance * normal;
  q.free_normal = normal;
  return q;
}

// Inside of a cylinder of the given radius whose axis passes through `base` along the unit
// vector `axis`. Particles live inside; the free normal points towards the axis. `along` is the
// coordinate of p along the axis, measured from `base`.
KOKKOS_INLINE_FUNCTION SurfaceQuery cylinder_inside_query(Vec3 base, Vec3 axis, double radius,
                                                          Vec3 p, double& along) {
  const Vec3 local = p - base;
  along = dot(local, axis);
  const Vec3 radial = local - along * axis;
  const double rho = norm(radial);
  const Vec3 outward = rho > 1e-300 ? (1.0 / rho) * radial : Vec3{1, 0, 0};
  SurfaceQuery q;
  q.signed_distance = radius - rho;
  q.point = base + along * axis + radius * outward;
  q.free_normal = -outward;
  return q;
}

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5), with the
// feature it lies on. The free normal is (p - closest)/|p - closest|, or the face normal when p
// lies on the triangle; the signed distance is the unsigned distance (walls are two-sided).
KOKKOS_INLINE_FUNCTION SurfaceQuery triangle_query(Vec3 a, Vec3 b, Vec3 c, Vec3 p) {
  SurfaceQuery q;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  const double vc = d1 * d4 - d3 * d2;
  const double vb = d5 * d2 - d1 * d6;
  const double va = d3 * d6 - d5 * d4;
  if (d1 <= 0 && d2 <= 0) {
    q.point = a, q.feature = 4;
  } else if (d3 >= 0 && d4 <= d3) {
    q.point = b, q.feature = 5;
  } else if (d6 >= 0 && d5 <= d6) {
    q.point = c, q.feature = 6;
  } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    q.point = a + (d1 / (d1 - d3)) * ab, q.feature = 1;
  } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    q.point = a + (d2 / (d2 - d6)) * ac, q.feature = 3;
  } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    q.point = b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), q.feature = 2;
  } else {
    const double denom = 1.0 / (va + vb + vc);
    q.point = a + (vb * denom) * ab + (vc * denom) * ac;
    q.feature = 0;
  }
  const Vec3 d = p - q.point;
  const double dist = norm(d);
  const Vec3 face_normal = cross(ab, ac);
  const Vec3 face_unit = (1.0 / norm(face_normal)) * face_normal;
  if (dist > 0) {
    q.free_normal = (1.0 / dist) * d;
  } else {
    q.free_normal = face_unit;
  }
  q.signed_distance = dist;
  return q;
}

} // namespace kdem
