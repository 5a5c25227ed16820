#pragma once
// How a contact's force is stored per pair (the pair loop, families/pair_loop.hpp, calls it for
// every pair type); summed per particle by sum_forces (force_sum.hpp).
#include "pair_list.hpp"

namespace kdem {

// The per-pair results a contact writes, and how it clears them when it ends.
struct PairSlots {
  Vec3View spring, rolling, force_on_i, torque_on_i;
  ScalarView overlap;

  explicit PairSlots(const PairList& list)
      : spring(list.tangential_spring), rolling(list.rolling_torque), force_on_i(list.force_on_i),
        torque_on_i(list.torque_on_i), overlap(list.overlap) {}

  KOKKOS_INLINE_FUNCTION void clear(int k) const {
    if (overlap(k) == 0)
      return; // every value is already zero (see PairList)
    store3(spring, k, Vec3{});
    if (rolling.extent(0) > 0)
      store3(rolling, k, Vec3{});
    store3(force_on_i, k, Vec3{});
    store3(torque_on_i, k, Vec3{});
    overlap(k) = 0;
  }

  // Hertz-Mindlin at a contact whose geometry is given with the normal from j towards i.
  template <bool RollingResistance>
  KOKKOS_INLINE_FUNCTION void apply(int k, const ParticleViews& p, int i, int j,
                                    const ContactGeometry& geometry, double effective_radius,
                                    const PairCoefficients& coefficients, double dt) const {
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
    ContactHistory history{load3(spring, k), Vec3{}};
    if constexpr (RollingResistance)
      history.rolling_torque = load3(rolling, k);
    const ContactOutput out = hertz_mindlin<RollingResistance>(coefficients, in, dt, history);
    store3(spring, k, history.tangential_spring);
    if constexpr (RollingResistance)
      store3(rolling, k, history.rolling_torque);
    store3(force_on_i, k, out.force_on_i);
    store3(torque_on_i, k, cross(point - xi, out.force_on_i) + out.rolling_torque_on_i);
    overlap(k) = geometry.overlap;
  }
};

} // namespace kdem
