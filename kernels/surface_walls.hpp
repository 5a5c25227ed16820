#pragma once
// Convex bodies (the posed surfaces of shapes/implicit_surface.hpp) against the wall elements:
// the body is posed in the wall's reference frame and the contact found there (planes: the
// deepest point, book Eqs. 2.11-2.12; cylinders: the point furthest from the axis; triangles:
// face, edge or vertex contact, with the mesh around the triangle read from the wall table).
#include "../shapes/surface_wall.hpp"
#include "walls.hpp"

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

template <class Surface>
KOKKOS_INLINE_FUNCTION SurfaceWallContact surface_mesh_triangle_contact(const WallElements& el,
                                                                        int e,
                                                                        const Surface& body) {
  return surface_triangle_contact(body, geometry_vec(el.geometry, e, 0),
                                  geometry_vec(el.geometry, e, 3), geometry_vec(el.geometry, e, 6),
                                  triangle_neighbourhood(el, e));
}

// The particle posed in the reference frame of a wall at its current pose.
template <class Surface>
KOKKOS_INLINE_FUNCTION Surface in_wall_frame(const Surface& body, const WallPose& wall) {
  Surface local = body;
  local.centre = wall.to_reference(body.centre);
  local.rotation = transpose(rotation_matrix(wall.rotation)) * body.rotation;
  return local;
}

// The contact of a posed body (in the wall's frame) with element e of the wall.
template <class Surface>
KOKKOS_INLINE_FUNCTION SurfaceWallContact surface_element_contact(const WallElements& el, int e,
                                                                  const Surface& body) {
  switch (el.kind(e)) {
  case plane_element:
    return surface_plane_contact(body, geometry_vec(el.geometry, e, 0),
                                 geometry_vec(el.geometry, e, 3));
  case cylinder_element: {
    SurfaceWallContact none;
    const Vec3 base = geometry_vec(el.geometry, e, 0), axis = geometry_vec(el.geometry, e, 3);
    const double along = dot(body.centre - base, axis);
    if (along < 0 || along > el.geometry(e, 7))
      return none; // as for spheres: the centre must lie along the cylinder's length
    return surface_inside_cylinder_contact(body, base, axis, el.geometry(e, 6));
  }
  default:
    return surface_mesh_triangle_contact(el, e, body);
  }
}

} // namespace kdem
