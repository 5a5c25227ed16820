#pragma once
// Dilated polyhedra against walls, in the particle's body frame: a plane touches the core's
// lowest convex vertices within reach, the inside of a cylinder its outermost ones, and a mesh
// triangle is a core of zero dilation (its face two-sided, its edges and vertices with the
// mesh's owners and the directions of the mesh around them as normal cones) met by the same
// feature-pair tests as two particles. Contacts of one wall element are weighted by the book's
// averaging; the slot key is the particle's feature times 8 plus the wall triangle's own
// (vertices 0-2, edges 3-5, face 6; 0 for planes and cylinders). Hertz radius: the particle's
// volume-equivalent radius (a wall is flat or much larger).
#include "family.hpp"

namespace kdem {

// Mesh triangle e of a wall as a core (zero dilation), in the wall's reference frame, its face
// normal turned towards the side `towards` points to.
struct WallTriangleCore {
  const WallElements& el;
  int e = 0;
  Vec3 normal;

  KOKKOS_INLINE_FUNCTION double dilation() const { return 0.0; }
  KOKKOS_INLINE_FUNCTION FeatureNumbering numbering() const { return {3, 3}; }
  KOKKOS_INLINE_FUNCTION CoreVertex vertex(int k) const {
    const int global = el.features(e, 3 + k);
    CoreVertex v;
    v.position = geometry_vec(el.geometry, e, 3 * k);
    v.cone_first = el.vertex_edge_start(global);
    v.cone_count = el.vertex_edge_start(global + 1) - v.cone_first;
    v.owner = el.vertex_owner(global) == e ? 0 : -1;
    v.convex = 1;
    return v;
  }
  KOKKOS_INLINE_FUNCTION CoreEdge edge(int k) const {
    const int global = el.features(e, k);
    CoreEdge edge;
    edge.vertex[0] = k, edge.vertex[1] = (k + 1) % 3;
    edge.inward[0] = -edge_outward_of(el, global, 0);
    edge.inward[1] = el.edge_sides(global) > 1 ? -edge_outward_of(el, global, 1) : edge.inward[0];
    edge.owner = el.edge_owner(global) == e ? 0 : -1;
    edge.convex = 1;
    return edge;
  }
  KOKKOS_INLINE_FUNCTION CoreFace face(int) const {
    CoreFace f;
    for (int k = 0; k < 3; ++k)
      f.vertex[k] = k, f.edge[k] = k;
    f.normal = normal;
    return f;
  }
  KOKKOS_INLINE_FUNCTION Vec3 cone(int k) const { return load3(el.vertex_edge_direction, k); }
};

struct DilatedPolyhedronWallContact {
  static constexpr int max_contacts = DilatedPolyhedronFamily::contact_points;
  WallElements el;
  DilatedPolyhedronFamily::Table table;
  ShapeFamilies shapes;
  ParticleViews p;

  // The contacts found in the body frame, into the world (normals from the wall to the particle).
  KOKKOS_INLINE_FUNCTION void to_world(const DeepestContacts<max_contacts>& deepest,
                                       const Mat3& rotation, Vec3 origin, double radius,
                                       WallContacts<max_contacts>& found) const {
    for (int c = 0; c < deepest.count; ++c) {
      const FeatureContact& f = deepest.contact[c];
      WallContactGeometry& contact = found.add();
      contact.geometry =
          ContactGeometry{true, f.overlap, rotation * f.normal, origin + rotation * f.point};
      contact.effective_radius = radius;
      contact.feature = 8 * f.feature_a + f.feature_b;
    }
    deepest.weights(table.settings.averaging,
                    [&](int c, double w) { found.contact[c].weight = w; });
  }

  KOKKOS_INLINE_FUNCTION void operator()(int i, int e, const WallPose& wall,
                                         WallContacts<max_contacts>& found) const {
    const DeviceCore core = DilatedPolyhedronFamily::core(table, shapes, p, i);
    const Mat3 rotation = rotation_matrix(load_quat(p.orientation, i));
    const Vec3 origin = load3(p.position, i);
    // The wall's reference frame placed in the body frame.
    const Mat3 wall_rotation = rotation_matrix(wall.rotation);
    const RelativePose pose{
        transpose(rotation) * wall_rotation,
        transpose_times(rotation, wall.offset - wall_rotation * wall.pivot - origin)};
    DeepestContacts<max_contacts> deepest(table.settings, core.dilation());
    const ConeSlack& slack = table.settings.slack;
    switch (el.kind(e)) {
    case plane_element:
      dilated_plane_contacts(core, pose.point(geometry_vec(el.geometry, e, 0)),
                             pose.rotation * geometry_vec(el.geometry, e, 3), slack, deepest);
      break;
    case cylinder_element:
      dilated_cylinder_contacts(core, pose.point(geometry_vec(el.geometry, e, 0)),
                                pose.rotation * geometry_vec(el.geometry, e, 3), el.geometry(e, 6),
                                el.geometry(e, 7), slack, deepest);
      break;
    default:
      triangle_contacts(core, e, pose, slack, deepest);
    }
    to_world(deepest, rotation, origin,
             DilatedPolyhedronFamily::equivalent_radius(table, shapes, p, i), found);
  }

  KOKKOS_INLINE_FUNCTION void triangle_contacts(const DeviceCore& core, int e,
                                                const RelativePose& pose, const ConeSlack& slack,
                                                DeepestContacts<max_contacts>& deepest) const {
    Vec3 corner[3];
    for (int k = 0; k < 3; ++k)
      corner[k] = pose.point(geometry_vec(el.geometry, e, 3 * k));
    const Vec3 centre = (1.0 / 3.0) * (corner[0] + corner[1] + corner[2]);
    double reach = 0;
    for (int k = 0; k < 3; ++k)
      reach = math::max(reach, norm(corner[k] - centre));
    // Two-sided: the face's normal on the particle's side (the body origin's).
    Vec3 normal = cross(corner[1] - corner[0], corner[2] - corner[0]);
    normal = (1.0 / norm(normal)) * normal;
    if (dot(Vec3{} - corner[0], normal) < 0)
      normal = -normal;
    const WallTriangleCore triangle{el, e, transpose_times(pose.rotation, normal)};
    const PlacedCore<DeviceCore> placed_core{core, RelativePose{identity3(), Vec3{}}, false};
    const PlacedCore<WallTriangleCore> placed_triangle{triangle, pose, true};
    for_each_face_near(core, centre, reach + core.dilation(), [&](int f) {
      face_pair_contacts(placed_core, f, placed_triangle, 0, slack, deepest);
    });
  }
};

inline DilatedPolyhedronWallContact
DilatedPolyhedronFamily::wall_contact(const Table& t, const ShapeFamilies& s,
                                      const WallElements& elements, const ParticleViews& p) {
  return DilatedPolyhedronWallContact{elements, t, s, p};
}

} // namespace kdem
