#pragma once
// Walls: analytic planes and cylinders and triangle meshes, each moving rigidly. Each wall is
// stored once in its reference frame; a particle centre is taken into that frame, queried, and
// the contact is taken back to the world frame.
#include <type_traits>

#include "../shapes/wall_geometry.hpp"
#include "binning.hpp"
#include "contact_law.hpp"
#include "contact_slots.hpp"
#include "particles.hpp"
#include "ragged_table.hpp"
#include "view_access.hpp"
#include "wall_bins.hpp"

namespace kdem {

enum WallElementKind : int { plane_element = 0, cylinder_element = 1, triangle_element = 2 };

// Rigid motion of a wall: x(t) = pivot + velocity tau + R(omega tau) (X - pivot),
// tau = max(0, t - start), and the wall takes part in contacts for active_from <= t < active_until.
struct WallMotion {
  Vec3 pivot;
  Vec3 velocity; // m/s
  Vec3 omega;    // rad/s
  double start = 0, active_from = 0, active_until = 1e300;
  int material = 0;
};

struct WallPose {
  Quat rotation;
  Vec3 offset; // current position of the pivot
  Vec3 pivot;
  Vec3 velocity, omega;
  int active = 1;
  int material = 0;

  KOKKOS_INLINE_FUNCTION Vec3 to_reference(Vec3 x) const {
    return pivot + rotate_inverse(rotation, x - offset);
  }
  KOKKOS_INLINE_FUNCTION Vec3 to_world(Vec3 x_ref) const {
    return offset + rotate(rotation, x_ref - pivot);
  }
  KOKKOS_INLINE_FUNCTION Vec3 velocity_at(Vec3 x) const {
    return velocity + cross(omega, x - offset);
  }
};

KOKKOS_INLINE_FUNCTION WallPose wall_pose_at(const WallMotion& m, double time) {
  WallPose pose;
  const double tau = time > m.start ? time - m.start : 0.0;
  pose.rotation = quat_from_rotation_vector(tau * m.omega);
  pose.pivot = m.pivot;
  pose.offset = m.pivot + tau * m.velocity;
  pose.velocity = m.velocity;
  pose.omega = m.omega;
  pose.active = (time >= m.active_from && time < m.active_until) ? 1 : 0;
  pose.material = m.material;
  return pose;
}

// Geometry of all wall elements, flattened. Triangles carry mesh topology so that a sphere near
// a mesh gets exactly one contact per surface patch it touches: every centre position is
// claimed by one feature (a face, an edge or a vertex) of the mesh, through tests that read the
// same stored numbers from whichever triangle evaluates them (see claimed_triangle_feature).
struct WallElements {
  int count = 0;
  IndexView kind;
  IndexView wall;
  // Per element in one row, as a triangle's contact reads it first (reference frame): plane:
  // origin, normal | cylinder: base, axis, radius, length | triangle: a, b, c, then per edge (ab,
  // bc, ca) the position of its first vertex and its edge_outward from the triangle's side.
  DeviceView<double* [27]> geometry;
  DeviceView<int* [6]> features;        // triangle: edge ids ab, bc, ca; vertex ids a, b, c
  double feature_tolerance = 0;         // m, width of the band that decides between features
  IndexView edge_owner;                 // lowest-indexed adjacent triangle: the one that reports
  IndexView edge_sides;                 // 1 or 2 adjacent triangles (side 0 is the owner)
  DeviceView<double* [6]> edge_outward; // per side: unit in-plane direction away from it
  DeviceView<int* [2]> edge_vertices;
  Vec3View edge_direction; // unit, from edge_vertices 0 to 1
  IndexView vertex_owner;
  Vec3View vertex_position;
  IndexView vertex_edge_start;     // CSR over vertices
  Vec3View vertex_edge_direction;  // unit vectors from the vertex along its edges
  IndexView vertex_triangle_start; // CSR over vertices
  IndexView vertex_triangle;       // elements around the vertex
  // For bodies that are not spheres (their families' wall contact): stored triangle normals, the
  // triangles of each edge, corner flags and the ring of neighbour vertices of each vertex.
  Vec3View triangle_normal;
  DeviceView<int* [2]> edge_triangles;
  IndexView vertex_corner;
  IndexView vertex_ring_start;
  DeviceView<Vec3*> vertex_ring;
};

// Walls, their motions and poses now, and where to look for their elements near a point (per
// wall, see kernels/wall_bins.hpp; cells: the element ids of each grid cell).
struct WallSet {
  int wall_count = 0;
  WallElements elements;
  DeviceView<WallMotion*> motion;
  DeviceView<WallPose*> pose;
  DeviceView<WallLookup*> lookup;
  RaggedTable<int> cells;
};

inline void update_wall_poses(const WallSet& walls, double time) {
  auto motion = walls.motion;
  auto pose = walls.pose;
  Kokkos::parallel_for(
      "kdem::wall_poses", RangePolicy(0, walls.wall_count),
      KOKKOS_LAMBDA(int w) { pose(w) = wall_pose_at(motion(w), time); });
}

KOKKOS_INLINE_FUNCTION Vec3 geometry_vec(const DeviceView<double* [27]>& g, int e, int first) {
  return {g(e, first), g(e, first + 1), g(e, first + 2)};
}

KOKKOS_INLINE_FUNCTION SurfaceQuery cylinder_query(const WallElements& el, int e, Vec3 p,
                                                   bool& in_range) {
  double along = 0;
  const SurfaceQuery q =
      cylinder_inside_query(geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3),
                            el.geometry(e, 6), p, along);
  in_range = along >= 0 && along <= el.geometry(e, 7);
  return q;
}

KOKKOS_INLINE_FUNCTION Vec3 edge_outward_of(const WallElements& el, int edge, int side) {
  return {el.edge_outward(edge, 3 * side), el.edge_outward(edge, 3 * side + 1),
          el.edge_outward(edge, 3 * side + 2)};
}

// How far p lies beyond the plane through `start` with the unit normal `direction`: the one
// computation of every claim test, in one compiled copy (see KDEM_ONE_COPY_FUNCTION), so that the
// face, edge and vertex tests of two triangles, and a certificate's shortcut, see a tie alike.
KDEM_ONE_COPY_FUNCTION double signed_beyond(Vec3 p, Vec3 start, Vec3 direction) {
  return dot(p - start, direction);
}

// Signed in-plane distance of p's projection beyond `edge`, seen from the triangle on `side`.
KOKKOS_INLINE_FUNCTION double beyond_edge(const WallElements& el, int edge, int side, Vec3 p) {
  return signed_beyond(p, load3(el.vertex_position, el.edge_vertices(edge, 0)),
                       edge_outward_of(el, edge, side));
}

// p projects into triangle e deeper than the tolerance from each of its edges. The same numbers
// as beyond_edge from e's side, read from e's own geometry row rather than through its edges: on
// a large mesh the chain of indirect loads is what a face test costs.
KOKKOS_INLINE_FUNCTION bool face_claims(const WallElements& el, int e, Vec3 p) {
  for (int k = 0; k < 3; ++k) {
    const Vec3 start = geometry_vec(el.geometry, e, 9 + 6 * k);
    const Vec3 outward = geometry_vec(el.geometry, e, 12 + 6 * k);
    if (!(signed_beyond(p, start, outward) < -el.feature_tolerance))
      return false;
  }
  return true;
}

// By how much p is inside the band face_claims tests (positive where, and only where, the face
// claims p: a difference of two doubles has the sign of their exact difference). Each term is
// 1-Lipschitz in p (unit directions), so the face claims every point nearer to p than that.
KOKKOS_INLINE_FUNCTION double face_claim_margin(const WallElements& el, int e, Vec3 p) {
  double margin = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 start = geometry_vec(el.geometry, e, 9 + 6 * k);
    const Vec3 outward = geometry_vec(el.geometry, e, 12 + 6 * k);
    const double inside = -el.feature_tolerance - signed_beyond(p, start, outward);
    margin = k == 0 || inside < margin ? inside : margin;
  }
  return margin;
}

// p projects onto no adjacent face, and along the edge further than the tolerance from its ends.
KOKKOS_INLINE_FUNCTION bool edge_claims(const WallElements& el, int edge, Vec3 p) {
  const double tol = el.feature_tolerance;
  for (int side = 0; side < el.edge_sides(edge); ++side)
    if (beyond_edge(el, edge, side, p) < -tol)
      return false;
  const Vec3 d = load3(el.edge_direction, edge);
  const Vec3 a = load3(el.vertex_position, el.edge_vertices(edge, 0));
  const Vec3 b = load3(el.vertex_position, el.edge_vertices(edge, 1));
  return signed_beyond(p, a, d) > tol && signed_beyond(p, b, -d) > tol;
}

// The fallback: p projects beyond no edge leaving the vertex and into no face around it.
KOKKOS_INLINE_FUNCTION bool vertex_claims(const WallElements& el, int vertex, Vec3 p) {
  const Vec3 v = load3(el.vertex_position, vertex);
  for (int k = el.vertex_edge_start(vertex); k < el.vertex_edge_start(vertex + 1); ++k)
    if (signed_beyond(p, v, load3(el.vertex_edge_direction, k)) > el.feature_tolerance)
      return false;
  for (int k = el.vertex_triangle_start(vertex); k < el.vertex_triangle_start(vertex + 1); ++k)
    if (face_claims(el, el.vertex_triangle(k), p))
      return false;
  return true;
}

KOKKOS_INLINE_FUNCTION SurfaceQuery point_feature_query(Vec3 point, Vec3 p, Vec3 fallback_normal,
                                                        int feature) {
  SurfaceQuery q;
  q.point = point;
  q.feature = feature;
  const Vec3 d = p - point;
  q.signed_distance = norm(d);
  q.free_normal = q.signed_distance > 0 ? (1.0 / q.signed_distance) * d : fallback_normal;
  return q;
}

// Triangle e's corners, its unit normal (from the corners, in their order) and the height of p
// above its plane along that normal.
struct TrianglePlane {
  Vec3 a, b, c, normal;
  double height = 0;
};

// Compiled once, like face_point_query: the full claim test and a face certificate's shortcut
// see the same plane.
KDEM_ONE_COPY_FUNCTION TrianglePlane triangle_plane(Vec3 a, Vec3 b, Vec3 c, Vec3 p) {
  TrianglePlane t;
  t.a = a, t.b = b, t.c = c;
  const Vec3 normal_raw = cross(t.b - t.a, t.c - t.a);
  t.normal = (1.0 / norm(normal_raw)) * normal_raw;
  t.height = dot(p - t.a, t.normal);
  return t;
}

KOKKOS_INLINE_FUNCTION TrianglePlane triangle_plane(const WallElements& el, int e, Vec3 p) {
  return triangle_plane(geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3),
                        geometry_vec(el.geometry, e, 6), p);
}

// The contact of p with the face of plane t (its foot on the plane), in one compiled copy: the
// full claim test and a face certificate's shortcut give it bit for bit.
KDEM_ONE_COPY_FUNCTION SurfaceQuery face_point_query(const TrianglePlane& t, Vec3 p) {
  return point_feature_query(p - t.height * t.normal, p, t.height >= 0 ? t.normal : -t.normal, 0);
}

// The feature of triangle e that claims p, if e reports it and it lies within `reach` of p:
// its face, or an edge or vertex that e owns. A centre is claimed by exactly one feature of a
// mesh (up to the edge cases of a tolerance band at obtuse corners, where it may be claimed by
// none), and the owner of an edge or vertex is unique, so a sphere gets one contact per feature
// it touches. Features beyond the reach (by a margin far above rounding) are not tested: they
// could only give a contact that does not touch, and on a fine mesh most candidates are such.
KOKKOS_INLINE_FUNCTION SurfaceQuery claimed_triangle_feature(const WallElements& el, int e, Vec3 p,
                                                             double reach, bool& applies) {
  const TrianglePlane t = triangle_plane(el, e, p);
  const Vec3 facing = t.height >= 0 ? t.normal : -t.normal;
  const double beyond = reach * (1 + 1e-9);
  applies = false;
  // Every feature of e lies in e: nearer than e, none can touch. The distance to e needs no
  // topology, which on a large mesh is what the memory traffic is.
  if (!(triangle_query(t.a, t.b, t.c, p).signed_distance < beyond))
    return SurfaceQuery{};
  applies = true;
  if (face_claims(el, e, p))
    return face_point_query(t, p);
  for (int k = 0; k < 3; ++k) {
    const int edge = el.features(e, k);
    if (el.edge_owner(edge) != e)
      continue;
    const Vec3 start = load3(el.vertex_position, el.edge_vertices(edge, 0));
    const Vec3 d = load3(el.edge_direction, edge);
    const Vec3 on_line = start + dot(p - start, d) * d;
    if (!(norm2(p - on_line) < beyond * beyond) || !edge_claims(el, edge, p))
      continue;
    return point_feature_query(on_line, p, facing, 1 + k);
  }
  for (int k = 0; k < 3; ++k) {
    const int vertex = el.features(e, 3 + k);
    if (el.vertex_owner(vertex) != e)
      continue;
    const Vec3 v = load3(el.vertex_position, vertex);
    if (!(norm2(p - v) < beyond * beyond) || !vertex_claims(el, vertex, p))
      continue;
    return point_feature_query(v, p, facing, 4 + k);
  }
  applies = false;
  return SurfaceQuery{};
}

// Closest point of element e to the reference-frame point p. `applies` is false when the
// element does not take part (outside a cylinder's length, a feature another triangle reports
// or one beyond `reach`).
KOKKOS_INLINE_FUNCTION SurfaceQuery query_element(const WallElements& el, int e, Vec3 p,
                                                  double reach, bool& applies) {
  applies = true;
  switch (el.kind(e)) {
  case plane_element:
    return plane_query(geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3), p);
  case cylinder_element:
    return cylinder_query(el, e, p, applies);
  default:
    return claimed_triangle_feature(el, e, p, reach, applies);
  }
}

// Particle-wall candidates: elements within reach (radius + skin), per particle, with history.
// Per particle its candidate wall elements (entries), and per entry its contact slots (see
// ContactSlots: one slot per entry unless a family present may touch one element at several
// points), each with its history keyed by the particle's feature that touches.
struct WallContactList {
  int entry_count = 0;
  IndexView row_start; // particle_count + 1
  IndexView element;
  IdView element_key;      // element index as a key for history transfer
  IndexView contact_start; // entry_count + 1, or empty: slot k of entry k
  int slot_count = 0;
  IndexView feature;          // per slot, of the particle; -1: free; empty with one slot each
  Vec3View tangential_spring; // per slot
  Vec3View rolling_torque;    // per slot; empty when no material pair has rolling resistance
  ScalarView overlap;         // per slot, m, 0 when not touching; then its history is 0 too
  // Per entry, this step: the sum of its contacts' forces, N, and torques about the particle's
  // centre, N m; summed per particle by sum_forces.
  Vec3View force_on_i;
  Vec3View torque_on_i;
  // Per entry, a copy of its triangle's corners (reference frame; zero for other elements;
  // empty in scenes without triangles),
  // derived from `element` whenever the list is made or read (copy_triangle_corners): the
  // contact kernel rules out a triangle beyond the particle's bounding radius from the entry
  // alone, without a load from the triangle's row, which on a large mesh is a cache miss.
  DeviceView<double* [9]> triangle_corners;
  // Per triangle entry, a certificate that its face claims a sphere's centre: a reference-frame
  // point where the face claimed it and the margin by which it did (columns 0-2, 3; margin 0:
  // none yet). Every point within half the margin is claimed too (see
  // certified_triangle_feature). Made by the contact kernel, zero in a new or read list.
  DeviceView<double* [4]> face_certificate;

  ContactSlots slots() const { return ContactSlots{contact_start}; }
  bool one_slot_per_entry() const { return contact_start.extent(0) == 0; }
};

// The fields a checkpoint keeps; force_on_i and torque_on_i are not among them, as every step
// computes them anew before sum_forces reads them.
template <class Visitor> void for_each_wall_contact_field(Visitor&& visit) {
  visit("row_start", &WallContactList::row_start);
  visit("element", &WallContactList::element);
  visit("element_key", &WallContactList::element_key);
  visit("contact_start", &WallContactList::contact_start);
  visit("feature", &WallContactList::feature);
  visit("tangential_spring", &WallContactList::tangential_spring);
  visit("rolling_torque", &WallContactList::rolling_torque);
  visit("overlap", &WallContactList::overlap);
}

KOKKOS_INLINE_FUNCTION bool element_within_reach(const WallElements& el, int e, Vec3 p,
                                                 double reach) {
  if (el.kind(e) == cylinder_element) {
    double along = 0;
    const SurfaceQuery q =
        cylinder_inside_query(geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3),
                              el.geometry(e, 6), p, along);
    return along >= -reach && along <= el.geometry(e, 7) + reach && q.signed_distance < reach;
  }
  if (el.kind(e) == plane_element)
    return plane_query(geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3), p)
               .signed_distance < reach;
  return triangle_query(geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3),
                        geometry_vec(el.geometry, e, 6), p)
             .signed_distance < reach;
}

// Scenes without mesh walls (no edges) keep no copies: the kernel reads them only for
// triangle entries.
inline void copy_triangle_corners(WallContactList& list, const WallElements& el) {
  const bool has_triangles = el.edge_owner.extent(0) > 0;
  list.triangle_corners =
      DeviceView<double* [9]>("wall_triangle_corners", has_triangles ? list.entry_count : 0);
  list.face_certificate =
      DeviceView<double* [4]>("wall_face_certificate", has_triangles ? list.entry_count : 0);
  if (!has_triangles)
    return;
  auto corners = list.triangle_corners;
  auto element = list.element;
  Kokkos::parallel_for(
      "kdem::wall_triangle_corners", RangePolicy(0, list.entry_count), KOKKOS_LAMBDA(int k) {
        const int e = element(k);
        if (el.kind(e) == triangle_element)
          for (int c = 0; c < 9; ++c)
            corners(k, c) = el.geometry(e, c);
      });
}

// Whether the triangle of entry k lies farther from the reference-frame centre p than a
// particle of bounding radius r reaches, by the test claimed_triangle_feature makes first (so
// that a sphere's contact is the same with or without this test).
KOKKOS_INLINE_FUNCTION Vec3 entry_corner(const DeviceView<double* [9]>& corners, int k, int v) {
  return {corners(k, 3 * v), corners(k, 3 * v + 1), corners(k, 3 * v + 2)};
}

KOKKOS_INLINE_FUNCTION bool triangle_out_of_reach(const DeviceView<double* [9]>& corners, int k,
                                                  Vec3 p, double r) {
  return !(triangle_query(entry_corner(corners, k, 0), entry_corner(corners, k, 1),
                          entry_corner(corners, k, 2), p)
               .signed_distance < r * (1 + 1e-9));
}

// The copies a triangle entry k keeps (see WallContactList::triangle_corners and
// face_certificate).
struct TriangleEntry {
  DeviceView<double* [9]> corners;
  DeviceView<double* [4]> certificate;
  int k = 0;
};

// claimed_triangle_feature of entry k's triangle e, for a sphere of radius `reach` whose
// triangle distance the caller found below the reach (triangle_out_of_reach). Where the entry's
// certificate holds (p within half its margin of its point, the margin far above rounding:
// face_claim_margin), the face claims p, and its query is made from the corner copy alone, by
// the same operations on the same numbers as claimed_triangle_feature's: the same contact
// without a load from the triangle's row. Otherwise the full test, and a face claim leaves a
// new certificate. A certificate stays true as long as the mesh is the same: it speaks of the
// triangle's face in its wall's frame, not of a time.
KOKKOS_INLINE_FUNCTION SurfaceQuery certified_triangle_feature(const WallElements& el,
                                                               const TriangleEntry& entry, int e,
                                                               Vec3 p, double reach,
                                                               bool& applies) {
  const int k = entry.k;
  const double margin = entry.certificate(k, 3);
  const Vec3 claimed_at{entry.certificate(k, 0), entry.certificate(k, 1), entry.certificate(k, 2)};
  if (margin > 0 && norm2(p - claimed_at) < 0.25 * margin * margin) {
    const TrianglePlane t =
        triangle_plane(entry_corner(entry.corners, k, 0), entry_corner(entry.corners, k, 1),
                       entry_corner(entry.corners, k, 2), p);
    // Claimed by the face, p's distance to the triangle is its height (up to rounding, which
    // decides nothing here: beyond the radius no contact touches).
    applies = math::fabs(t.height) < reach * (1 + 1e-9);
    if (!applies)
      return SurfaceQuery{};
    return face_point_query(t, p);
  }
  const SurfaceQuery q = claimed_triangle_feature(el, e, p, reach, applies);
  if (applies && q.feature == 0) {
    const double new_margin = face_claim_margin(el, e, p);
    if (new_margin > 1e-6 * reach) { // rounding of the tests is below 1e-12 of a metre-sized mesh
      entry.certificate(k, 0) = p.x, entry.certificate(k, 1) = p.y, entry.certificate(k, 2) = p.z;
      entry.certificate(k, 3) = new_margin;
    }
  }
  return q;
}

// The per-entry results and derived copies of a list whose entries are set.
inline void allocate_wall_contact_results(WallContactList& list, const WallElements& el) {
  list.force_on_i = Vec3View("wall_force", list.entry_count);
  list.torque_on_i = Vec3View("wall_torque", list.entry_count);
  copy_triangle_corners(list, el);
}

// Gives the entries of particle i slots_of(i) contact slots each (count, scan); without this
// every entry has one.
template <class SlotsOf>
void assign_wall_contact_slots(WallContactList& list, int particle_count, SlotsOf slots_of) {
  IndexView counts = uninitialized<IndexView>("wall_slot_count", list.entry_count);
  auto row_start = list.row_start;
  Kokkos::parallel_for(
      "kdem::wall_slot_count", RangePolicy(0, particle_count), KOKKOS_LAMBDA(int i) {
        for (int k = row_start(i); k < row_start(i + 1); ++k)
          counts(k) = slots_of(i);
      });
  list.contact_start = exclusive_scan_with_total(counts, list.slot_count);
}

// The contact state of a wall list: per slot its history, per entry its force and torque.
inline void allocate_wall_contacts(WallContactList& list, const WallElements& el,
                                   bool rolling_state) {
  if (list.one_slot_per_entry())
    list.slot_count = list.entry_count;
  const int slots = list.slot_count;
  if (!list.one_slot_per_entry()) {
    list.feature = IndexView("wall_contact_feature", slots);
    Kokkos::deep_copy(list.feature, -1);
  }
  list.tangential_spring = Vec3View("wall_tangential_spring", slots);
  if (rolling_state)
    list.rolling_torque = Vec3View("wall_rolling_torque", slots);
  list.overlap = ScalarView("wall_overlap", slots);
  allocate_wall_contact_results(list, el);
}

KOKKOS_INLINE_FUNCTION double segment_distance(Vec3 a, Vec3 b, Vec3 p) {
  const Vec3 ab = b - a;
  const double t = dot(p - a, ab) / norm2(ab);
  return norm(p - (a + (t < 0 ? 0.0 : t > 1 ? 1.0 : t) * ab));
}

// Whether triangle e may give a sphere of radius r a touching contact (through its face or a
// feature it reports, see claimed_triangle_feature) while the sphere's centre stays within
// `drift` of p. Each condition below is necessary for such a claim at some point within drift of
// p: the claims' tests move by at most the drift (projections and distances to features are
// 1-Lipschitz), the tolerance band is added, and a relative margin covers rounding. On a fine
// mesh a sphere is within its reach of many triangles, but few of them can claim it.
KOKKOS_INLINE_FUNCTION bool triangle_may_touch(const WallElements& el, int e, Vec3 p, double r,
                                               double drift) {
  const double margin = 1e-9 * (r + drift);
  const double band = drift + el.feature_tolerance + margin; // slack of the claims' tests
  const double touch = r + drift + margin;                   // of the distances
  const TrianglePlane t = triangle_plane(el, e, p);
  if (!(math::fabs(t.height) < touch))
    return false;
  if (triangle_query(t.a, t.b, t.c, p - t.height * t.normal).signed_distance <= band)
    return true; // the face may claim it
  for (int k = 0; k < 3; ++k) {
    const int edge = el.features(e, k);
    if (el.edge_owner(edge) != e)
      continue;
    bool beyond_faces = true;
    for (int side = 0; side < el.edge_sides(edge); ++side)
      beyond_faces = beyond_faces && beyond_edge(el, edge, side, p) >= -band;
    const Vec3 start = load3(el.vertex_position, el.edge_vertices(edge, 0));
    const Vec3 end = load3(el.vertex_position, el.edge_vertices(edge, 1));
    if (beyond_faces && segment_distance(start, end, p) < touch)
      return true;
  }
  for (int k = 0; k < 3; ++k) {
    const int vertex = el.features(e, 3 + k);
    if (el.vertex_owner(vertex) != e)
      continue;
    const Vec3 v = load3(el.vertex_position, vertex);
    bool beyond_edges = norm(p - v) < touch;
    for (int m = el.vertex_edge_start(vertex); m < el.vertex_edge_start(vertex + 1); ++m)
      beyond_edges = beyond_edges && dot(p - v, load3(el.vertex_edge_direction, m)) <= band;
    if (beyond_edges)
      return true;
  }
  return false;
}

// Calls found(e) for every element within `reach` of world point x, walls and elements in
// ascending order, each tested in its wall's reference frame at the wall's pose now. For a
// sphere of radius r (point_contact; reach = r + drift), triangles that cannot claim it while
// it drifts are left out.
template <class Found>
KOKKOS_INLINE_FUNCTION void for_each_element_within_reach(const WallSet& walls, Vec3 x, double r,
                                                          double drift, bool point_contact,
                                                          Found&& found) {
  const double reach = r + drift;
  for (int w = 0; w < walls.wall_count; ++w) {
    const Vec3 p = walls.pose(w).to_reference(x);
    for_each_candidate_element(walls.lookup(w), walls.cells, p, reach, [&](int e) {
      if (!element_within_reach(walls.elements, e, p, reach))
        return;
      if (point_contact && walls.elements.kind(e) == triangle_element &&
          !triangle_may_touch(walls.elements, e, p, r, drift))
        return;
      found(e);
    });
  }
}

// The candidate elements of each particle; no contact state yet (see allocate_wall_contacts).
// Particles of shape sphere_shape touch a mesh through the feature that claims their centre
// (SphereWallContact), and skin bounds how far a centre moves against a wall before the next
// build: their lists hold only the triangles that may claim them meanwhile.
inline WallContactList build_wall_contact_list(const ParticleViews& p, const WallSet& walls,
                                               double skin, int sphere_shape) {
  const int n = p.count;
  WallContactList list;
  IndexView counts("wall_candidate_count", n);
  auto x = p.position;
  auto radius = p.radius;
  auto shape = p.shape;
  Kokkos::parallel_for(
      "kdem::wall_candidate_count", RangePolicy(0, n), KOKKOS_LAMBDA(int i) {
        int found = 0;
        for_each_element_within_reach(walls, load3(x, i), radius(i), skin, shape(i) == sphere_shape,
                                      [&](int) { ++found; });
        counts(i) = found;
      });
  list.row_start = exclusive_scan_with_total(counts, list.entry_count);
  const int entries = list.entry_count;
  list.element = uninitialized<IndexView>("wall_candidate_element", entries);
  list.element_key = uninitialized<IdView>("wall_candidate_key", entries);
  auto row_start = list.row_start;
  auto element = list.element;
  auto key = list.element_key;
  Kokkos::parallel_for(
      "kdem::wall_candidate_fill", RangePolicy(0, n), KOKKOS_LAMBDA(int i) {
        int slot = row_start(i);
        for_each_element_within_reach(walls, load3(x, i), radius(i), skin, shape(i) == sphere_shape,
                                      [&](int e) {
                                        element(slot) = e;
                                        key(slot) = e;
                                        ++slot;
                                      });
      });
  return list;
}

// Wall rows are per particle; history moves by (particle id, element), slot by slot (with its
// feature; a list with one slot per entry has feature 0).
inline void transfer_wall_history(WallContactList& fresh, const WallContactList& old,
                                  const IndexView& old_row_of_id, const IdView& id,
                                  int particle_count) {
  auto row_start = fresh.row_start;
  auto key = fresh.element_key;
  const ContactSlots slots = fresh.slots(), old_slots = old.slots();
  auto spring = fresh.tangential_spring, rolling = fresh.rolling_torque;
  auto feature = fresh.feature, old_feature = old.feature;
  auto old_start = old.row_start;
  auto old_key = old.element_key;
  auto old_spring = old.tangential_spring, old_rolling = old.rolling_torque;
  const bool copy_rolling = rolling.extent(0) > 0 && old_rolling.extent(0) > 0;
  const bool keyed = !fresh.one_slot_per_entry(), old_keyed = !old.one_slot_per_entry();
  Kokkos::parallel_for(
      "kdem::wall_history_transfer", RangePolicy(0, particle_count), KOKKOS_LAMBDA(int i) {
        const int old_row = old_row_of_id(id(i));
        for (int k = row_start(i); k < row_start(i + 1); ++k) {
          const int found = find_in_row(old_start, old_key, old_row, key(k));
          if (found < 0)
            continue;
          const int fresh_count = slots.end(k) - slots.first(k);
          const int old_count = old_slots.end(found) - old_slots.first(found);
          const int shared = fresh_count < old_count ? fresh_count : old_count;
          for (int c = 0; c < shared; ++c) {
            const int to = slots.first(k) + c, from = old_slots.first(found) + c;
            for (int d = 0; d < 3; ++d)
              spring(to, d) = old_spring(from, d);
            if (copy_rolling)
              for (int d = 0; d < 3; ++d)
                rolling(to, d) = old_rolling(from, d);
            if (keyed)
              feature(to) = old_keyed ? old_feature(from) : 0;
          }
        }
      });
}

// A particle-wall contact in the world frame, with the Hertz radius it gets and the feature of
// the particle that touches (0 for bodies with one contact point).
struct WallContactGeometry {
  ContactGeometry geometry;
  double effective_radius = 0; // m
  int feature = 0;
  double weight = 1; // scales its force (see PairContact)
};

// Up to K contacts of one particle with one wall element; only the first `count` are set (see
// PairContacts), a functor of several appends with add().
template <int K> struct WallContacts {
  int count = 0;
  union {
    WallContactGeometry contact[K];
  };

  KOKKOS_INLINE_FUNCTION WallContacts() {}
  KOKKOS_INLINE_FUNCTION WallContactGeometry& add() {
    contact[count] = WallContactGeometry{};
    return contact[count++];
  }
};

// The contact law of particle i at a contact with a wall at `wall`; advances `history` and gives
// the contact's torque on i about its centre.
template <class Law>
KOKKOS_INLINE_FUNCTION ContactOutput wall_contact_law(const ParticleViews& p, int i,
                                                      const WallPose& wall,
                                                      const WallContactGeometry& contact,
                                                      const CoefficientTable& table, double dt,
                                                      ContactHistory& history, Vec3& torque) {
  const Vec3 xi = load3(p.position, i), vi = load3(p.velocity, i),
             wi = load3(p.angular_velocity, i);
  ContactInput in;
  in.geometry = contact.geometry;
  const Vec3 point = in.geometry.point;
  in.relative_velocity = point_velocity(vi, wi, xi, point) - wall.velocity_at(point);
  in.relative_angular_velocity = wi - wall.omega;
  in.effective_radius = contact.effective_radius;
  in.effective_mass = p.mass(i);
  const ContactOutput out = Law::force(table(p.material(i), wall.material), in, dt, history);
  torque = cross(point - xi, out.force_on_i) + out.rolling_torque_on_i;
  return out;
}

// The per-slot and per-entry values a wall contact writes.
struct WallSlots {
  ContactSlots slots;
  Vec3View spring, rolling, force_on_i, torque_on_i;
  ScalarView overlap;
  IndexView feature;

  explicit WallSlots(const WallContactList& list)
      : slots(list.slots()), spring(list.tangential_spring), rolling(list.rolling_torque),
        force_on_i(list.force_on_i), torque_on_i(list.torque_on_i), overlap(list.overlap),
        feature(list.feature) {}

  KOKKOS_INLINE_FUNCTION void clear_slot(int s) const {
    store3(spring, s, Vec3{});
    if (rolling.extent(0) > 0)
      store3(rolling, s, Vec3{});
    overlap(s) = 0;
    if (!slots.single())
      feature(s) = -1;
  }

  template <class Law> KOKKOS_INLINE_FUNCTION ContactHistory history_of(int s) const {
    ContactHistory history{load3(spring, s), Vec3{}};
    if constexpr (Law::rolling)
      history.rolling_torque = load3(rolling, s);
    return history;
  }

  template <class Law>
  KOKKOS_INLINE_FUNCTION void keep(int s, const ContactHistory& history, double overlap_now) const {
    store3(spring, s, history.tangential_spring);
    if constexpr (Law::rolling)
      store3(rolling, s, history.rolling_torque);
    overlap(s) = overlap_now;
  }
};

// Whether a family's wall-contact functor takes the triangle entry (SphereWallContact).
template <class T, class = void> struct certifies_faces : std::false_type {};
template <class T>
struct certifies_faces<T, std::void_t<decltype(T::certifies_faces)>>
    : std::integral_constant<bool, T::certifies_faces> {};

// The contacts of particle i with element e (of list entry `entry`) of a wall at `wall`: a
// functor of one contact point gives it (or none), one of several fills `found` itself. (Here,
// not in the kernel's lambda: nvcc does not let an extended lambda capture in a constexpr-if.)
template <class ContactOf, int K>
KOKKOS_INLINE_FUNCTION void find_wall_contacts(const ContactOf& contact_of, int i, int e,
                                               const WallPose& wall, const TriangleEntry& entry,
                                               WallContacts<K>& found) {
  if constexpr (certifies_faces<ContactOf>::value) {
    static_assert(K == 1, "a certified face gives one contact point");
    found.contact[0] = contact_of(i, e, wall, entry);
    found.count = found.contact[0].geometry.touching ? 1 : 0;
  } else if constexpr (K == 1) {
    found.contact[0] = contact_of(i, e, wall);
    found.count = found.contact[0].geometry.touching ? 1 : 0;
  } else {
    contact_of(i, e, wall, found);
  }
}

// Stores the contacts of entry k of particle i: with one slot per entry, into it; with
// several, each takes the history of the slot that held the same feature at the last step (or
// a fresh one), they are written from the entry's first slot on in the functor's order, and
// their forces and torques summed in that order.
template <class Law, int K>
KOKKOS_INLINE_FUNCTION void store_wall_contacts(const WallSlots& slots, int k,
                                                const ParticleViews& p, int i, const WallPose& wall,
                                                const WallContacts<K>& found,
                                                const CoefficientTable& table, double dt) {
  const int first = slots.slots.first(k), capacity = slots.slots.end(k) - first;
  const int kept = capacity < K ? capacity : K;
  const auto previous = read_previous_slots<K, int, ContactHistory>(
      first, kept, [&](int s, int& feature, ContactHistory& history) {
        feature = K == 1 ? 0 : slots.feature(s);
        history = slots.history_of<Law>(s);
      });
  const int n = found.count < kept ? found.count : kept;
  Vec3 force, torque;
  for (int c = 0; c < n; ++c) {
    const WallContactGeometry& contact = found.contact[c];
    ContactHistory history = previous.matching(contact.feature);
    Vec3 contact_torque;
    const ContactOutput out =
        wall_contact_law<Law>(p, i, wall, contact, table, dt, history, contact_torque);
    slots.keep<Law>(first + c, history, contact.geometry.overlap);
    if (K > 1) {
      slots.feature(first + c) = contact.feature;
      contact_torque = contact.weight * contact_torque;
    }
    const Vec3 contact_force = K > 1 ? contact.weight * out.force_on_i : out.force_on_i;
    force = c == 0 ? contact_force : force + contact_force;
    torque = c == 0 ? contact_torque : torque + contact_torque;
  }
  for (int c = n; c < capacity; ++c)
    slots.clear_slot(first + c);
  store3(slots.force_on_i, k, force);
  store3(slots.torque_on_i, k, torque);
}

// The history of a point contact with a triangle that ended at this step (element -1: none).
struct ReleasedHistory {
  int element = -1;
  Vec3 spring, rolling;
};

KOKKOS_INLINE_FUNCTION bool triangles_share_a_vertex(const WallElements& el, int a, int b) {
  for (int u = 3; u < 6; ++u)
    for (int v = 3; v < 6; ++v)
      if (el.features(a, u) == el.features(b, v))
        return true;
  return false;
}

// Tangential history across the triangles of a mesh, for bodies with one contact point per
// entry: a contact that starts on triangle e (its slot holds no history) while the particle's
// contact with a neighbouring triangle of the same wall (one sharing a vertex) ends takes that
// contact's spring and rolling torque, so that a sphere rolling or sliding over a triangulated
// surface keeps its spring from one triangle to the next. The ending contact is one of the
// particle's entries before k that stopped touching at this step (`released`), or one after k
// that held a history and whose contact, evaluated now, does not touch. Bodies with several
// contacts per entry (K > 1) keep theirs per feature and are left alone.
template <int K> struct WallHandover {
  template <class Entries, class ContactOf>
  KOKKOS_INLINE_FUNCTION static void apply(const WallElements&, const WallSlots&, const Entries&,
                                           int, const ContactOf&, int, int, const WallPose&, bool,
                                           ReleasedHistory&) {}
};

template <> struct WallHandover<1> {
  KOKKOS_INLINE_FUNCTION static bool holds_history(const WallSlots& slots, int s) {
    const bool rolling =
        slots.rolling.extent(0) > 0 &&
        (slots.rolling(s, 0) != 0 || slots.rolling(s, 1) != 0 || slots.rolling(s, 2) != 0);
    return slots.spring(s, 0) != 0 || slots.spring(s, 1) != 0 || slots.spring(s, 2) != 0 || rolling;
  }

  KOKKOS_INLINE_FUNCTION static void give(const WallSlots& slots, int s, Vec3 spring,
                                          Vec3 rolling) {
    store3(slots.spring, s, spring);
    if (slots.rolling.extent(0) > 0)
      store3(slots.rolling, s, rolling);
  }

  KOKKOS_INLINE_FUNCTION static Vec3 rolling_of(const WallSlots& slots, int s) {
    return slots.rolling.extent(0) > 0 ? load3(slots.rolling, s) : Vec3{};
  }

  template <class Entries, class ContactOf>
  KOKKOS_INLINE_FUNCTION static void
  apply(const WallElements& el, const WallSlots& slots, const Entries& element, int row_end,
        const ContactOf& contact_of, int i, int k, const WallPose& wall, bool touches,
        ReleasedHistory& released) {
    const int e = element(k);
    if (el.kind(e) != triangle_element)
      return;
    const int s = slots.slots.first(k);
    const bool held = holds_history(slots, s);
    if (held && !touches) {
      released = ReleasedHistory{e, load3(slots.spring, s), rolling_of(slots, s)};
      return;
    }
    if (held || !touches)
      return;
    if (released.element >= 0 && el.wall(released.element) == el.wall(e) &&
        triangles_share_a_vertex(el, released.element, e)) {
      give(slots, s, released.spring, released.rolling);
      released.element = -1;
      return;
    }
    for (int later = k + 1; later < row_end; ++later) {
      const int f = element(later), t = slots.slots.first(later);
      if (el.kind(f) != triangle_element || el.wall(f) != el.wall(e) || !holds_history(slots, t) ||
          !triangles_share_a_vertex(el, e, f))
        continue;
      if (contact_of(i, f, wall).geometry.touching)
        continue; // still touching: not a contact that moved to e
      give(slots, s, load3(slots.spring, t), rolling_of(slots, t));
      give(slots, t, Vec3{}, Vec3{}); // handed over once
      return;
    }
  }
};

// The wall contacts of `count` particles (the m-th particle is row row_of(m)), stored per
// candidate entry like pair contacts and summed per particle by sum_forces. The family's
// functor contact_of gives, for particle i and element e of a wall at its pose, one contact
// (max_contacts == 1: WallContactGeometry operator()(i, e, pose)) or several
// (void operator()(i, e, pose, WallContacts<max_contacts>&)); SphereWallContact below, each
// family's wall_contact. A particle's entries are taken in order by one thread, so that a
// contact moving between triangles hands its history over (WallHandover).
template <class Law, class RowOf, class ContactOf>
void compute_wall_contacts(const std::string& label, const ParticleViews& p, const WallSet& walls,
                           const WallContactList& list, const CoefficientTable& table, double dt,
                           int count, RowOf row_of, ContactOf contact_of) {
  constexpr int K = ContactOf::max_contacts;
  auto el = walls.elements;
  auto pose = walls.pose;
  auto row_start = list.row_start;
  auto element = list.element;
  auto corners = list.triangle_corners;
  auto certificate = list.face_certificate;
  auto position = p.position;
  auto radius = p.radius;
  const WallSlots slots(list);
  Kokkos::parallel_for(
      label, BalancedPolicy(0, count), KOKKOS_LAMBDA(int m) {
        const int i = row_of(m);
        ReleasedHistory released;
        for (int k = row_start(i); k < row_start(i + 1); ++k) {
          const int e = element(k);
          const WallPose wall = pose(el.wall(e));
          WallContacts<K> found;
          if (wall.active != 0 &&
              !(el.kind(e) == triangle_element &&
                triangle_out_of_reach(corners, k, wall.to_reference(load3(position, i)),
                                      radius(i))))
            find_wall_contacts(contact_of, i, e, wall, TriangleEntry{corners, certificate, k},
                               found);
          WallHandover<K>::apply(el, slots, element, row_start(i + 1), contact_of, i, k, wall,
                                 found.count > 0, released);
          store_wall_contacts<Law>(slots, k, p, i, wall, found, table, dt);
        }
      });
}

// The contact of a sphere (centre in the wall's reference frame) whose closest wall feature the
// query `q` found, in the world frame; none where the feature does not apply.
KOKKOS_INLINE_FUNCTION WallContactGeometry sphere_wall_contact_from(const WallPose& wall,
                                                                    Vec3 centre, double radius,
                                                                    const SurfaceQuery& q,
                                                                    bool applies) {
  WallContactGeometry contact;
  if (!applies)
    return contact;
  const ContactGeometry local = sphere_on_surface(centre, radius, q.signed_distance, q.free_normal);
  contact.geometry.touching = local.touching;
  contact.geometry.overlap = local.overlap;
  contact.geometry.normal = rotate(wall.rotation, local.normal);
  contact.geometry.point = wall.to_world(local.point);
  contact.effective_radius = radius;
  return contact;
}

// A sphere against a wall element: the closest-point query in the wall's frame.
struct SphereWallContact {
  static constexpr int max_contacts = 1;
  WallElements el;
  Vec3View position;
  ScalarView radius;

  static constexpr bool certifies_faces = true; // the kernel passes its triangle entries

  KOKKOS_INLINE_FUNCTION WallContactGeometry operator()(int i, int e, const WallPose& wall) const {
    const Vec3 centre = wall.to_reference(load3(position, i));
    bool applies = true;
    const SurfaceQuery q = query_element(el, e, centre, radius(i), applies);
    return contact_from(i, wall, centre, q, applies);
  }

  // The same contact, through the certificate of entry k where e is a triangle.
  KOKKOS_INLINE_FUNCTION WallContactGeometry operator()(int i, int e, const WallPose& wall,
                                                        const TriangleEntry& entry) const {
    if (el.kind(e) != triangle_element || entry.certificate.extent(0) == 0)
      return (*this)(i, e, wall);
    const Vec3 centre = wall.to_reference(load3(position, i));
    bool applies = true;
    const SurfaceQuery q = certified_triangle_feature(el, entry, e, centre, radius(i), applies);
    return contact_from(i, wall, centre, q, applies);
  }

  KOKKOS_INLINE_FUNCTION WallContactGeometry contact_from(int i, const WallPose& wall, Vec3 centre,
                                                          const SurfaceQuery& q,
                                                          bool applies) const {
    return sphere_wall_contact_from(wall, centre, radius(i), q, applies);
  }
};

// A sphere of `radius` centred at `world_centre` against wall element e (a clump's sphere
// element; sphere particles go through SphereWallContact, which may use a face certificate).
KOKKOS_INLINE_FUNCTION WallContactGeometry sphere_wall_contact(const WallElements& el, int e,
                                                               const WallPose& wall,
                                                               Vec3 world_centre, double radius) {
  const Vec3 centre = wall.to_reference(world_centre);
  bool applies = true;
  const SurfaceQuery q = query_element(el, e, centre, radius, applies);
  return sphere_wall_contact_from(wall, centre, radius, q, applies);
}

} // namespace kdem
