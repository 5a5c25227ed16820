#pragma once
// Velocity Verlet for translation. Rotation has two integrators:
// - spheres (isotropic inertia): the angular velocity is kicked by the same half steps and the
//   orientation advanced by the exact rotation of omega dt, then renormalised;
// - rigid bodies with principal inertias I1, I2, I3 (families with rigid_rotation): the angular
// momentum is
//   kicked by the torque, and the free rotation in between is the symmetric splitting of
//   Dullweber, Leimkuhler & McLachlan (J. Chem. Phys. 107 (1997) 5840), the "NO_SQUISH" scheme
//   of Miller et al. (J. Chem. Phys. 116 (2002) 8649) cited by the book (Ch. 6): exact
//   rotations about body axes 1, 2, 3, 2, 1 for dt/2, dt/2, dt, dt/2, dt/2. It is symplectic
//   and time-reversible, keeps |L| exactly and the energy of a free body without drift.
#include "particles.hpp"
#include "view_access.hpp"

namespace kdem {

KOKKOS_INLINE_FUNCTION Vec3 componentwise(Vec3 a, Vec3 b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
KOKKOS_INLINE_FUNCTION Vec3 componentwise_divide(Vec3 a, Vec3 b) {
  return {a.x / b.x, a.y / b.y, a.z / b.z};
}

// World angular momentum of a body with principal inertia `inertia` (body frame).
KOKKOS_INLINE_FUNCTION Vec3 angular_momentum(Quat q, Vec3 inertia, Vec3 omega_world) {
  return rotate(q, componentwise(inertia, rotate_inverse(q, omega_world)));
}

// Free rotation for time h about body axis `axis` (0, 1, 2): the body turns by
// phi = h pi_k / I_k about that axis, and the body-frame momentum pi turns by -phi. Forced
// inline: the five calls of free_rotation, each with a constant axis, then fold to straight code
// with one half-angle sine and cosine per angle; left to the compiler's unit-wide budget, a larger
// translation unit once made it a call (+16 % instructions in the superquadric integration).
KOKKOS_FORCEINLINE_FUNCTION void rotate_about_body_axis(int axis, double h, Vec3 inertia, Quat& q,
                                                        Vec3& body_momentum) {
  double pi_[3] = {body_momentum.x, body_momentum.y, body_momentum.z};
  const double inertia_[3] = {inertia.x, inertia.y, inertia.z};
  const double phi = h * pi_[axis] / inertia_[axis];
  double half_sine = 0, half_cosine = 1; // sin(phi), cos(phi) from those of phi / 2
  half_angle_sine_cosine(phi, half_sine, half_cosine);
  const double c = 1.0 - 2.0 * half_sine * half_sine, s = 2.0 * half_sine * half_cosine;
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const double pa = pi_[a], pb = pi_[b];
  pi_[a] = c * pa + s * pb;
  pi_[b] = -s * pa + c * pb;
  body_momentum = Vec3{pi_[0], pi_[1], pi_[2]};
  double half[3] = {0, 0, 0};
  half[axis] = half_sine;
  q = q * Quat{half_cosine, half[0], half[1], half[2]};
}

// The free rotation for dt of a body with body-frame angular momentum `body_momentum`, which it
// turns with the body: R pi, the world momentum, stays what it was (to rounding).
KOKKOS_INLINE_FUNCTION Quat free_rotation(Quat q, Vec3 inertia, Vec3& body_momentum, double dt) {
  rotate_about_body_axis(0, 0.5 * dt, inertia, q, body_momentum);
  rotate_about_body_axis(1, 0.5 * dt, inertia, q, body_momentum);
  rotate_about_body_axis(2, dt, inertia, q, body_momentum);
  rotate_about_body_axis(1, 0.5 * dt, inertia, q, body_momentum);
  rotate_about_body_axis(0, 0.5 * dt, inertia, q, body_momentum);
  return normalized(q);
}

// Rotation of a sphere: omega kicked by torque / I, orientation turned by omega dt.
struct IsotropicRotation {
  static constexpr bool bounds_turning = false; // spheres: no shape turns with them
  KOKKOS_INLINE_FUNCTION static Vec3 kicked(Quat, Vec3 inertia, Vec3 omega, Vec3 torque, double h) {
    return omega + (h / inertia.x) * torque;
  }
  KOKKOS_INLINE_FUNCTION static void kick_and_turn(Quat& q, Vec3& omega, Vec3 inertia, Vec3 torque,
                                                   double dt) {
    omega = kicked(q, inertia, omega, torque, 0.5 * dt);
    q = normalized(quat_from_rotation_vector(dt * omega) * q);
  }
};

// Rotation of a rigid body: angular momentum L = R diag(I) R^T omega kicked by the torque, then
// the free rotation. Written for omega and the body-frame momentum, so that a step turns five
// vectors by q where going through the world momentum takes nine: the kick of L by h T is the
// kick of omega by R diag(1/I) R^T h T, and after the free rotation omega = R_new (pi / I).
struct RigidBodyRotation {
  static constexpr bool bounds_turning = true; // keeps ParticleViews::turned_angle
  KOKKOS_INLINE_FUNCTION static Vec3 kicked(Quat q, Vec3 inertia, Vec3 omega, Vec3 torque,
                                            double h) {
    return omega + rotate(q, componentwise_divide(rotate_inverse(q, h * torque), inertia));
  }
  KOKKOS_INLINE_FUNCTION static void kick_and_turn(Quat& q, Vec3& omega, Vec3 inertia, Vec3 torque,
                                                   double dt) {
    Vec3 body_momentum =
        componentwise(inertia, rotate_inverse(q, omega)) + rotate_inverse(q, (0.5 * dt) * torque);
    q = free_rotation(q, inertia, body_momentum, dt);
    omega = rotate(q, componentwise_divide(body_momentum, inertia));
  }
};

// An upper bound on the angle of the rotation from orientation a to b, in [0, pi]: with
// d = b a^-1, the angle is 2 atan(|vec d| / |w d|) <= 2 |vec d| / |w d|, without a
// transcendental call.
KOKKOS_INLINE_FUNCTION double rotation_angle_bound(Quat a, Quat b) {
  const Quat d = b * Quat{a.w, -a.x, -a.y, -a.z};
  const double sine = math::sqrt(d.x * d.x + d.y * d.y + d.z * d.z), cosine = math::fabs(d.w);
  constexpr double pi = 3.14159265358979323846;
  return 2.0 * sine < pi * cosine ? 2.0 * sine / cosine : pi;
}

// Half kick of velocities, then the drift of positions and orientations; rigid bodies also add
// the angle they turned to turned_angle and return how far any point of their surfaces moved at
// most (|v dt| + turned angle x bounding radius, the bound of the separation certificates;
// unbounded_travel where that is not finite, a particle gone wrong, so that every certificate
// expires); spheres, which no certificate tracks, return 0.
constexpr double unbounded_travel = 1e300;

template <class Rotation = IsotropicRotation>
double kick_and_drift(const ParticleViews& p, double dt) {
  auto x = p.position, v = p.velocity, w = p.angular_velocity;
  auto q = p.orientation;
  auto force = p.force, torque = p.torque;
  auto mass = p.mass;
  auto inertia = p.inertia;
  auto turned = p.turned_angle;
  auto radius = p.radius;
  const auto advance = KOKKOS_LAMBDA(int i) {
    const Vec3 vi = load3(v, i) + (0.5 * dt / mass(i)) * load3(force, i);
    store3(v, i, vi);
    store3(x, i, load3(x, i) + dt * vi);
    Quat qi = load_quat(q, i);
    Vec3 wi = load3(w, i);
    const Quat before = qi;
    Rotation::kick_and_turn(qi, wi, load3(inertia, i), load3(torque, i), dt);
    double travel = dt * norm(vi);
    if (Rotation::bounds_turning) { // not constexpr: nvcc will not capture in that context
      const double angle = rotation_angle_bound(before, qi);
      turned(i) += angle;
      travel += angle * radius(i);
    }
    store_quat(q, i, qi);
    store3(w, i, wi);
    const double bound = unbounded_travel; // its value, not the host variable, in device code
    return travel < bound ? travel : bound;
  };
  if (!Rotation::bounds_turning) {
    Kokkos::parallel_for(
        "kdem::kick_and_drift", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) { advance(i); });
    return 0;
  }
  double farthest = 0;
  Kokkos::parallel_reduce(
      "kdem::kick_and_drift", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, double& largest) {
        const double travel = advance(i);
        largest = travel > largest ? travel : largest;
      },
      Kokkos::Max<double>(farthest));
  // Over no particles (a scene that rains them in) the reduction gives its identity, -inf,
  // which would stop the surface travel, and every certificate with it, for good.
  return math::max(farthest, 0.0);
}

// The second half kick of velocities.
template <class Rotation = IsotropicRotation> void kick(const ParticleViews& p, double dt) {
  auto v = p.velocity, w = p.angular_velocity;
  auto q = p.orientation;
  auto force = p.force, torque = p.torque;
  auto mass = p.mass;
  auto inertia = p.inertia;
  Kokkos::parallel_for(
      "kdem::kick", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        store3(v, i, load3(v, i) + (0.5 * dt / mass(i)) * load3(force, i));
        store3(w, i,
               Rotation::kicked(load_quat(q, i), load3(inertia, i), load3(w, i), load3(torque, i),
                                0.5 * dt));
      });
}

// Instantiated once, in src/engine.cpp. nvcc gives each translation unit its own hidden
// helper for an extended lambda; were a test and the engine each to instantiate these
// templates, the linker would keep one copy, which may call the other unit's helper before it
// is set (a call through a null pointer, seen on CUDA). scripts/check_cuda_lambdas.sh guards
// against a lambda-holding template compiled in two units.
extern template double kick_and_drift<IsotropicRotation>(const ParticleViews&, double);
extern template double kick_and_drift<RigidBodyRotation>(const ParticleViews&, double);
extern template void kick<IsotropicRotation>(const ParticleViews&, double);
extern template void kick<RigidBodyRotation>(const ParticleViews&, double);

inline double kick_and_drift_rigid(const ParticleViews& p, double dt) {
  return kick_and_drift<RigidBodyRotation>(p, dt);
}

inline void kick_rigid(const ParticleViews& p, double dt) {
  kick<RigidBodyRotation>(p, dt);
}

} // namespace kdem
