#pragma once
// Sphere-sphere contact forces, one thread per candidate pair, stored per pair; then gathered
// per particle in list order (deterministic for any thread count, no atomics).
#include "pair_list.hpp"

namespace kdem {

template <bool RollingResistance>
void compute_sphere_pair_forces(const ParticleViews& p, PairList& list,
                                const CoefficientTable& table, double dt) {
  auto x = p.position, v = p.velocity, w = p.angular_velocity;
  auto radius = p.radius, mass = p.mass;
  auto material = p.material;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  auto spring = list.tangential_spring, rolling = list.rolling_torque;
  auto force_on_i = list.force_on_i, torque_on_i = list.torque_on_i, torque_on_j = list.torque_on_j;
  auto overlap = list.overlap;
  Kokkos::parallel_for(
      "kdem::sphere_pair_forces", RangePolicy(0, list.pair_count), KOKKOS_LAMBDA(int k) {
        const int i = pair_i(k), j = pair_j(k);
        const Vec3 xi = load3(x, i), xj = load3(x, j);
        ContactInput in;
        in.geometry = sphere_sphere(xi, radius(i), xj, radius(j));
        if (!in.geometry.touching) {
          // overlap(k) == 0 means every per-pair value is already zero (see PairList).
          if (overlap(k) == 0)
            return;
          store3(spring, k, Vec3{});
          store3(rolling, k, Vec3{});
          store3(force_on_i, k, Vec3{});
          store3(torque_on_i, k, Vec3{});
          store3(torque_on_j, k, Vec3{});
          overlap(k) = 0;
          return;
        }
        const Vec3 point = in.geometry.point;
        const Vec3 wi = load3(w, i), wj = load3(w, j);
        in.relative_velocity =
            point_velocity(load3(v, i), wi, xi, point) - point_velocity(load3(v, j), wj, xj, point);
        in.relative_angular_velocity = wi - wj;
        in.effective_radius = radius(i) * radius(j) / (radius(i) + radius(j));
        in.effective_mass = mass(i) * mass(j) / (mass(i) + mass(j));
        ContactHistory history{load3(spring, k), load3(rolling, k)};
        const ContactOutput out =
            hertz_mindlin<RollingResistance>(table(material(i), material(j)), in, dt, history);
        store3(spring, k, history.tangential_spring);
        if constexpr (RollingResistance)
          store3(rolling, k, history.rolling_torque);
        store3(force_on_i, k, out.force_on_i);
        store3(torque_on_i, k, cross(point - xi, out.force_on_i) + out.rolling_torque_on_i);
        store3(torque_on_j, k, cross(point - xj, -out.force_on_i) - out.rolling_torque_on_i);
        overlap(k) = in.geometry.overlap;
      });
}

// Adds the pair forces to the particles' force and torque accumulators.
inline void gather_pair_forces(const ParticleViews& p, const PairList& list) {
  auto force = p.force, torque = p.torque;
  auto row_start = list.row_start, reverse_start = list.reverse_start;
  auto reverse_pair = list.reverse_pair;
  auto force_on_i = list.force_on_i, torque_on_i = list.torque_on_i, torque_on_j = list.torque_on_j;
  Kokkos::parallel_for(
      "kdem::gather_pair_forces", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        Vec3 f = load3(force, i), t = load3(torque, i);
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
