#pragma once
// Hertz-Mindlin contact law with history (the "hertz/mindlin" family of LIGGGHTS and EDEM):
//   normal:     F_n = 4/3 E* sqrt(R*) d^(3/2) - gamma_n sqrt(S_n m*) v_n,   S_n = 2 E* sqrt(R* d)
//   tangential: F_t = -S_t xi - gamma_t sqrt(S_t m*) v_t,  S_t = 8 G* sqrt(R* d),  |F_t| <= mu F_n
//   rolling:    elastic-plastic spring-dashpot without dashpot ("EPSD2", Ai et al., Powder Technol.
//               206 (2011) 269, model C without damping): M_r += -k_r w_roll dt,
//               k_r = 2.25 S_n mu_r^2 R*^2, |M_r| <= mu_r R* F_n.
// gamma_n is calibrated per material pair so that the coefficient of restitution is exactly the
// input value (damping_for_restitution, src/restitution.cpp); gamma_t = gamma_n.
#include "../shapes/math.hpp"
#include "../shapes/sphere.hpp"
#include "types.hpp"

namespace kdem {

struct PairCoefficients {
  double effective_youngs = 0; // E*, Pa
  double effective_shear = 0;  // G*, Pa
  double damping = 0;          // gamma_n = gamma_t, dimensionless
  double friction = 0;         // sliding friction coefficient
  double rolling_friction = 0; // rolling friction coefficient (dimensionless, times R*)
};

using CoefficientTable = DeviceView<PairCoefficients**>;

KOKKOS_INLINE_FUNCTION Vec3 point_velocity(Vec3 velocity, Vec3 angular_velocity, Vec3 centre,
                                           Vec3 point) {
  return velocity + cross(angular_velocity, point - centre);
}

// State that a contact carries from step to step.
struct ContactHistory {
  Vec3 tangential_spring; // m, tangential displacement of i relative to j
  Vec3 rolling_torque;    // N m, elastic rolling torque on i
};

struct ContactInput {
  ContactGeometry geometry;
  Vec3 relative_velocity;         // of i relative to j at the contact point, m/s
  Vec3 relative_angular_velocity; // omega_i - omega_j, rad/s
  double effective_radius = 0;    // R*, m
  double effective_mass = 0;      // m*, kg
};

struct ContactOutput {
  Vec3 force_on_i;          // N, applied at the contact point
  Vec3 rolling_torque_on_i; // N m
  double normal_force = 0;  // N, signed (negative when damping pulls)
};

KOKKOS_INLINE_FUNCTION Vec3 project_on_plane(Vec3 a, Vec3 unit_normal) {
  return a - dot(a, unit_normal) * unit_normal;
}

// Rotates a stored tangential vector onto the current tangent plane, keeping its length (one
// square root of the ratio of squared lengths; a fresh contact's zero vector costs none). A
// vector within 1e-12 rad of the normal has no direction left in the plane: dropped.
KOKKOS_INLINE_FUNCTION Vec3 rotate_onto_plane(Vec3 a, Vec3 unit_normal) {
  const double old_length2 = norm2(a);
  if (old_length2 == 0)
    return Vec3{};
  const Vec3 projected = project_on_plane(a, unit_normal);
  const double new_length2 = norm2(projected);
  if (!(new_length2 > 1e-24 * old_length2))
    return Vec3{};
  return math::sqrt(old_length2 / new_length2) * projected;
}

template <bool RollingResistance>
KOKKOS_INLINE_FUNCTION ContactOutput hertz_mindlin(const PairCoefficients& c,
                                                   const ContactInput& in, double dt,
                                                   ContactHistory& history) {
  ContactOutput out;
  const Vec3 n = in.geometry.normal;
  const double overlap = in.geometry.overlap;
  const double contact_radius = math::sqrt(in.effective_radius * overlap); // a = sqrt(R* d)
  const double normal_stiffness = 2.0 * c.effective_youngs * contact_radius;
  const double tangential_stiffness = 8.0 * c.effective_shear * contact_radius;

  const double normal_velocity = dot(in.relative_velocity, n);
  const double elastic_normal = 2.0 / 3.0 * normal_stiffness * overlap; // 4/3 E* sqrt(R*) d^1.5
  const double normal_damping =
      c.damping * math::sqrt(normal_stiffness * in.effective_mass) * normal_velocity;
  const double normal_force = elastic_normal - normal_damping;
  const double friction_limit = c.friction * math::max(normal_force, 0.0);

  const Vec3 tangential_velocity = in.relative_velocity - normal_velocity * n;
  Vec3 spring = rotate_onto_plane(history.tangential_spring, n) + dt * tangential_velocity;
  Vec3 tangential_force = -tangential_stiffness * spring;
  const double spring_force2 = norm2(tangential_force);
  if (spring_force2 > friction_limit * friction_limit) { // sliding: the root only then
    const double scale = friction_limit / math::sqrt(spring_force2);
    spring = scale * spring;
    tangential_force = scale * tangential_force;
  } else {
    tangential_force -=
        c.damping * math::sqrt(tangential_stiffness * in.effective_mass) * tangential_velocity;
  }
  history.tangential_spring = spring;
  out.force_on_i = normal_force * n + tangential_force;
  out.normal_force = normal_force;

  if constexpr (RollingResistance) {
    const double rolling_stiffness = 2.25 * normal_stiffness * c.rolling_friction *
                                     c.rolling_friction * in.effective_radius * in.effective_radius;
    const Vec3 rolling_velocity = project_on_plane(in.relative_angular_velocity, n);
    Vec3 torque =
        rotate_onto_plane(history.rolling_torque, n) - (rolling_stiffness * dt) * rolling_velocity;
    const double limit = c.rolling_friction * in.effective_radius * math::max(normal_force, 0.0);
    const double magnitude = norm(torque);
    if (magnitude > limit)
      torque = (magnitude > 0 ? limit / magnitude : 0.0) * torque;
    history.rolling_torque = torque;
    out.rolling_torque_on_i = torque;
  }
  return out;
}

// A contact law, the pair and wall loops' template parameter: the force at one contact point
// from its geometry, relative motion and history.
//   static constexpr bool rolling;   it keeps a rolling torque (the slots then store one)
//   static ContactOutput force(const PairCoefficients&, const ContactInput&, double dt,
//                              ContactHistory&)
// A law with other per-pair constants or history extends PairCoefficients and ContactHistory
// (their storage is per slot in PairList and WallContactList).
template <bool RollingResistance> struct HertzMindlin {
  static constexpr bool rolling = RollingResistance;

  KOKKOS_INLINE_FUNCTION static ContactOutput
  force(const PairCoefficients& c, const ContactInput& in, double dt, ContactHistory& history) {
    return hertz_mindlin<RollingResistance>(c, in, dt, history);
  }
};

} // namespace kdem
