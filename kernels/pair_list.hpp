#pragma once
// Half candidate lists of particle pairs within reach (r_i + r_j + skin, r the bounding radius),
// built by count -> scan -> fill over the cell bins, with a reverse index so that each particle can
// gather the forces of the pairs it belongs to in a fixed order, without atomics. Contact history
// moves from the old list to the new one by stable particle ids.
#include "binning.hpp"
#include "contact_law.hpp"
#include "contact_slots.hpp"

namespace kdem {

struct PairList {
  int pair_count = 0;
  IndexView row_start; // particle_count + 1: pairs (i, j after i in cell order) are owned by i
  IndexView pair_i, pair_j;
  IdView partner_id;       // stable id of j, the key for history transfer
  IndexView reverse_start; // particle_count + 1
  IndexView reverse_pair;  // pairs in which the particle is j
  // Per contact slot (see ContactSlots): its history, keyed by the features of i and of j that
  // touch (an element, octant or surface point of each body; empty when every pair has one
  // slot, whose features are then 0 and 0), and its overlap.
  IndexView contact_start; // see ContactSlots
  int slot_count = 0;
  IndexView feature_i, feature_j; // -1: the slot is free
  Vec3View tangential_spring;     // history, see ContactHistory
  Vec3View rolling_torque;        // history; empty when no material pair has rolling resistance
  ScalarView overlap;             // m, 0 when not touching; then the slot's history is 0 too
  // Per pair: the sum of the forces of its contacts on i this step, N, and their torques on i
  // and on j about their centres, N m (the force on j is -F). All are 0 when no slot of the pair
  // touches.
  Vec3View force_on_i;
  Vec3View torque_on_i;
  Vec3View torque_on_j;
  // Pair types with an iterative narrow phase only (empty in scenes of spheres): the Newton
  // warm start per slot (midway point relative to the midpoint of the two centres, m;
  // multiplier, 0 = none; how far that relative point moved between the last two evaluations,
  // m, by which the next start is extrapolated) and per pair the axis that last separated the
  // bounding boxes.
  Vec3View midway_point;
  ScalarView midway_multiplier;
  Vec3View midway_step;
  IndexView separating_axis;
  // Separation certificate of a pair that did not touch (see SeparationCertificates): a lower
  // bound on its gap, m (0 = none), and the centre offset x_j - x_i and turned angles of i and j
  // when it was issued; and the surface travel (Engine's running sum of the farthest any surface
  // moved in a step, m) up to which it holds without a look at the bodies (0 = none).
  ScalarView separation_margin;
  Vec3View separation_offset;
  ScalarView turned_i_at_separation;
  ScalarView turned_j_at_separation;
  ScalarView separation_expiry;

  ContactSlots slots() const { return ContactSlots{contact_start}; }
  bool one_slot_per_pair() const { return contact_start.extent(0) == 0; }
};

template <class Visitor> void for_each_pair_list_field(Visitor&& visit) {
  visit("row_start", &PairList::row_start);
  visit("pair_i", &PairList::pair_i);
  visit("pair_j", &PairList::pair_j);
  visit("partner_id", &PairList::partner_id);
  visit("reverse_start", &PairList::reverse_start);
  visit("reverse_pair", &PairList::reverse_pair);
  visit("contact_start", &PairList::contact_start);
  visit("feature_i", &PairList::feature_i);
  visit("feature_j", &PairList::feature_j);
  visit("tangential_spring", &PairList::tangential_spring);
  visit("rolling_torque", &PairList::rolling_torque);
  visit("force_on_i", &PairList::force_on_i);
  visit("torque_on_i", &PairList::torque_on_i);
  visit("overlap", &PairList::overlap);
  visit("midway_point", &PairList::midway_point);
  visit("midway_multiplier", &PairList::midway_multiplier);
  visit("midway_step", &PairList::midway_step);
  visit("separating_axis", &PairList::separating_axis);
  visit("separation_margin", &PairList::separation_margin);
  visit("separation_offset", &PairList::separation_offset);
  visit("turned_i_at_separation", &PairList::turned_i_at_separation);
  visit("turned_j_at_separation", &PairList::turned_j_at_separation);
  visit("separation_expiry", &PairList::separation_expiry);
}

// Calls visit(j) for every particle j after i in the cell order within reach of i, in a fixed
// order.
template <class Visit>
KOKKOS_INLINE_FUNCTION void for_each_candidate(const CellBins& bins, const Vec3View& position,
                                               const ScalarView& radius, double skin, int i,
                                               Visit&& visit) {
  const Vec3 xi = load3(position, i);
  const int slot_i = bins.slot(i);
  const CellGrid& g = bins.grid;
  const int c[3] = {g.coordinate(xi.x, 0), g.coordinate(xi.y, 1), g.coordinate(xi.z, 2)};
  for (int dz = -1; dz <= 1; ++dz) {
    const int cz = c[2] + dz;
    if (cz < 0 || cz >= g.dims[2])
      continue;
    for (int dy = -1; dy <= 1; ++dy) {
      const int cy = c[1] + dy;
      if (cy < 0 || cy >= g.dims[1])
        continue;
      for (int dx = -1; dx <= 1; ++dx) {
        const int cx = c[0] + dx;
        if (cx < 0 || cx >= g.dims[0])
          continue;
        const int cell = g.flat(cx, cy, cz);
        // Half list: only partners after i in the cell order.
        const int first = bins.cell_start(cell) > slot_i ? bins.cell_start(cell) : slot_i + 1;
        for (int slot = first; slot < bins.cell_start(cell + 1); ++slot) {
          const int j = bins.particle(slot);
          const double reach = radius(i) + radius(j) + skin;
          if (norm2(load3(position, j) - xi) < reach * reach)
            visit(j);
        }
      }
    }
  }
}

// For each particle, the pairs in which it is j, in ascending pair order (so that the gather
// order does not depend on scheduling): slots claimed with atomics, then each short row sorted.
inline void fill_reverse_index(PairList& list, int particles) {
  auto pair_j = list.pair_j;
  IndexView reverse_count("reverse_count", particles);
  Kokkos::parallel_for(
      "kdem::pair_reverse_count", RangePolicy(0, list.pair_count),
      KOKKOS_LAMBDA(int k) { Kokkos::atomic_add(&reverse_count(pair_j(k)), 1); });
  int reverse_total = 0;
  list.reverse_start = exclusive_scan_with_total(reverse_count, reverse_total);
  list.reverse_pair = uninitialized<IndexView>("reverse_pair", reverse_total);
  auto reverse_start = list.reverse_start;
  auto reverse_pair = list.reverse_pair;
  auto cursor = uninitialized<IndexView>("reverse_cursor", particles);
  Kokkos::deep_copy(cursor, Kokkos::subview(reverse_start, Kokkos::make_pair(0, particles)));
  Kokkos::parallel_for(
      "kdem::pair_reverse_fill", RangePolicy(0, list.pair_count),
      KOKKOS_LAMBDA(int k) { reverse_pair(Kokkos::atomic_fetch_add(&cursor(pair_j(k)), 1)) = k; });
  Kokkos::parallel_for(
      "kdem::pair_reverse_order", RangePolicy(0, particles), KOKKOS_LAMBDA(int i) {
        const int begin = reverse_start(i), end = reverse_start(i + 1);
        for (int a = begin + 1; a < end; ++a) { // insertion sort: rows hold a few pairs
          const int moving = reverse_pair(a);
          int b = a - 1;
          while (b >= begin && reverse_pair(b) > moving) {
            reverse_pair(b + 1) = reverse_pair(b);
            --b;
          }
          reverse_pair(b + 1) = moving;
        }
      });
}

inline void allocate_narrow_phase_state(PairList& list) {
  list.midway_point = Vec3View("pair_midway_point", list.slot_count);
  list.midway_multiplier = ScalarView("pair_midway_multiplier", list.slot_count);
  list.midway_step = Vec3View("pair_midway_step", list.slot_count);
  list.separating_axis = IndexView("pair_separating_axis", list.pair_count);
  Kokkos::deep_copy(list.separating_axis, -1);
  list.separation_margin = ScalarView("pair_separation_margin", list.pair_count);
  list.separation_offset = Vec3View("pair_separation_offset", list.pair_count);
  list.turned_i_at_separation = ScalarView("pair_turned_i_at_separation", list.pair_count);
  list.turned_j_at_separation = ScalarView("pair_turned_j_at_separation", list.pair_count);
  list.separation_expiry = ScalarView("pair_separation_expiry", list.pair_count);
}

// The candidate pairs, their owner rows and the reverse index; no contact state yet (see
// allocate_pair_contacts).
inline PairList build_pair_list(const ParticleViews& p, const CellBins& bins, double skin) {
  const int n = p.count;
  PairList list;
  IndexView half_count("half_count", n);
  auto position = p.position;
  auto radius = p.radius;
  Kokkos::parallel_for(
      "kdem::pair_count", RangePolicy(0, n), KOKKOS_LAMBDA(int i) {
        int above = 0;
        for_each_candidate(bins, position, radius, skin, i, [&](int) { ++above; });
        half_count(i) = above;
      });
  list.row_start = exclusive_scan_with_total(half_count, list.pair_count);
  const int pairs = list.pair_count;
  list.pair_i = uninitialized<IndexView>("pair_i", pairs);
  list.pair_j = uninitialized<IndexView>("pair_j", pairs);
  list.partner_id = uninitialized<IdView>("partner_id", pairs);
  auto row_start = list.row_start;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  auto partner_id = list.partner_id;
  auto id = p.id;
  Kokkos::parallel_for(
      "kdem::pair_fill", RangePolicy(0, n), KOKKOS_LAMBDA(int i) {
        int slot = row_start(i);
        for_each_candidate(bins, position, radius, skin, i, [&](int j) {
          pair_i(slot) = i;
          pair_j(slot) = j;
          partner_id(slot) = id(j);
          ++slot;
        });
      });
  fill_reverse_index(list, n);
  return list;
}

// Gives pair k slots_of(k) contact slots (count, scan); without this every pair has one.
template <class SlotsOf> void assign_contact_slots(PairList& list, SlotsOf slots_of) {
  IndexView counts = uninitialized<IndexView>("contact_slot_count", list.pair_count);
  Kokkos::parallel_for(
      "kdem::contact_slot_count", RangePolicy(0, list.pair_count),
      KOKKOS_LAMBDA(int k) { counts(k) = slots_of(k); });
  list.contact_start = exclusive_scan_with_total(counts, list.slot_count);
}

// The torque on j is recomputed at every step before the force sum reads it (a pair not
// touching keeps its zero), so a checkpoint does not keep it: a restored list gets it anew.
inline void allocate_torque_on_j(PairList& list) {
  list.torque_on_j = Vec3View("pair_torque_j", list.pair_count);
}

// The contact state of a pair list: per slot its history (features only with several slots per
// pair), per pair its force and torque; the warm starts and certificates where a pair type
// needs them.
inline void allocate_pair_contacts(PairList& list, bool rolling_state, bool narrow_phase_state) {
  if (list.one_slot_per_pair())
    list.slot_count = list.pair_count;
  const int slots = list.slot_count;
  if (!list.one_slot_per_pair()) {
    list.feature_i = IndexView("contact_feature_i", slots);
    list.feature_j = IndexView("contact_feature_j", slots);
    Kokkos::deep_copy(list.feature_i, -1);
    Kokkos::deep_copy(list.feature_j, -1);
  }
  list.tangential_spring = Vec3View("tangential_spring", slots);
  if (rolling_state)
    list.rolling_torque = Vec3View("rolling_torque", slots);
  list.overlap = ScalarView("pair_overlap", slots);
  list.force_on_i = Vec3View("pair_force", list.pair_count);
  list.torque_on_i = Vec3View("pair_torque_i", list.pair_count);
  allocate_torque_on_j(list);
  if (narrow_phase_state)
    allocate_narrow_phase_state(list);
}

// row_of_id(stable id) = the row of that particle in the particle order of `old_list`, or -1.
inline IndexView rows_by_id(const IdView& id, int count, std::int64_t id_bound) {
  IndexView row_of_id("row_of_id", id_bound);
  Kokkos::deep_copy(row_of_id, -1);
  Kokkos::parallel_for(
      "kdem::rows_by_id", RangePolicy(0, count), KOKKOS_LAMBDA(int i) { row_of_id(id(i)) = i; });
  return row_of_id;
}

// Finds pair (a, b) of stable ids in the old list: its slot, and whether it was stored as (b, a).
KOKKOS_INLINE_FUNCTION int find_old_pair(const PairList& old, const IndexView& old_row_of_id,
                                         std::int64_t a, std::int64_t b, bool& flipped) {
  flipped = false;
  const int found = find_in_row(old.row_start, old.partner_id, old_row_of_id(a), b);
  if (found >= 0)
    return found;
  flipped = true;
  return find_in_row(old.row_start, old.partner_id, old_row_of_id(b), a);
}

// Slot c of pair k in the fresh list takes the history of slot c of the same pair in the old
// list (a pair type keeps its number of slots; its narrow phase writes contacts from slot 0 on).
KOKKOS_INLINE_FUNCTION int shared_slots(const ContactSlots& fresh, int k, const ContactSlots& old,
                                        int found) {
  const int fresh_count = fresh.end(k) - fresh.first(k);
  const int old_count = old.end(found) - old.first(found);
  return fresh_count < old_count ? fresh_count : old_count;
}

// Warm starts and separation certificates survive a rebuild (the midway point and its step are
// relative to the midpoint of the centres, the same for both orders). Flipped pairs (midway-point
// method of implicit surfaces): grad F_j + (1/lambda^2) grad F_i = 0, so the multiplier becomes
// 1/lambda; the box axes of i and j swap, so the separating-axis hint is dropped; the
// certificate's offset changes sign and its turned angles swap.
inline void transfer_narrow_phase_state(PairList& fresh, const PairList& old,
                                        const IndexView& old_row_of_id, const IdView& id) {
  auto pair_i = fresh.pair_i;
  auto partner = fresh.partner_id;
  const ContactSlots slots = fresh.slots(), old_slots = old.slots();
  auto point = fresh.midway_point, step = fresh.midway_step;
  auto multiplier = fresh.midway_multiplier;
  auto axis = fresh.separating_axis;
  auto old_point = old.midway_point, old_step = old.midway_step;
  auto old_multiplier = old.midway_multiplier;
  auto old_axis = old.separating_axis;
  auto margin = fresh.separation_margin, old_margin = old.separation_margin;
  auto offset = fresh.separation_offset, old_offset = old.separation_offset;
  auto turned_i = fresh.turned_i_at_separation, old_turned_i = old.turned_i_at_separation;
  auto turned_j = fresh.turned_j_at_separation, old_turned_j = old.turned_j_at_separation;
  auto expiry = fresh.separation_expiry, old_expiry = old.separation_expiry;
  Kokkos::parallel_for(
      "kdem::narrow_phase_state_transfer", RangePolicy(0, fresh.pair_count), KOKKOS_LAMBDA(int k) {
        bool flipped = false;
        const int found = find_old_pair(old, old_row_of_id, id(pair_i(k)), partner(k), flipped);
        if (found < 0)
          return;
        const int shared = shared_slots(slots, k, old_slots, found);
        for (int c = 0; c < shared; ++c) {
          const int to = slots.first(k) + c, from = old_slots.first(found) + c;
          for (int d = 0; d < 3; ++d) {
            point(to, d) = old_point(from, d);
            step(to, d) = old_step(from, d);
          }
          const double lambda = old_multiplier(from);
          multiplier(to) = flipped ? (lambda > 0 ? 1.0 / lambda : 0.0) : lambda;
        }
        axis(k) = flipped ? -1 : old_axis(found);
        margin(k) = old_margin(found);
        const double sign = flipped ? -1.0 : 1.0;
        for (int c = 0; c < 3; ++c)
          offset(k, c) = sign * old_offset(found, c);
        turned_i(k) = flipped ? old_turned_j(found) : old_turned_i(found);
        turned_j(k) = flipped ? old_turned_i(found) : old_turned_j(found);
        expiry(k) = old_expiry(found);
      });
}

// Copies the contact history of every pair that was in the old list, slot by slot; a pair whose
// order of i and j flipped gets its vectors negated (they are defined for the body i) and the
// features of its two bodies swapped. A list with one slot per pair has the features 0 and 0.
inline void transfer_pair_history(PairList& fresh, const PairList& old,
                                  const IndexView& old_row_of_id, const IdView& id) {
  auto pair_i = fresh.pair_i;
  auto partner = fresh.partner_id;
  const ContactSlots slots = fresh.slots(), old_slots = old.slots();
  auto spring = fresh.tangential_spring, rolling = fresh.rolling_torque;
  auto old_spring = old.tangential_spring, old_rolling = old.rolling_torque;
  auto overlap = fresh.overlap, old_overlap = old.overlap;
  auto feature_i = fresh.feature_i, feature_j = fresh.feature_j;
  auto old_feature_i = old.feature_i, old_feature_j = old.feature_j;
  const bool copy_rolling = rolling.extent(0) > 0 && old_rolling.extent(0) > 0;
  const bool keyed = !fresh.one_slot_per_pair(), old_keyed = !old.one_slot_per_pair();
  Kokkos::parallel_for(
      "kdem::pair_history_transfer", RangePolicy(0, fresh.pair_count), KOKKOS_LAMBDA(int k) {
        bool flipped = false;
        const int found = find_old_pair(old, old_row_of_id, id(pair_i(k)), partner(k), flipped);
        if (found < 0)
          return;
        const double sign = flipped ? -1.0 : 1.0;
        const int shared = shared_slots(slots, k, old_slots, found);
        for (int c = 0; c < shared; ++c) {
          const int to = slots.first(k) + c, from = old_slots.first(found) + c;
          overlap(to) = old_overlap(from);
          for (int d = 0; d < 3; ++d)
            spring(to, d) = sign * old_spring(from, d);
          if (copy_rolling)
            for (int d = 0; d < 3; ++d)
              rolling(to, d) = sign * old_rolling(from, d);
          if (!keyed)
            continue;
          const int on_i = old_keyed ? old_feature_i(from) : 0;
          const int on_j = old_keyed ? old_feature_j(from) : 0;
          feature_i(to) = flipped ? on_j : on_i;
          feature_j(to) = flipped ? on_i : on_j;
        }
      });
  if (fresh.midway_point.extent(0) > 0 && old.midway_point.extent(0) > 0)
    transfer_narrow_phase_state(fresh, old, old_row_of_id, id);
}

} // namespace kdem
