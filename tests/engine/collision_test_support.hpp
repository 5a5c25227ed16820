#pragma once
// Elastic collisions through the whole engine, shared by the shaped families' engine tests: the
// kinetic energy, an elastic frictionless scene, and a run until two bodies have touched and
// parted.
#include <algorithm>

#include "scene_builders.hpp"

namespace kdem::testing {

inline double kinetic_energy(const Engine& engine) {
  const Diagnostics d = engine.diagnostics();
  return d.translational_energy + d.rotational_energy;
}

// Glass, restitution 1, no friction, no gravity; a step of 0.2 us.
inline SceneConfig elastic_scene() {
  return empty_scene(2e-7, {material("glass", 2500, 1e8, 0.3, 1.0, 0.0)});
}

struct Collision {
  double before = 0, after = 0;
  int pair_contacts = 0;
};

// Runs until the bodies have touched and separated; kinetic energy before and after.
inline Collision collide(Engine& engine, int max_steps) {
  Collision c;
  c.before = kinetic_energy(engine);
  bool touched = false;
  for (int k = 0; k < max_steps; ++k) {
    engine.step();
    const int contacts = engine.diagnostics().pair_contacts;
    c.pair_contacts = std::max(c.pair_contacts, contacts);
    touched = touched || contacts > 0;
    if (touched && contacts == 0)
      break;
  }
  c.after = kinetic_energy(engine);
  return c;
}

} // namespace kdem::testing
