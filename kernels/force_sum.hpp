#pragma once
// The one stage that sets each particle's force and torque: gravity, then its wall contacts in
// candidate order, then the pairs it owns (it is i), then the pairs in which it is j, in
// ascending pair order. Contact kernels only store per contact, so the sum has one owner and
// one fixed order: the result does not depend on the thread count, the backend's scheduling or
// which families a scene holds, and no atomics are needed. A scene of spheres alone has the
// first three terms added by its pair kernel (compute_sphere_rows) in this order, and
// sum_reverse_forces adds the last: the same additions in the same order, bit for bit.
#include "pair_list.hpp"
#include "walls.hpp"

namespace kdem {

// The first terms of a particle's sum: gravity, then its wall contacts in candidate order.
struct GravityAndWallTerms {
  ScalarView mass;
  Vec3 gravity;
  IndexView wall_start;
  ScalarView wall_overlap;
  ContactSlots wall_slots;
  Vec3View wall_force, wall_torque;

  GravityAndWallTerms(const ParticleViews& p, Vec3 g, const WallContactList& walls)
      : mass(p.mass), gravity(g), wall_start(walls.row_start), wall_overlap(walls.overlap),
        wall_slots(walls.slots()), wall_force(walls.force_on_i), wall_torque(walls.torque_on_i) {}

  KOKKOS_INLINE_FUNCTION void start(int i, Vec3& f, Vec3& t) const {
    f = mass(i) * gravity;
    t = Vec3{};
    for (int k = wall_start(i); k < wall_start(i + 1); ++k) {
      if (wall_overlap(wall_slots.first(k)) == 0)
        continue; // no contact (contacts fill an entry's slots from the first): all zero
      f += load3(wall_force, k);
      t += load3(wall_torque, k);
    }
  }
};

// The last terms: the pairs in which particle i is j, ascending. A particle that is j of pair k
// gets -F and the torque (x_j - x_i) x F - T_i (see PairList::torque_on_i).
struct ReversePairTerms {
  Vec3View position;
  IndexView reverse_start, reverse_pair, pair_i;
  Vec3View force_on_i, torque_on_i;

  ReversePairTerms(const ParticleViews& p, const PairList& pairs)
      : position(p.position), reverse_start(pairs.reverse_start), reverse_pair(pairs.reverse_pair),
        pair_i(pairs.pair_i), force_on_i(pairs.force_on_i), torque_on_i(pairs.torque_on_i) {}

  KOKKOS_INLINE_FUNCTION void add(int i, Vec3& f, Vec3& t) const {
    const Vec3 xi = load3(position, i);
    for (int m = reverse_start(i); m < reverse_start(i + 1); ++m) {
      const int k = reverse_pair(m);
      const Vec3 force_on_partner = load3(force_on_i, k);
      f -= force_on_partner;
      t += cross(xi - load3(position, pair_i(k)), force_on_partner) - load3(torque_on_i, k);
    }
  }
};

inline void sum_forces(const ParticleViews& p, Vec3 gravity, const WallContactList& walls,
                       const PairList& pairs) {
  auto force = p.force, torque = p.torque;
  const GravityAndWallTerms first_terms(p, gravity, walls);
  const ReversePairTerms reverse_terms(p, pairs);
  auto row_start = pairs.row_start;
  auto force_on_i = pairs.force_on_i, torque_on_i = pairs.torque_on_i;
  Kokkos::parallel_for(
      "kdem::sum_forces", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        Vec3 f, t;
        first_terms.start(i, f, t);
        for (int k = row_start(i); k < row_start(i + 1); ++k) {
          f += load3(force_on_i, k);
          t += load3(torque_on_i, k);
        }
        reverse_terms.add(i, f, t);
        store3(force, i, f);
        store3(torque, i, t);
      });
}

// Ends the sums that a pair kernel began in force and torque (gravity, walls, the particle's own
// pairs): adds the pairs in which each particle is j.
inline void sum_reverse_forces(const ParticleViews& p, const PairList& pairs) {
  auto force = p.force, torque = p.torque;
  const ReversePairTerms reverse_terms(p, pairs);
  Kokkos::parallel_for(
      "kdem::sum_reverse_forces", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        Vec3 f = load3(force, i), t = load3(torque, i);
        reverse_terms.add(i, f, t);
        store3(force, i, f);
        store3(torque, i, t);
      });
}

} // namespace kdem
