#pragma once
// Superquadric particles against walls: the contacts with the wall elements of each
// superquadric particle's candidate list, one thread per superquadric particle, by the convex
// wall numerics of kernels/surface_walls.hpp, taken back to the world frame.
#include "../surface_walls.hpp"
#include "pairs.hpp"

namespace kdem {

// A posed implicit surface against wall element e, in the world frame; the Hertz radius from its
// curvature at its deepest point, within `limit` of `equivalent_radius`.
template <class Surface>
KOKKOS_INLINE_FUNCTION WallContactGeometry implicit_wall_contact(const WallElements& el, int e,
                                                                 const WallPose& wall,
                                                                 const Surface& body,
                                                                 double equivalent_radius,
                                                                 double limit) {
  const SurfaceWallContact local = surface_element_contact(el, e, in_wall_frame(body, wall));
  WallContactGeometry contact;
  contact.geometry = local.geometry;
  if (!local.geometry.touching)
    return contact;
  contact.geometry.normal = rotate(wall.rotation, local.geometry.normal);
  contact.geometry.point = wall.to_world(local.geometry.point);
  contact.effective_radius = curvature_radius(local.curvature, 0.0, equivalent_radius, limit);
  return contact;
}

// A particle of a family with an implicit surface (superquadric, poly-superquadric) against a
// wall element, posed in the wall's frame; the Hertz radius from the particle's curvature at its
// deepest point (a wall is flat or much larger).
template <class F> struct ImplicitWallContactOf {
  static constexpr int max_contacts = 1;
  WallElements el;
  typename F::Table table;
  ShapeFamilies shapes;
  ParticleViews p;
  double limit = 2;

  KOKKOS_INLINE_FUNCTION WallContactGeometry operator()(int i, int e, const WallPose& wall) const {
    return implicit_wall_contact(el, e, wall, F::pose(table, shapes, p, i),
                                 F::equivalent_radius(table, shapes, p, i), limit);
  }
};

inline SuperquadricWallContactOf SuperquadricFamily::wall_contact(const Table& t,
                                                                  const ShapeFamilies& s,
                                                                  const WallElements& elements,
                                                                  const ParticleViews& p) {
  return SuperquadricWallContactOf{elements, t, s, p, t.settings.curvature_limit};
}

} // namespace kdem
