#pragma once
// Velocity Verlet for translation; for rotation of spheres (isotropic inertia) the angular
// velocity is kicked by the same half steps and the orientation advanced by the exact rotation
// of omega dt, then renormalised.
#include "particles.hpp"
#include "view_access.hpp"

namespace kdem {

// Half kick of velocities, then the drift of positions and orientations.
inline void kick_and_drift(const ParticleViews& p, double dt) {
  auto x = p.position, v = p.velocity, w = p.angular_velocity;
  auto q = p.orientation;
  auto force = p.force, torque = p.torque;
  auto mass = p.mass;
  auto inertia = p.inertia;
  Kokkos::parallel_for(
      "kdem::kick_and_drift", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        const Vec3 vi = load3(v, i) + (0.5 * dt / mass(i)) * load3(force, i);
        const Vec3 wi = load3(w, i) + (0.5 * dt / inertia(i, 0)) * load3(torque, i);
        store3(v, i, vi);
        store3(w, i, wi);
        store3(x, i, load3(x, i) + dt * vi);
        store_quat(q, i, normalized(quat_from_rotation_vector(dt * wi) * load_quat(q, i)));
      });
}

inline void kick(const ParticleViews& p, double dt) {
  auto v = p.velocity, w = p.angular_velocity;
  auto force = p.force, torque = p.torque;
  auto mass = p.mass;
  auto inertia = p.inertia;
  Kokkos::parallel_for(
      "kdem::kick", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        store3(v, i, load3(v, i) + (0.5 * dt / mass(i)) * load3(force, i));
        store3(w, i, load3(w, i) + (0.5 * dt / inertia(i, 0)) * load3(torque, i));
      });
}

} // namespace kdem
