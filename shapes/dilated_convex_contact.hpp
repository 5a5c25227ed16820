#pragma once
// A dilated core against any convex body known by its support points (a superquadric, a
// poly-superquadric, a clump's element): the generic narrow phase of the dilated polyhedra.
// Host and device.
//
// The core is a union of triangles, each of them convex, and the distance from a convex body to
// one is a convex function on it with one minimum. For each core face near the body:
// - The body's support point along the face's inward normal is its point lowest over the face's
//   plane. Where it lies over the face and above the plane, it and its foot are the closest pair
//   of body and face, exactly: a face contact of normal n and overlap r - height. Over the face
//   and below the plane while the body crosses the face's triangle, it is the same contact with
//   a negative height (deeper than the dilation radius), continuing the first. A height within
//   GJK's tolerance of 0 counts as in front: GJK converges slowly on bodies that just touch,
//   and would not tell the crossing at that depth.
// - Otherwise the closest point of the face is on its boundary: GJK (convex_distance.hpp) finds
//   the body's closest point, and the face's edges and vertices meet it as they would a sphere
//   of radius 0 centred there (face_boundary_contacts), with the same owner and normal-cone
//   tests, so that each local minimum of the distance between body and core is found once, with
//   the keys a sphere's contacts have.
// The over-the-face test includes the face's edges to 1e-12 of its size, so that a lowest point
// on an edge between two coplanar faces (a flat face's diagonal) is claimed by at least one of
// them; by both within that band (the averaging weights two equal contacts by one half each). A
// body crossing a face with its lowest point over no face makes no contact there (the book's
// odd-even rule is not implemented: docs/architecture.md).
#include "convex_distance.hpp"
#include "dilated_polyhedron.hpp"

namespace kdem {

namespace dilated {

// Whether the projection of x onto triangle (a, b, c)'s plane (unit normal n) lies in the
// triangle or within 1e-12 of its size outside; the projection in `foot`.
KOKKOS_INLINE_FUNCTION bool over_triangle(Vec3 a, Vec3 b, Vec3 c, Vec3 n, Vec3 x, Vec3& foot) {
  foot = x - dot(x - a, n) * n;
  const Vec3 winding = cross(b - a, c - a);
  const double area2 = norm2(winding), slack = -1e-12 * area2;
  return dot(cross(b - a, foot - a), winding) >= slack &&
         dot(cross(c - b, foot - b), winding) >= slack &&
         dot(cross(a - c, foot - c), winding) >= slack;
}

} // namespace dilated

// What one body's search found besides its contacts.
struct DilatedConvexTally {
  int iterations = 0; // GJK iterations over them
  int deep = 0;       // faces crossed by the body
  int unconverged = 0;
  bool tree_walk_complete = true;
};

// Face f's contacts with the convex body (support in the core's frame; `centre` a point inside
// it, as the GJK's first guess).
template <class Core, class Support, class Sink>
KOKKOS_INLINE_FUNCTION void face_convex_contacts(const Core& core, int f, const Support& support,
                                                 Vec3 centre, ConvexDistanceControls controls,
                                                 const ConeSlack& slack, Sink& sink,
                                                 DilatedConvexTally& tally) {
  const CoreFace& face = core.face(f);
  const Vec3 n = face.normal;
  const double r = core.dilation();
  TriangleSupport triangle;
  for (int k = 0; k < 3; ++k)
    triangle.corner[k] = core.vertex(face.vertex[k]).position;
  const Vec3 lowest = support(-n);
  const double height = dot(lowest - triangle.corner[0], n);
  if (!(height < r))
    return; // the whole body lies beyond reach in front of the face's plane
  Vec3 foot;
  const bool over_face = dilated::over_triangle(triangle.corner[0], triangle.corner[1],
                                                triangle.corner[2], n, lowest, foot);
  const auto face_contact = [&] {
    FeatureContact contact;
    contact.overlap = r - height;
    contact.normal = -n;
    contact.point = 0.5 * (foot + r * n + lowest);
    contact.feature_a = core.numbering().face(f);
    contact.feature_b = 0;
    sink.add(contact);
  };
  if (over_face && height > -controls.tolerance) {
    face_contact(); // in front of the plane, or touching it to GJK's precision
    return;
  }
  const Vec3 face_centre =
      (1.0 / 3.0) * (triangle.corner[0] + triangle.corner[1] + triangle.corner[2]);
  controls.cutoff = r;
  const ConvexDistance between = convex_distance(support, triangle, centre - face_centre, controls);
  tally.iterations += between.iterations;
  tally.unconverged += between.status != 0 ? 1 : 0;
  if (between.intersecting) {
    ++tally.deep;
    if (over_face)
      face_contact();
    return;
  }
  if (!between.beyond(r))
    face_boundary_contacts(core, f, between.point_a, 0.0, slack, sink);
}

// The contacts of a dilated core with a convex body (support in the core's frame, `centre` and
// `reach`: a bounding sphere of the body), in the core's frame: normals from the body towards
// the core, feature_a the core's feature key, feature_b 0.
template <class Core, class Support, class Sink>
KOKKOS_INLINE_FUNCTION DilatedConvexTally dilated_convex_contacts(
    const Core& core, const Support& support, Vec3 centre, double reach,
    const ConvexDistanceControls& controls, const ConeSlack& slack, Sink& sink) {
  DilatedConvexTally tally;
  tally.tree_walk_complete = for_each_face_near(core, centre, core.dilation() + reach, [&](int f) {
    face_convex_contacts(core, f, support, centre, controls, slack, sink, tally);
  });
  return tally;
}

// The support of a body turned and moved into another frame: x_frame = rotation x_body +
// translation, the body's own support taking body-frame directions.
template <class Body> struct SupportInFrame {
  Body body;
  Mat3 rotation;
  Vec3 translation;
  KOKKOS_INLINE_FUNCTION Vec3 operator()(Vec3 d) const {
    return translation + rotation * body.support_local(transpose_times(rotation, d));
  }
};

} // namespace kdem
