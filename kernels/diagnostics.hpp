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
  double mechanical() const { return translational + rotational + potential; }
};

// Adds particle i's energies to the sums.
KOKKOS_INLINE_FUNCTION void add_particle_energy(const ParticleViews& p, Vec3 gravity, int i,
                                                double& translational, double& rotational,
                                                double& potential) {
  translational += 0.5 * p.mass(i) * norm2(load3(p.velocity, i));
  const Vec3 body_omega = rotate_inverse(load_quat(p.orientation, i), load3(p.angular_velocity, i));
  rotational += 0.5 * (p.inertia(i, 0) * body_omega.x * body_omega.x +
                       p.inertia(i, 1) * body_omega.y * body_omega.y +
                       p.inertia(i, 2) * body_omega.z * body_omega.z);
  potential -= p.mass(i) * dot(gravity, load3(p.position, i));
}

inline EnergySums kinetic_and_potential_energy(const ParticleViews& p, Vec3 gravity) {
  double translational = 0, rotational = 0, potential = 0;
  Kokkos::parallel_reduce(
      "kdem::energy", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, double& et, double& er, double& ep) {
        add_particle_energy(p, gravity, i, et, er, ep);
      },
      translational, rotational, potential);
  return {translational, rotational, potential};
}

// The energies of the particles with keep(i) == 0 (those about to be removed).
inline EnergySums energy_of_removed(const ParticleViews& p, Vec3 gravity, const IndexView& keep) {
  double translational = 0, rotational = 0, potential = 0;
  Kokkos::parallel_reduce(
      "kdem::energy_of_removed", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, double& et, double& er, double& ep) {
        if (keep(i) == 0)
          add_particle_energy(p, gravity, i, et, er, ep);
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

// The box a particle must stay in: it has left once its centre lies farther than its radius
// outside (it is then wholly outside).
struct DomainBounds {
  double min[3], max[3];
  bool active = false;
};

KOKKOS_INLINE_FUNCTION bool wholly_outside(const DomainBounds& b, Vec3 x, double radius) {
  return x.x < b.min[0] - radius || x.x > b.max[0] + radius || x.y < b.min[1] - radius ||
         x.y > b.max[1] + radius || x.z < b.min[2] - radius || x.z > b.max[2] + radius;
}

struct Removals {
  int discharged = 0;
  double discharged_mass = 0; // kg
  int lost = 0;               // left the domain
  double lost_mass = 0;       // kg
};

// Marks for removal (keep(i) = 0) the particles whose centre lies in any outlet box
// (discharged) and, where the bounds are active, those wholly outside them (lost: lost(i) = 1).
inline Removals mark_removals(const ParticleViews& p, const DeviceView<OutletBox*>& outlets,
                              int outlet_count, const DomainBounds& bounds, IndexView& keep,
                              IndexView& lost) {
  auto x = p.position;
  auto mass = p.mass;
  auto radius = p.radius;
  Removals r;
  Kokkos::parallel_reduce(
      "kdem::removals", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, int& discharged, double& discharged_mass, int& lost_count,
                    double& lost_mass) {
        const Vec3 xi = load3(x, i);
        int inside = 0;
        for (int o = 0; o < outlet_count; ++o) {
          const OutletBox& b = outlets(o);
          if (xi.x >= b.min[0] && xi.x <= b.max[0] && xi.y >= b.min[1] && xi.y <= b.max[1] &&
              xi.z >= b.min[2] && xi.z <= b.max[2])
            inside = 1;
        }
        const int left = !inside && bounds.active && wholly_outside(bounds, xi, radius(i)) ? 1 : 0;
        keep(i) = 1 - inside - left;
        lost(i) = left;
        discharged += inside;
        lost_count += left;
        if (inside)
          discharged_mass += mass(i);
        if (left)
          lost_mass += mass(i);
      },
      r.discharged, r.discharged_mass, r.lost, r.lost_mass);
  return r;
}

// flag(i) = 1 where particle i is wholly outside the bounds; returns how many.
inline int mark_outside(const ParticleViews& p, const DomainBounds& bounds, IndexView& flag) {
  auto x = p.position;
  auto radius = p.radius;
  int outside = 0;
  Kokkos::parallel_reduce(
      "kdem::outside_domain", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, int& count) {
        flag(i) = wholly_outside(bounds, load3(x, i), radius(i)) ? 1 : 0;
        count += flag(i);
      },
      outside);
  return outside;
}

KOKKOS_INLINE_FUNCTION bool finite3(Vec3 a) {
  return math::isfinite(a.x) && math::isfinite(a.y) && math::isfinite(a.z);
}

// flag(i) = 1 where particle i has a position, velocity, angular velocity or orientation that is
// not finite; returns how many.
inline int mark_non_finite(const ParticleViews& p, IndexView& flag) {
  int bad = 0;
  Kokkos::parallel_reduce(
      "kdem::non_finite", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, int& count) {
        const Quat q = load_quat(p.orientation, i);
        const bool finite = finite3(load3(p.position, i)) && finite3(load3(p.velocity, i)) &&
                            finite3(load3(p.angular_velocity, i)) && finite3(Vec3{q.x, q.y, q.z}) &&
                            math::isfinite(q.w);
        flag(i) = finite ? 0 : 1;
        count += flag(i);
      },
      bad);
  return bad;
}

using ValueAndIndex = Kokkos::MaxLoc<double, int>::value_type;

// The start of a search for the largest positive value: none yet (index -1).
inline ValueAndIndex nothing_found() {
  ValueAndIndex none;
  none.val = 0;
  none.loc = -1;
  return none;
}

// A search's result, index -1 when it found no positive value.
inline ValueAndIndex found_or_none(ValueAndIndex best) {
  return best.val > 0 ? best : nothing_found();
}

// The deepest pair contact relative to the smaller radius of its pair: ratio and pair index
// (-1: no contact).
inline ValueAndIndex deepest_pair_contact(const ParticleViews& p, const PairList& list) {
  auto overlap = list.overlap;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  const ContactSlots slots = list.slots();
  auto radius = p.radius;
  ValueAndIndex deepest = nothing_found();
  Kokkos::parallel_reduce(
      "kdem::deepest_pair_contact", RangePolicy(0, list.pair_count),
      KOKKOS_LAMBDA(int k, ValueAndIndex& best) {
        for (int s = slots.first(k); s < slots.end(k); ++s) {
          const double ratio = overlap(s) / math::min(radius(pair_i(k)), radius(pair_j(k)));
          if (overlap(s) > 0 && ratio > best.val)
            best.val = ratio, best.loc = k;
        }
      },
      Kokkos::MaxLoc<double, int>(deepest));
  return found_or_none(deepest);
}

// The deepest wall contact relative to its particle's radius: ratio and candidate entry (-1:
// none).
inline ValueAndIndex deepest_wall_contact(const ParticleViews& p, const WallContactList& list) {
  auto overlap = list.overlap;
  auto row_start = list.row_start;
  const ContactSlots slots = list.slots();
  auto radius = p.radius;
  ValueAndIndex deepest = nothing_found();
  Kokkos::parallel_reduce(
      "kdem::deepest_wall_contact", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, ValueAndIndex& best) {
        for (int k = row_start(i); k < row_start(i + 1); ++k)
          for (int s = slots.first(k); s < slots.end(k); ++s)
            if (overlap(s) > 0 && overlap(s) / radius(i) > best.val)
              best.val = overlap(s) / radius(i), best.loc = k;
      },
      Kokkos::MaxLoc<double, int>(deepest));
  return found_or_none(deepest);
}

// The fastest particle: its speed squared and index.
inline ValueAndIndex fastest_particle(const ParticleViews& p) {
  auto v = p.velocity;
  ValueAndIndex fastest = nothing_found();
  Kokkos::parallel_reduce(
      "kdem::fastest_particle", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, ValueAndIndex& best) {
        const double speed2 = norm2(load3(v, i));
        if (speed2 > best.val)
          best.val = speed2, best.loc = i;
      },
      Kokkos::MaxLoc<double, int>(fastest));
  return found_or_none(fastest);
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

// The rows of the first `most` particles with flag(i) = 1, in row order.
inline IndexView first_flagged_rows(const IndexView& flag, int most) {
  int flagged = 0;
  const IndexView rows = kept_indices(flag, flagged);
  IndexView first("first_flagged_rows", flagged < most ? flagged : most);
  Kokkos::deep_copy(first, Kokkos::subview(rows, std::make_pair(0, int(first.extent(0)))));
  return first;
}

// Particle i's row with the wall-list entry k among its entries.
inline int particle_of_wall_entry(const WallContactList& list, int particle_count, int k) {
  auto row_start = list.row_start;
  int row = -1;
  Kokkos::parallel_reduce(
      "kdem::particle_of_wall_entry", RangePolicy(0, particle_count),
      KOKKOS_LAMBDA(int i, int& found) {
        if (row_start(i) <= k && k < row_start(i + 1))
          found = i;
      },
      Kokkos::Max<int>(row));
  return row;
}

// Id, shape, position and velocity of the particles at `rows`, in that order.
inline ParticleViews gathered_rows(const ParticleViews& p, const IndexView& rows) {
  ParticleViews g;
  g.count = int(rows.extent(0));
  g.id = IdView("gathered_id", g.count);
  g.shape = IndexView("gathered_shape", g.count);
  g.position = Vec3View("gathered_position", g.count);
  g.velocity = Vec3View("gathered_velocity", g.count);
  Kokkos::parallel_for(
      "kdem::gather_rows", RangePolicy(0, g.count), KOKKOS_LAMBDA(int m) {
        const int i = rows(m);
        g.id(m) = p.id(i);
        g.shape(m) = p.shape(i);
        for (int c = 0; c < 3; ++c)
          g.position(m, c) = p.position(i, c), g.velocity(m, c) = p.velocity(i, c);
      });
  return g;
}

inline double total_mass(const ParticleViews& p) {
  auto mass = p.mass;
  double sum = 0;
  Kokkos::parallel_reduce(
      "kdem::total_mass", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, double& m) { m += mass(i); }, sum);
  return sum;
}

} // namespace kdem
