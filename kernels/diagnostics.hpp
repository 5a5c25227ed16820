#pragma once
// Reductions over particles and contacts: list-rebuild trigger, energies, contact statistics,
// outlets.
#include <vector>

#include "pair_list.hpp"
#include "walls.hpp"

namespace kdem {

// Largest squared displacement of any particle since the lists were built.
inline double max_displacement_squared(const ParticleViews& p) {
  auto x = p.position, x0 = p.position_at_build;
  double result = 0;
  Kokkos::parallel_reduce(
      "kdem::max_displacement", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, double& m) {
        const double d2 = norm2(load3(x, i) - load3(x0, i));
        if (d2 > m)
          m = d2;
      },
      Kokkos::Max<double>(result));
  return math::max(result, 0.0);
}

inline void remember_build_positions(const ParticleViews& p) {
  Kokkos::deep_copy(p.position_at_build, p.position);
}

struct EnergySums {
  double translational = 0; // J
  double rotational = 0;    // J
  double potential = 0;     // J, gravitational, relative to the origin
};

inline EnergySums kinetic_and_potential_energy(const ParticleViews& p, Vec3 gravity) {
  auto x = p.position, v = p.velocity, w = p.angular_velocity;
  auto q = p.orientation;
  auto mass = p.mass;
  auto inertia = p.inertia;
  double translational = 0, rotational = 0, potential = 0;
  Kokkos::parallel_reduce(
      "kdem::energy", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, double& et, double& er, double& ep) {
        et += 0.5 * mass(i) * norm2(load3(v, i));
        const Vec3 body_omega = rotate_inverse(load_quat(q, i), load3(w, i));
        er += 0.5 * (inertia(i, 0) * body_omega.x * body_omega.x +
                     inertia(i, 1) * body_omega.y * body_omega.y +
                     inertia(i, 2) * body_omega.z * body_omega.z);
        ep -= mass(i) * dot(gravity, load3(x, i));
      },
      translational, rotational, potential);
  return {translational, rotational, potential};
}

struct ContactStatistics {
  int contacts = 0;
  double largest_overlap_ratio = 0; // overlap / smaller radius
};

// Contact points of all pairs (a pair may have several), and the deepest relative to the smaller
// bounding radius of its pair.
inline ContactStatistics pair_contact_statistics(const ParticleViews& p, const PairList& list) {
  auto overlap = list.overlap;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  const ContactSlots slots = list.slots();
  auto radius = p.radius;
  int contacts = 0;
  double largest = 0;
  Kokkos::parallel_reduce(
      "kdem::pair_contact_statistics", RangePolicy(0, list.pair_count),
      KOKKOS_LAMBDA(int k, int& count, double& m) {
        for (int s = slots.first(k); s < slots.end(k); ++s) {
          if (overlap(s) <= 0)
            continue;
          ++count;
          const double ratio = overlap(s) / math::min(radius(pair_i(k)), radius(pair_j(k)));
          if (ratio > m)
            m = ratio;
        }
      },
      contacts, Kokkos::Max<double>(largest));
  return {contacts, math::max(largest, 0.0)};
}

inline ContactStatistics wall_contact_statistics(const ParticleViews& p,
                                                 const WallContactList& list) {
  auto overlap = list.overlap;
  auto row_start = list.row_start;
  const ContactSlots slots = list.slots();
  auto radius = p.radius;
  int contacts = 0;
  double largest = 0;
  Kokkos::parallel_reduce(
      "kdem::wall_contact_statistics", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, int& count, double& m) {
        for (int k = row_start(i); k < row_start(i + 1); ++k)
          for (int s = slots.first(k); s < slots.end(k); ++s) {
            if (overlap(s) <= 0)
              continue;
            ++count;
            if (overlap(s) / radius(i) > m)
              m = overlap(s) / radius(i);
          }
      },
      contacts, Kokkos::Max<double>(largest));
  return {contacts, math::max(largest, 0.0)};
}

// Particles per label value in [0, labels) (a source or tag index; -1 counts nowhere): one
// reduction per value, each bringing one integer to the host.
inline std::vector<std::int64_t> count_by_label(const ParticleViews& p, const IndexView& label,
                                                int labels) {
  std::vector<std::int64_t> counts(labels, 0);
  for (int value = 0; value < labels; ++value)
    Kokkos::parallel_reduce(
        "kdem::count_by_label", RangePolicy(0, p.count),
        KOKKOS_LAMBDA(int i, std::int64_t& n) { n += label(i) == value ? 1 : 0; }, counts[value]);
  return counts;
}

struct OutletBox {
  double min[3], max[3];
};

// Marks particles whose centre lies in any outlet box (keep(i) = 0), returns how many and their
// mass.
inline int mark_discharged(const ParticleViews& p, const DeviceView<OutletBox*>& outlets,
                           int outlet_count, IndexView& keep, double& discharged_mass) {
  auto x = p.position;
  auto mass = p.mass;
  int removed = 0;
  double removed_mass = 0;
  Kokkos::parallel_reduce(
      "kdem::outlets", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, int& count, double& m) {
        const Vec3 xi = load3(x, i);
        int inside = 0;
        for (int o = 0; o < outlet_count; ++o) {
          const OutletBox& b = outlets(o);
          if (xi.x >= b.min[0] && xi.x <= b.max[0] && xi.y >= b.min[1] && xi.y <= b.max[1] &&
              xi.z >= b.min[2] && xi.z <= b.max[2])
            inside = 1;
        }
        keep(i) = 1 - inside;
        count += inside;
        if (inside)
          m += mass(i);
      },
      removed, removed_mass);
  discharged_mass = removed_mass;
  return removed;
}

// Indices of the kept particles, in order.
inline IndexView kept_indices(const IndexView& keep, int& kept) {
  IndexView offsets = exclusive_scan_with_total(keep, kept);
  IndexView source("kept_indices", kept);
  Kokkos::parallel_for(
      "kdem::kept_indices", RangePolicy(0, static_cast<int>(keep.extent(0))), KOKKOS_LAMBDA(int i) {
        if (keep(i))
          source(offsets(i)) = i;
      });
  return source;
}

} // namespace kdem
