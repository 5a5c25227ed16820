#pragma once
// How a contact's force is stored per pair (the pair loop, families/pair_loop.hpp, calls it for
// every pair type); summed per particle by sum_forces (force_sum.hpp).
#include "pair_list.hpp"

namespace kdem {

// A contact point a narrow phase found: its geometry (normal from the second body towards the
// first, as the narrow phase orders them), its Hertz radius, and the features of the two bodies
// that touch (0 and 0 for bodies with one contact point), which key its history; its force is
// scaled by `weight` (below 1 where contacts of several features share one contact region, see
// SeamSettings in shapes/clump.hpp).
struct PairContact {
  ContactGeometry geometry;
  double effective_radius = 0; // m
  int feature_a = 0, feature_b = 0;
  double weight = 1;
};

// Up to K contact points of one pair, in the narrow phase's order. Only the first `count` are
// set: the list is made for every pair at every step, and setting all K (up to 16 x 88 bytes)
// cost a clump bed more than its contacts did (docs/performance.md, section 26). A narrow phase
// appends with add(), which sets the new entry whole; one with a single contact point may write
// contact[0]'s geometry and radius alone (the only fields a pair of one slot reads).
template <int K> struct PairContacts {
  static_assert(K >= 1 && K <= 16, "a pair keeps a short list of contact points");
  int count = 0;
  union {
    PairContact contact[K];
  };

  KOKKOS_INLINE_FUNCTION PairContacts() {}
  KOKKOS_INLINE_FUNCTION PairContact& add() {
    contact[count] = PairContact{};
    return contact[count++];
  }
};

// A contact's (or a pair's) torques on i and on j, each about its own centre.
struct PairTorques {
  Vec3 on_i, on_j;
};
KOKKOS_INLINE_FUNCTION PairTorques operator+(const PairTorques& a, const PairTorques& b) {
  return {a.on_i + b.on_i, a.on_j + b.on_j};
}

// The per-contact and per-pair results a pair's contacts write, and how they are cleared when
// the contacts end.
struct PairSlots {
  ContactSlots slots;
  Vec3View spring, rolling, force_on_i, torque_on_i, torque_on_j;
  ScalarView overlap;
  IndexView feature_i, feature_j;

  explicit PairSlots(const PairList& list)
      : slots(list.slots()), spring(list.tangential_spring), rolling(list.rolling_torque),
        force_on_i(list.force_on_i), torque_on_i(list.torque_on_i), torque_on_j(list.torque_on_j),
        overlap(list.overlap), feature_i(list.feature_i), feature_j(list.feature_j) {}

  KOKKOS_INLINE_FUNCTION void clear_slot(int s) const {
    store3(spring, s, Vec3{});
    if (rolling.extent(0) > 0)
      store3(rolling, s, Vec3{});
    overlap(s) = 0;
    if (!slots.single()) {
      feature_i(s) = -1;
      feature_j(s) = -1;
    }
  }

  KOKKOS_INLINE_FUNCTION void clear(int k) const {
    bool touched = false;
    for (int s = slots.first(k); s < slots.end(k); ++s) {
      if (overlap(s) == 0)
        continue; // every value of the slot is already zero (see PairList)
      clear_slot(s);
      touched = true;
    }
    if (!touched)
      return;
    store3(force_on_i, k, Vec3{});
    store3(torque_on_i, k, Vec3{});
    store3(torque_on_j, k, Vec3{});
  }

  // The contact law at one contact point (normal from j towards i) with the history `history`,
  // which it advances; `torque` holds the contact's torques on i and on j about their centres.
  template <class Law>
  KOKKOS_INLINE_FUNCTION ContactOutput law(const ParticleViews& p, int i, int j,
                                           const ContactGeometry& geometry, double effective_radius,
                                           const PairCoefficients& coefficients, double dt,
                                           ContactHistory& history, PairTorques& torque) const {
    ContactInput in;
    in.geometry = geometry;
    const Vec3 xi = load3(p.position, i), xj = load3(p.position, j);
    const Vec3 wi = load3(p.angular_velocity, i), wj = load3(p.angular_velocity, j);
    const Vec3 point = geometry.point;
    in.relative_velocity = point_velocity(load3(p.velocity, i), wi, xi, point) -
                           point_velocity(load3(p.velocity, j), wj, xj, point);
    in.relative_angular_velocity = wi - wj;
    in.effective_radius = effective_radius;
    in.effective_mass = p.mass(i) * p.mass(j) / (p.mass(i) + p.mass(j));
    const ContactOutput out = Law::force(coefficients, in, dt, history);
    torque.on_i = cross(point - xi, out.force_on_i) + out.rolling_torque_on_i;
    torque.on_j = cross(out.force_on_i, point - xj) - out.rolling_torque_on_i;
    return out;
  }

  template <class Law> KOKKOS_INLINE_FUNCTION ContactHistory history_of(int s) const {
    ContactHistory history{load3(spring, s), Vec3{}};
    if constexpr (Law::rolling)
      history.rolling_torque = load3(rolling, s);
    return history;
  }

  template <class Law>
  KOKKOS_INLINE_FUNCTION void keep_history(int s, const ContactHistory& history,
                                           double overlap_now) const {
    store3(spring, s, history.tangential_spring);
    if constexpr (Law::rolling)
      store3(rolling, s, history.rolling_torque);
    overlap(s) = overlap_now;
  }

  // The contact point of a pair with one slot.
  template <class Law>
  KOKKOS_INLINE_FUNCTION void apply(int k, const ParticleViews& p, int i, int j,
                                    const ContactGeometry& geometry, double effective_radius,
                                    const PairCoefficients& coefficients, double dt) const {
    const int s = slots.first(k);
    ContactHistory history = history_of<Law>(s);
    PairTorques torque;
    const ContactOutput out =
        law<Law>(p, i, j, geometry, effective_radius, coefficients, dt, history, torque);
    keep_history<Law>(s, history, geometry.overlap);
    store3(force_on_i, k, out.force_on_i);
    store3(torque_on_i, k, torque.on_i);
    store3(torque_on_j, k, torque.on_j);
  }

  // Several contact points of pair k, normals from j towards i; each takes the history of the
  // slot that held the same features (of i, of j) at the last step, or a fresh one, and they are
  // written to the pair's slots in the narrow phase's order (slots left over are cleared). The
  // pair's force and torque are their sums, each weighted, in that order. `flipped`: the narrow
  // phase's first body is j.
  template <class Law, int K>
  KOKKOS_INLINE_FUNCTION void apply_several(int k, const ParticleViews& p, int i, int j,
                                            const PairContacts<K>& found, bool flipped,
                                            const PairCoefficients& coefficients, double dt) const {
    const int first = slots.first(k), capacity = slots.end(k) - first;
    const int kept = capacity < K ? capacity : K;
    const auto previous = read_previous_slots<K, FeaturePair, ContactHistory>(
        first, kept, [&](int s, FeaturePair& key, ContactHistory& history) {
          key = {feature_i(s), feature_j(s)};
          history = history_of<Law>(s);
        });
    const int count = found.count < kept ? found.count : kept;
    Vec3 force;
    PairTorques torque;
    for (int c = 0; c < count; ++c) {
      const PairContact& contact = found.contact[c];
      const int on_i = flipped ? contact.feature_b : contact.feature_a;
      const int on_j = flipped ? contact.feature_a : contact.feature_b;
      ContactHistory history = previous.matching({on_i, on_j});
      PairTorques contact_torque;
      const ContactOutput out = law<Law>(p, i, j, contact.geometry, contact.effective_radius,
                                         coefficients, dt, history, contact_torque);
      keep_history<Law>(first + c, history, contact.geometry.overlap);
      feature_i(first + c) = on_i;
      feature_j(first + c) = on_j;
      const Vec3 contact_force = contact.weight * out.force_on_i;
      contact_torque = {contact.weight * contact_torque.on_i, contact.weight * contact_torque.on_j};
      force = c == 0 ? contact_force : force + contact_force;
      torque = c == 0 ? contact_torque : torque + contact_torque;
    }
    for (int c = count; c < capacity; ++c)
      clear_slot(first + c);
    store3(force_on_i, k, force);
    store3(torque_on_i, k, torque.on_i);
    store3(torque_on_j, k, torque.on_j);
  }
};

} // namespace kdem
