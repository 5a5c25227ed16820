#pragma once
// Walls: analytic planes and cylinders and triangle meshes, each moving rigidly. Each wall is
// stored once in its reference frame; a particle centre is taken into that frame, queried, and
// the contact is taken back to the world frame.
#include "../shapes/wall_geometry.hpp"
#include "binning.hpp"
#include "contact_law.hpp"
#include "contact_slots.hpp"
#include "particles.hpp"
#include "view_access.hpp"

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
  DeviceView<double* [9]> geometry;     // plane: origin, normal | cylinder: base, axis, radius,
                                        // length | triangle: a, b, c (reference frame)
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

struct WallSet {
  int wall_count = 0;
  WallElements elements;
  DeviceView<WallMotion*> motion;
  DeviceView<WallPose*> pose;
};

inline void update_wall_poses(const WallSet& walls, double time) {
  auto motion = walls.motion;
  auto pose = walls.pose;
  Kokkos::parallel_for(
      "kdem::wall_poses", RangePolicy(0, walls.wall_count),
      KOKKOS_LAMBDA(int w) { pose(w) = wall_pose_at(motion(w), time); });
}

KOKKOS_INLINE_FUNCTION Vec3 geometry_vec(const DeviceView<double* [9]>& g, int e, int first) {
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

// Signed in-plane distance of p's projection beyond `edge`, seen from the triangle on `side`.
KOKKOS_INLINE_FUNCTION double beyond_edge(const WallElements& el, int edge, int side, Vec3 p) {
  return dot(p - load3(el.vertex_position, el.edge_vertices(edge, 0)),
             edge_outward_of(el, edge, side));
}

// p projects into triangle e deeper than the tolerance from each of its edges.
KOKKOS_INLINE_FUNCTION bool face_claims(const WallElements& el, int e, Vec3 p) {
  for (int k = 0; k < 3; ++k) {
    const int edge = el.features(e, k);
    const int side = el.edge_owner(edge) == e ? 0 : 1;
    if (!(beyond_edge(el, edge, side, p) < -el.feature_tolerance))
      return false;
  }
  return true;
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
  return dot(p - a, d) > tol && dot(p - b, -d) > tol;
}

// The fallback: p projects beyond no edge leaving the vertex and into no face around it.
KOKKOS_INLINE_FUNCTION bool vertex_claims(const WallElements& el, int vertex, Vec3 p) {
  const Vec3 v = load3(el.vertex_position, vertex);
  for (int k = el.vertex_edge_start(vertex); k < el.vertex_edge_start(vertex + 1); ++k)
    if (dot(p - v, load3(el.vertex_edge_direction, k)) > el.feature_tolerance)
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

// The feature of triangle e that claims p, if e reports it: its face, or an edge or vertex
// that e owns. A centre is claimed by exactly one feature of a mesh (up to the edge cases of a
// tolerance band at obtuse corners, where it may be claimed by none), and the owner of an edge
// or vertex is unique, so a sphere gets one contact per feature it touches.
KOKKOS_INLINE_FUNCTION SurfaceQuery claimed_triangle_feature(const WallElements& el, int e, Vec3 p,
                                                             bool& applies) {
  const Vec3 a = geometry_vec(el.geometry, e, 0), b = geometry_vec(el.geometry, e, 3),
             c = geometry_vec(el.geometry, e, 6);
  const Vec3 normal_raw = cross(b - a, c - a);
  const Vec3 normal = (1.0 / norm(normal_raw)) * normal_raw;
  const double height = dot(p - a, normal);
  const Vec3 facing = height >= 0 ? normal : -normal;
  applies = true;
  if (face_claims(el, e, p))
    return point_feature_query(p - height * normal, p, facing, 0);
  for (int k = 0; k < 3; ++k) {
    const int edge = el.features(e, k);
    if (el.edge_owner(edge) != e || !edge_claims(el, edge, p))
      continue;
    const Vec3 start = load3(el.vertex_position, el.edge_vertices(edge, 0));
    const Vec3 d = load3(el.edge_direction, edge);
    return point_feature_query(start + dot(p - start, d) * d, p, facing, 1 + k);
  }
  for (int k = 0; k < 3; ++k) {
    const int vertex = el.features(e, 3 + k);
    if (el.vertex_owner(vertex) != e || !vertex_claims(el, vertex, p))
      continue;
    return point_feature_query(load3(el.vertex_position, vertex), p, facing, 4 + k);
  }
  applies = false;
  return SurfaceQuery{};
}

// Closest point of element e to the reference-frame point p. `applies` is false when the
// element does not take part (outside a cylinder's length, a feature another triangle reports).
KOKKOS_INLINE_FUNCTION SurfaceQuery query_element(const WallElements& el, int e, Vec3 p,
                                                  bool& applies) {
  applies = true;
  switch (el.kind(e)) {
  case plane_element:
    return plane_query(geometry_vec(el.geometry, e, 0), geometry_vec(el.geometry, e, 3), p);
  case cylinder_element:
    return cylinder_query(el, e, p, applies);
  default:
    return claimed_triangle_feature(el, e, p, applies);
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

inline void allocate_wall_contact_results(WallContactList& list) {
  list.force_on_i = Vec3View("wall_force", list.entry_count);
  list.torque_on_i = Vec3View("wall_torque", list.entry_count);
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
inline void allocate_wall_contacts(WallContactList& list, bool rolling_state) {
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
  allocate_wall_contact_results(list);
}

// The candidate elements of each particle; no contact state yet (see allocate_wall_contacts).
inline WallContactList build_wall_contact_list(const ParticleViews& p, const WallSet& walls,
                                               double skin) {
  const int n = p.count;
  WallContactList list;
  IndexView counts("wall_candidate_count", n);
  auto el = walls.elements;
  auto pose = walls.pose;
  auto x = p.position;
  auto radius = p.radius;
  const int elements = el.count;
  Kokkos::parallel_for(
      "kdem::wall_candidate_count", RangePolicy(0, n), KOKKOS_LAMBDA(int i) {
        int found = 0;
        for (int e = 0; e < elements; ++e)
          if (element_within_reach(el, e, pose(el.wall(e)).to_reference(load3(x, i)),
                                   radius(i) + skin))
            ++found;
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
        for (int e = 0; e < elements; ++e) {
          if (!element_within_reach(el, e, pose(el.wall(e)).to_reference(load3(x, i)),
                                    radius(i) + skin))
            continue;
          element(slot) = e;
          key(slot) = e;
          ++slot;
        }
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
};

// Up to K contacts of one particle with one wall element.
template <int K> struct WallContacts {
  int count = 0;
  WallContactGeometry contact[K];
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

// The contacts of particle i with element e of a wall at `wall`: a functor of one contact point
// gives it (or none), one of several fills `found` itself.
template <class ContactOf, int K>
KOKKOS_INLINE_FUNCTION void find_wall_contacts(const ContactOf& contact_of, int i, int e,
                                               const WallPose& wall, WallContacts<K>& found) {
  if constexpr (K == 1) {
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
    if (K > 1)
      slots.feature(first + c) = contact.feature;
    force = c == 0 ? out.force_on_i : force + out.force_on_i;
    torque = c == 0 ? contact_torque : torque + contact_torque;
  }
  for (int c = n; c < capacity; ++c)
    slots.clear_slot(first + c);
  store3(slots.force_on_i, k, force);
  store3(slots.torque_on_i, k, torque);
}

// The wall contacts of `count` particles (the m-th particle is row row_of(m)), stored per
// candidate entry like pair contacts and summed per particle by sum_forces. The family's
// functor contact_of gives, for particle i and element e of a wall at its pose, one contact
// (max_contacts == 1: WallContactGeometry operator()(i, e, pose)) or several
// (void operator()(i, e, pose, WallContacts<max_contacts>&)); SphereWallContact below, each
// family's wall_contact.
template <class Law, class RowOf, class ContactOf>
void compute_wall_contacts(const std::string& label, const ParticleViews& p, const WallSet& walls,
                           const WallContactList& list, const CoefficientTable& table, double dt,
                           int count, RowOf row_of, ContactOf contact_of) {
  constexpr int K = ContactOf::max_contacts;
  auto el = walls.elements;
  auto pose = walls.pose;
  auto row_start = list.row_start;
  auto element = list.element;
  const WallSlots slots(list);
  Kokkos::parallel_for(
      label, RangePolicy(0, count), KOKKOS_LAMBDA(int m) {
        const int i = row_of(m);
        for (int k = row_start(i); k < row_start(i + 1); ++k) {
          const int e = element(k);
          const WallPose wall = pose(el.wall(e));
          WallContacts<K> found;
          if (wall.active != 0)
            find_wall_contacts(contact_of, i, e, wall, found);
          store_wall_contacts<Law>(slots, k, p, i, wall, found, table, dt);
        }
      });
}

// A sphere against a wall element: the closest-point query in the wall's frame.
struct SphereWallContact {
  static constexpr int max_contacts = 1;
  WallElements el;
  Vec3View position;
  ScalarView radius;

  KOKKOS_INLINE_FUNCTION WallContactGeometry operator()(int i, int e, const WallPose& wall) const {
    WallContactGeometry contact;
    const Vec3 centre = wall.to_reference(load3(position, i));
    bool applies = true;
    const SurfaceQuery q = query_element(el, e, centre, applies);
    if (!applies)
      return contact;
    const ContactGeometry local =
        sphere_on_surface(centre, radius(i), q.signed_distance, q.free_normal);
    contact.geometry.touching = local.touching;
    contact.geometry.overlap = local.overlap;
    contact.geometry.normal = rotate(wall.rotation, local.normal);
    contact.geometry.point = wall.to_world(local.point);
    contact.effective_radius = radius(i);
    return contact;
  }
};

} // namespace kdem
