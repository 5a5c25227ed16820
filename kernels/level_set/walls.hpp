#pragma once
// Level-set bodies against walls, in the particle's body frame (digest B7): its surface points
// beyond a plane or beyond the inside of a cylinder; against a mesh triangle, its points beyond
// the triangle's plane whose foot lies in the triangle and inside the body (face contact), and
// where there is none, the triangle's vertices and points along its edges inside the body's grid
// (vertex and edge contacts: the body's value and gradient there), each edge and vertex tested
// only by the triangle that owns it. Contacts of one element are grouped into patches (the
// connected regions of penetration, patches.hpp) and weighted by the book's averaging; the slot key
// is 8 times the particle's key plus the triangle's feature (vertices 0-2, edges 3-5, face 6; 0 for
// planes and cylinders). Hertz radius: the particle's volume-equivalent radius (a wall is flat or
// much larger).
#include "family.hpp"
#include "patches.hpp"

namespace kdem {

struct LevelSetWallContact {
  static constexpr int max_contacts = LevelSetFamily::contact_points;
  WallElements el;
  LevelSetFamily::Table table;
  ShapeFamilies shapes;
  ParticleViews p;

  KOKKOS_INLINE_FUNCTION void to_world(const LevelSetPatches<max_contacts>& patches,
                                       const Mat3& rotation, Vec3 origin, double radius,
                                       WallContacts<max_contacts>& found) const {
    for (int c = 0; c < patches.count; ++c) {
      const FeatureContact& f = patches.contact[c];
      WallContactGeometry& contact = found.add();
      contact.geometry =
          ContactGeometry{true, f.overlap, rotation * f.normal, origin + rotation * f.point};
      contact.effective_radius = radius;
      contact.feature = 8 * f.feature_a + f.feature_b;
    }
    patches.weights(table.settings.averaging,
                    [&](int c, double w) { found.contact[c].weight = w; });
  }

  KOKKOS_INLINE_FUNCTION void operator()(int i, int e, const WallPose& wall,
                                         WallContacts<max_contacts>& found) const {
    const LevelSetBodyView body = LevelSetFamily::body(table, shapes, p, i);
    const Mat3 rotation = rotation_matrix(load_quat(p.orientation, i));
    const Vec3 origin = load3(p.position, i);
    const Mat3 wall_rotation = rotation_matrix(wall.rotation);
    const RelativePose pose{
        transpose(rotation) * wall_rotation,
        transpose_times(rotation, wall.offset - wall_rotation * wall.pivot - origin)};
    const double radius = LevelSetFamily::equivalent_radius(table, shapes, p, i);
    LevelSetPatches<max_contacts> patches(table.settings, radius);
    switch (el.kind(e)) {
    case plane_element:
      points_beyond_plane(body, pose.point(geometry_vec(el.geometry, e, 0)),
                          pose.rotation * geometry_vec(el.geometry, e, 3), patches);
      break;
    case cylinder_element:
      points_beyond_cylinder(body, pose.point(geometry_vec(el.geometry, e, 0)),
                             pose.rotation * geometry_vec(el.geometry, e, 3), el.geometry(e, 6),
                             el.geometry(e, 7), patches);
      break;
    default:
      triangle_contacts(body, e, pose, patches);
    }
    to_world(patches, rotation, origin, radius, found);
  }

  // The face contacts: points beyond the triangle's plane (seen from the body's origin), whose
  // foot on the plane lies in the triangle and inside the body. Such a point and its foot lie
  // within the body's reach, so it lies in the triangle's prism two reaches deep: only the points
  // in that prism's box are visited.
  KOKKOS_INLINE_FUNCTION void face_contacts(const LevelSetBodyView& body, const Vec3 (&corner)[3],
                                            Vec3 normal,
                                            LevelSetPatches<max_contacts>& patches) const {
    const double reach2 = body.reach * body.reach;
    Vec3 lo = corner[0], hi = corner[0];
    for (int k = 0; k < 6; ++k) {
      const Vec3 x = k < 3 ? corner[k] : corner[k - 3] - (2 * body.reach) * normal;
      lo = Vec3{math::min(lo.x, x.x), math::min(lo.y, x.y), math::min(lo.z, x.z)};
      hi = Vec3{math::max(hi.x, x.x), math::max(hi.y, x.y), math::max(hi.z, x.z)};
    }
    body.for_points_in_box(lo, hi, [&](int q) {
      const Vec3 x = body.points[q];
      const double height = dot(x - corner[0], normal);
      if (!(height < 0))
        return;
      const Vec3 foot = x - height * normal;
      Vec3 in_face;
      LevelSetSample s;
      if (norm2(foot) >= reach2 ||
          !dilated::face_interior(corner[0], corner[1], corner[2], normal, foot, in_face) ||
          !interpolate_level_set(body.grid, body.values, foot, s) || !(s.value < 0))
        return;
      FeatureContact c;
      c.overlap = -height;
      c.normal = normal;
      c.point = x + (0.5 * c.overlap) * normal;
      c.feature_a = 1 + q;
      c.feature_b = 6;
      patches.add(c);
    });
  }

  // A wall point inside the body: overlap minus the value, normal against the body's outward
  // normal there (from the wall into the body).
  KOKKOS_INLINE_FUNCTION static void point_inside(const LevelSetBodyView& body, Vec3 x, int key,
                                                  LevelSetPatches<max_contacts>& patches) {
    LevelSetSample s;
    if (!body.sample(x, s) || !(s.value < 0))
      return;
    const Vec3 out = level_set::outward(s, x);
    FeatureContact c;
    c.overlap = -s.value;
    c.normal = -out;
    c.point = x - (0.5 * c.overlap) * out;
    c.feature_a = 0;
    c.feature_b = key;
    patches.add(c);
  }

  // The triangle's owned vertices, and points along its owned edges at the grid's spacing.
  KOKKOS_INLINE_FUNCTION void
  edge_and_vertex_contacts(const LevelSetBodyView& body, int e, const Vec3 (&corner)[3],
                           LevelSetPatches<max_contacts>& patches) const {
    for (int k = 0; k < 3; ++k) {
      if (el.vertex_owner(el.features(e, 3 + k)) == e)
        point_inside(body, corner[k], k, patches);
      if (el.edge_owner(el.features(e, k)) != e)
        continue;
      const Vec3 from = corner[k], to = corner[(k + 1) % 3];
      const int pieces = int(norm(to - from) / body.grid.spacing) + 1;
      for (int s = 1; s < pieces; ++s)
        point_inside(body, from + (double(s) / pieces) * (to - from), 3 + k, patches);
    }
  }

  KOKKOS_INLINE_FUNCTION void triangle_contacts(const LevelSetBodyView& body, int e,
                                                const RelativePose& pose,
                                                LevelSetPatches<max_contacts>& patches) const {
    Vec3 corner[3];
    for (int k = 0; k < 3; ++k)
      corner[k] = pose.point(geometry_vec(el.geometry, e, 3 * k));
    // Two-sided: the face's normal on the particle's side (the body origin's).
    Vec3 normal = cross(corner[1] - corner[0], corner[2] - corner[0]);
    normal = (1.0 / norm(normal)) * normal;
    if (dot(Vec3{} - corner[0], normal) < 0)
      normal = -normal;
    if (dot(Vec3{} - corner[0], normal) > body.reach)
      return;
    const int before = patches.count;
    face_contacts(body, corner, normal, patches);
    if (patches.count == before)
      edge_and_vertex_contacts(body, e, corner, patches);
  }
};

inline LevelSetWallContact LevelSetFamily::wall_contact(const Table& t, const ShapeFamilies& s,
                                                        const WallElements& elements,
                                                        const ParticleViews& p) {
  return LevelSetWallContact{elements, t, s, p};
}

} // namespace kdem
