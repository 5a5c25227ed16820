#pragma once
// Clumps (multi-superquadric particles, book Sect. 3.1; digest ch3 Sects. 1.2-1.5): a rigid body
// of sphere and superquadric elements placed in its principal frame. Contacts are found per
// element: each element of one body against each element (or the whole convex body) of the
// other, every touching pair a contact point of its own. Device-callable.
//
// Element contacts by kind: two spheres in closed form; a sphere against a superquadric or a
// poly-superquadric by the closest point; two superquadrics by the midway point; a superquadric
// against a poly-superquadric by the octant walk. A clump of spheres runs no Newton at all.
#include "poly_superquadric_contact.hpp"
#include "superquadric_contact.hpp"

namespace kdem {

// Most elements of one clump: a pair of clumps keeps at most this many contact points
// (PairContacts' cap), and a clump against a wall element as many.
constexpr int clump_max_elements = 16;

// One element of a clump template, in the clump's principal frame.
struct ClumpElementTemplate {
  SuperquadricShape shape;      // a sphere: a = b = c = its radius, n1 = n2 = 2
  Vec3 centre;                  // m, from the clump's centroid
  Mat3 axes;                    // columns: the element's axes in the principal frame
  double bounding_radius = 0;   // m, about the element's centre (a sphere: its radius)
  double equivalent_radius = 0; // m, of the sphere of the element's volume
  int is_sphere = 0;            // 1: contacts in closed form
};

// A sphere as one piece of a contact (a sphere particle, or a clump's sphere element).
struct SpherePiece {
  Vec3 centre;
  double radius = 0;
};

// A clump element placed in the world: its superquadric (a sphere element's too, for the
// closest-point solves) and what the element-pair tests need.
struct PlacedElement {
  PosedSuperquadric body;
  double bounding_radius = 0, equivalent_radius = 0;
  bool sphere = false;

  KOKKOS_INLINE_FUNCTION SpherePiece as_sphere() const {
    return SpherePiece{body.centre, body.shape.a};
  }
};

// Element e of a clump whose centroid is at `position` with principal axes `rotation`.
KOKKOS_INLINE_FUNCTION PlacedElement place_element(const ClumpElementTemplate& e, Vec3 position,
                                                   const Mat3& rotation) {
  return PlacedElement{
      PosedSuperquadric{e.shape, position + rotation * e.centre, rotation * e.axes},
      e.bounding_radius, e.equivalent_radius, e.is_sphere != 0};
}

namespace clump_contact {

// The same contact with the bodies in the other order: the normal turns, the curvatures swap,
// and the multiplier of the midway point becomes its inverse (grad F_j + (1/lambda^2) grad F_i =
// 0; the closest point's stored flag 1 stays 1).
KOKKOS_INLINE_FUNCTION MidwayState reversed(MidwayState s) {
  if (s.multiplier > 0)
    s.multiplier = 1.0 / s.multiplier;
  return s;
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult reversed(NarrowPhaseResult r) {
  r.geometry.normal = -r.geometry.normal;
  const double k = r.curvature_i;
  r.curvature_i = r.curvature_j;
  r.curvature_j = k;
  r.state = reversed(r.state);
  return r;
}

} // namespace clump_contact

// Contacts between two pieces (normal from b towards a, state in the order (a, b)): every
// combination of a sphere, a superquadric and a poly-superquadric that a clump can meet.
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const SpherePiece& a, const SpherePiece& b,
                                                       const MidwayState&,
                                                       const NarrowPhaseControls&) {
  NarrowPhaseResult r;
  r.geometry = sphere_sphere(a.centre, a.radius, b.centre, b.radius);
  r.curvature_i = 1.0 / a.radius;
  r.curvature_j = 1.0 / b.radius;
  if (!r.geometry.touching)
    r.separation = norm(a.centre - b.centre) - a.radius - b.radius;
  return r;
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const SpherePiece& a,
                                                       const PosedSuperquadric& b,
                                                       const MidwayState& start,
                                                       const NarrowPhaseControls& controls) {
  return sphere_superquadric_contact(a.centre, a.radius, b, start, controls);
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const PosedSuperquadric& a,
                                                       const SpherePiece& b,
                                                       const MidwayState& start,
                                                       const NarrowPhaseControls& controls) {
  using namespace clump_contact;
  return reversed(sphere_superquadric_contact(b.centre, b.radius, a, reversed(start), controls));
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const PosedSuperquadric& a,
                                                       const PosedSuperquadric& b,
                                                       const MidwayState& start,
                                                       const NarrowPhaseControls& controls) {
  return superquadric_pair_contact(a, b, start, controls);
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const PosedPolySuperquadric& a,
                                                       const SpherePiece& b,
                                                       const MidwayState& start,
                                                       const NarrowPhaseControls& controls) {
  using namespace clump_contact;
  return reversed(
      sphere_poly_superquadric_contact(b.centre, b.radius, a, reversed(start), controls));
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const PosedPolySuperquadric& a,
                                                       const PosedSuperquadric& b,
                                                       const MidwayState& start,
                                                       const NarrowPhaseControls& controls) {
  return piecewise_pair_contact(a, b, start, controls);
}

// A piece against a clump element, by the element's kind.
template <class PieceA>
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const PieceA& a, const PlacedElement& b,
                                                       const MidwayState& start,
                                                       const NarrowPhaseControls& controls) {
  return b.sphere ? piece_contact(a, b.as_sphere(), start, controls)
                  : piece_contact(a, b.body, start, controls);
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult piece_contact(const PlacedElement& a,
                                                       const PlacedElement& b,
                                                       const MidwayState& start,
                                                       const NarrowPhaseControls& controls) {
  return a.sphere ? piece_contact(a.as_sphere(), b, start, controls)
                  : piece_contact(a.body, b, start, controls);
}

// Whether a piece's contact needs an iterative solve (counted in the narrow-phase tally).
KOKKOS_INLINE_FUNCTION bool iterative_pair(const SpherePiece&, const PlacedElement& b) {
  return !b.sphere;
}
KOKKOS_INLINE_FUNCTION bool iterative_pair(const PlacedElement& a, const PlacedElement& b) {
  return !(a.sphere && b.sphere);
}
template <class PieceA>
KOKKOS_INLINE_FUNCTION bool iterative_pair(const PieceA&, const PlacedElement&) {
  return true;
}

// --- Seams ---------------------------------------------------------------------------------------
// Where two elements of one clump overlap, a body touching the union near their seam touches
// both, and the two element contacts describe one contact region (digest ch3 Sect. 1.5): summed,
// the force there would be about doubled. Dropping one of them (the digest's options (b), a
// contact whose surface point is buried in another element, and (c), keeping the deepest of
// contacts that nearly coincide) removes a contact that still has a finite overlap, so the force
// jumps as a contact slides across a seam. Instead each contact's force is weighted by
//   w_c = delta_c / (delta_c + sum_{c' != c} kappa(c, c') delta_c'),
// kappa in [0, 1] a smooth measure of how much c and c' are one contact (1 where their points
// and normals coincide, 0 from a distance `seam_distance` x the smaller element size or an angle
// `seam_angle` on). Coinciding contacts of equal depth share the force (w = 1/2 each), separate
// ones keep theirs (w = 1), and a contact that appears or fades does so from zero: every weight
// is continuous in the bodies' poses, so the force is too.
struct SeamSettings {
  bool weighted = true;         // false: contacts summed as found (the usual clump practice)
  double distance = 0.5;        // of the smaller element size (equivalent radius)
  double cos_angle = 0.8660254; // cos 30 degrees
};

// How much two contacts are one: their points' distance against `reach`, their normals' angle
// against the settings'.
KOKKOS_INLINE_FUNCTION double seam_kernel(const ContactGeometry& a, const ContactGeometry& b,
                                          double reach, const SeamSettings& seam) {
  const double alignment = dot(a.normal, b.normal);
  if (!(alignment > seam.cos_angle))
    return 0;
  return math::falloff(norm(a.point - b.point) / reach) *
         math::falloff((1.0 - alignment) / (1.0 - seam.cos_angle));
}

// The weights of `count` contacts (geometry(c), size(c): the smaller equivalent radius of its two
// pieces) into weight(c).
template <class GeometryOf, class SizeOf, class SetWeight>
KOKKOS_INLINE_FUNCTION void seam_weights(int count, const GeometryOf& geometry, const SizeOf& size,
                                         const SeamSettings& seam, const SetWeight& set_weight) {
  for (int c = 0; c < count; ++c) {
    const ContactGeometry& gc = geometry(c);
    double shared = gc.overlap;
    if (seam.weighted)
      for (int d = 0; d < count; ++d) {
        if (d == c)
          continue;
        const double reach = seam.distance * math::min(size(c), size(d));
        shared += seam_kernel(gc, geometry(d), reach, seam) * geometry(d).overlap;
      }
    set_weight(c, shared > 0 ? gc.overlap / shared : 1.0);
  }
}

} // namespace kdem
