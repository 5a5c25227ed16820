#pragma once
// Superquadric particles against walls: the contacts with the wall elements of each
// superquadric particle's candidate list, one thread per superquadric particle. The particle is
// posed in the wall's reference frame, the contact found there (planes: the deepest point of
// book Eqs. 2.11-2.12; cylinders: the point furthest from the axis; triangles: face, edge or
// vertex contact), and taken back to the world frame.
#include "../../shapes/superquadric_wall.hpp"
#include "pairs.hpp"

namespace kdem {

// What triangle e knows of the mesh around it, from the mesh topology (see TriangleNeighbourhood).
KOKKOS_INLINE_FUNCTION TriangleNeighbourhood triangle_neighbourhood(const WallElements& el, int e) {
  TriangleNeighbourhood t;
  t.normal = load3(el.triangle_normal, e);
  for (int k = 0; k < 3; ++k) {
    const int edge = el.features(e, k);
    t.owns_edge[k] = el.edge_owner(edge) == e;
    const int other =
        el.edge_triangles(edge, 0) == e ? el.edge_triangles(edge, 1) : el.edge_triangles(edge, 0);
    t.has_neighbour[k] = other >= 0;
    if (other >= 0) {
      t.neighbour_normal[k] = load3(el.triangle_normal, other);
      for (int v = 0; v < 3; ++v) { // the neighbour's vertex off the shared edge
        const int vertex = el.features(other, 3 + v);
        if (vertex != el.edge_vertices(edge, 0) && vertex != el.edge_vertices(edge, 1))
          t.neighbour_opposite[k] = geometry_vec(el.geometry, other, 3 * v);
      }
    }
    const int vertex = el.features(e, 3 + k);
    t.reports_vertex[k] = el.vertex_owner(vertex) == e && el.vertex_corner(vertex) != 0;
    t.vertex_ring[k] = el.vertex_ring.data() + el.vertex_ring_start(vertex);
    t.vertex_ring_size[k] = el.vertex_ring_start(vertex + 1) - el.vertex_ring_start(vertex);
  }
  return t;
}

KOKKOS_INLINE_FUNCTION SuperquadricWallContact
superquadric_mesh_triangle_contact(const WallElements& el, int e, const PosedSuperquadric& body) {
  return superquadric_triangle_contact(
      body, geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3),
      geometry_vec(el.geometry, e, 6), triangle_neighbourhood(el, e));
}

// The particle posed in the reference frame of a wall at its current pose.
KOKKOS_INLINE_FUNCTION PosedSuperquadric in_wall_frame(const PosedSuperquadric& body,
                                                       const WallPose& wall) {
  PosedSuperquadric local = body;
  local.centre = wall.to_reference(body.centre);
  local.rotation = transpose(rotation_matrix(wall.rotation)) * body.rotation;
  return local;
}

KOKKOS_INLINE_FUNCTION SuperquadricWallContact
superquadric_element_contact(const WallElements& el, int e, const PosedSuperquadric& body) {
  switch (el.kind(e)) {
  case plane_element:
    return superquadric_plane_contact(body, geometry_vec(el.geometry, e, 0),
                                      geometry_vec(el.geometry, e, 3));
  case cylinder_element: {
    SuperquadricWallContact none;
    const Vec3 base = geometry_vec(el.geometry, e, 0), axis = geometry_vec(el.geometry, e, 3);
    const double along = dot(body.centre - base, axis);
    if (along < 0 || along > el.geometry(e, 7))
      return none; // as for spheres: the centre must lie along the cylinder's length
    return superquadric_inside_cylinder_contact(body, base, axis, el.geometry(e, 6));
  }
  default:
    return superquadric_mesh_triangle_contact(el, e, body);
  }
}

// A superquadric particle against a wall element, posed in the wall's frame; the Hertz radius
// from the particle's curvature at its deepest point (a wall is flat or much larger).
struct SuperquadricWallContactOf {
  static constexpr int max_contacts = 1;
  WallElements el;
  SuperquadricFamily::Table table;
  ShapeFamilies shapes;
  ParticleViews p;
  double limit = 2;

  KOKKOS_INLINE_FUNCTION WallContactGeometry operator()(int i, int e, const WallPose& wall) const {
    const SuperquadricWallContact local = superquadric_element_contact(
        el, e, in_wall_frame(SuperquadricFamily::pose(table, shapes, p, i), wall));
    WallContactGeometry contact;
    contact.geometry = local.geometry;
    if (!local.geometry.touching)
      return contact;
    contact.geometry.normal = rotate(wall.rotation, local.geometry.normal);
    contact.geometry.point = wall.to_world(local.geometry.point);
    contact.effective_radius = curvature_radius(
        local.curvature, 0.0, SuperquadricFamily::equivalent_radius(table, shapes, p, i), limit);
    return contact;
  }
};

inline SuperquadricWallContactOf SuperquadricFamily::wall_contact(const Table& t,
                                                                  const ShapeFamilies& s,
                                                                  const WallElements& elements,
                                                                  const ParticleViews& p) {
  return SuperquadricWallContactOf{elements, t, s, p, t.settings.curvature_limit};
}

} // namespace kdem
