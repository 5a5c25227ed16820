#pragma once
// Structure-of-arrays particle store in the execution space's memory.
#include <string>
#include <type_traits>
#include <utility>

#include "types.hpp"

namespace kdem {

struct ParticleViews {
  int count = 0;
  Vec3View position;         // m
  Vec3View velocity;         // m/s
  Vec3View angular_velocity; // rad/s, world frame
  QuatView orientation;      // body to world
  Vec3View force;            // N
  Vec3View torque;           // N m, world frame
  ScalarView radius;         // m
  ScalarView mass;           // kg
  Vec3View inertia;          // kg m^2, principal moments in the body frame
  IndexView material;
  IndexView shape;
  IndexView source;           // the scene source that made it (its index), -1: added by the program
  IndexView tag;              // index of its source's tag among the scene's tags, -1: none
  IdView id;                  // stable across sorting, restarts and deletion
  Vec3View position_at_build; // positions when the candidate lists were last built
  // rad, an upper bound on the total angle the particle has turned since it was created (summed
  // per step; rigid-body rotation only): separation certificates of pairs use its growth.
  ScalarView turned_angle;

  void allocate(int n) {
    count = n;
    position = Vec3View("position", n);
    velocity = Vec3View("velocity", n);
    angular_velocity = Vec3View("angular_velocity", n);
    orientation = QuatView("orientation", n);
    force = Vec3View("force", n);
    torque = Vec3View("torque", n);
    radius = ScalarView("radius", n);
    mass = ScalarView("mass", n);
    inertia = Vec3View("inertia", n);
    material = IndexView("material", n);
    shape = IndexView("shape", n);
    source = IndexView("source", n);
    tag = IndexView("tag", n);
    id = IdView("id", n);
    position_at_build = Vec3View("position_at_build", n);
    turned_angle = ScalarView("turned_angle", n);
  }
};

// Every per-particle field, as (name, member pointer), so that copying, permuting and
// checkpointing cover all fields without listing them again.
template <class Visitor> void for_each_particle_field(Visitor&& visit) {
  visit("position", &ParticleViews::position);
  visit("velocity", &ParticleViews::velocity);
  visit("angular_velocity", &ParticleViews::angular_velocity);
  visit("orientation", &ParticleViews::orientation);
  visit("force", &ParticleViews::force);
  visit("torque", &ParticleViews::torque);
  visit("radius", &ParticleViews::radius);
  visit("mass", &ParticleViews::mass);
  visit("inertia", &ParticleViews::inertia);
  visit("material", &ParticleViews::material);
  visit("shape", &ParticleViews::shape);
  visit("source", &ParticleViews::source);
  visit("tag", &ParticleViews::tag);
  visit("id", &ParticleViews::id);
  visit("position_at_build", &ParticleViews::position_at_build);
  visit("turned_angle", &ParticleViews::turned_angle);
}

// new_field(k) = old_field(source(k)) for every field; `source` has new_count entries.
template <class T>
DeviceView<T*> gather_rows(const DeviceView<T*>& old_field, const IndexView& source,
                           int new_count) {
  auto result = uninitialized<DeviceView<T*>>(old_field.label(), new_count);
  Kokkos::parallel_for(
      "kdem::gather_rows", RangePolicy(0, new_count),
      KOKKOS_LAMBDA(int k) { result(k) = old_field(source(k)); });
  return result;
}

template <class T, std::size_t N>
DeviceView<T* [N]> gather_rows(const DeviceView<T* [N]>& old_field, const IndexView& source,
                               int new_count) {
  auto result = uninitialized<DeviceView<T* [N]>>(old_field.label(), new_count);
  Kokkos::parallel_for(
      "kdem::gather_rows", RangePolicy(0, new_count), KOKKOS_LAMBDA(int k) {
        for (std::size_t c = 0; c < N; ++c)
          result(k, c) = old_field(source(k), c);
      });
  return result;
}

inline void permute_particles(ParticleViews& p, const IndexView& source, int new_count) {
  for_each_particle_field(
      [&](const char*, auto member) { p.*member = gather_rows(p.*member, source, new_count); });
  p.count = new_count;
}

// Copies the first `rows` rows of every field of `from` into `to`, from row first_row_in_to on.
inline void copy_particle_rows(const ParticleViews& from, ParticleViews& to, int rows,
                               int first_row_in_to = 0) {
  for_each_particle_field([&](const char*, auto member) {
    const auto source = std::make_pair(0, rows);
    const auto target = std::make_pair(first_row_in_to, first_row_in_to + rows);
    if constexpr (std::decay_t<decltype(from.*member)>::rank == 1)
      Kokkos::deep_copy(Kokkos::subview(to.*member, target), Kokkos::subview(from.*member, source));
    else
      Kokkos::deep_copy(Kokkos::subview(to.*member, target, Kokkos::ALL),
                        Kokkos::subview(from.*member, source, Kokkos::ALL));
  });
}

} // namespace kdem
