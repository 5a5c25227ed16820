#pragma once
// The one stage that sets each particle's force and torque: gravity, then its wall contacts in
// candidate order, then the pairs it owns (it is i), then the pairs in which it is j, in
// ascending pair order. Contact kernels only store per contact, so the sum has one owner and
// one fixed order: the result does not depend on the thread count, the backend's scheduling or
// which families a scene holds, and no atomics are needed.
#include "pair_list.hpp"
#include "walls.hpp"

namespace kdem {

// A particle that is j of pair k gets -F and the pair's torque on j.
inline void sum_forces(const ParticleViews& p, Vec3 gravity, const WallContactList& walls,
                       const PairList& pairs) {
  auto force = p.force, torque = p.torque;
  auto mass = p.mass;
  auto wall_start = walls.row_start;
  auto wall_overlap = walls.overlap;
  const ContactSlots wall_slots = walls.slots();
  auto wall_force = walls.force_on_i, wall_torque = walls.torque_on_i;
  auto row_start = pairs.row_start, reverse_start = pairs.reverse_start;
  auto reverse_pair = pairs.reverse_pair;
  auto force_on_i = pairs.force_on_i, torque_on_i = pairs.torque_on_i;
  auto torque_on_j = pairs.torque_on_j;
  Kokkos::parallel_for(
      "kdem::sum_forces", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        Vec3 f = mass(i) * gravity, t{};
        for (int k = wall_start(i); k < wall_start(i + 1); ++k) {
          if (wall_overlap(wall_slots.first(k)) == 0)
            continue; // no contact (contacts fill an entry's slots from the first): all zero
          f += load3(wall_force, k);
          t += load3(wall_torque, k);
        }
        for (int k = row_start(i); k < row_start(i + 1); ++k) {
          f += load3(force_on_i, k);
          t += load3(torque_on_i, k);
        }
        for (int m = reverse_start(i); m < reverse_start(i + 1); ++m) {
          const int k = reverse_pair(m);
          f -= load3(force_on_i, k);
          t += load3(torque_on_j, k);
        }
        store3(force, i, f);
        store3(torque, i, t);
      });
}

} // namespace kdem
