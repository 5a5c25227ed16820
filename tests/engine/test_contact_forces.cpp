// The contact-force record (Engine::contact_forces, written with each frame when the scene's
// output asks for it): a column of three spheres at rest on a plane, each contact carrying the
// weight above it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scene_builders.hpp"

namespace kdem::testing {
namespace {

TEST(ContactForces, AColumnAtRestCarriesTheWeightAboveEachContact) {
  // Equal spheres stacked on a plane, settled by damping (restitution 0.2) for 0.1 s. Each pair
  // force and the wall force equal the weight above (stated 1e-6: what the damped settling
  // leaves of the bodies' motion, below 1e-9 m/s).
  const double r = 1e-3, density = 2500, g = 9.81;
  SceneConfig scene = empty_scene(1e-6, {material("glass", density, 1e8, 0.3, 0.2, 0.3)});
  scene.gravity = {0, 0, -g};
  scene.walls.push_back(plane_wall("glass", {0, 0, 0}, {0, 0, 1}));
  Engine engine(scene);
  engine.add_particles({sphere({0, 0, r}, r), sphere({0, 0, 3 * r}, r), sphere({0, 0, 5 * r}, r)});
  for (int k = 0; k < 100000; ++k)
    engine.step();
  const double weight = density * 4.0 / 3.0 * 3.14159265358979323846 * r * r * r * g;
  const ParticleSnapshot s = engine.snapshot();
  const auto height_of = [&](std::int64_t id) {
    for (std::size_t i = 0; i < s.size(); ++i)
      if (s.id[i] == id)
        return s.position[3 * i + 2];
    return -1.0;
  };
  const std::vector<ContactForceRecord> records = engine.contact_forces();
  ASSERT_EQ(records.size(), 3u);
  int pairs = 0, walls = 0;
  for (const ContactForceRecord& c : records) {
    EXPECT_NEAR(c.force[0], 0, 1e-12);
    EXPECT_NEAR(c.force[1], 0, 1e-12);
    if (c.wall >= 0) {
      ++walls;
      EXPECT_EQ(c.partner, -1);
      EXPECT_EQ(c.wall, 0);
      EXPECT_NEAR(c.force[2], 3 * weight, 1e-6 * weight);
      continue;
    }
    ++pairs;
    // The force on `id` from `partner`: upward when `id` is the upper one. Spheres above the
    // contact: 2 for the lower contact, 1 for the upper.
    const bool upper = height_of(c.id) > height_of(c.partner);
    const double lower_of_two = std::min(height_of(c.id), height_of(c.partner));
    const double above = lower_of_two < 2 * r ? 2 : 1;
    EXPECT_NEAR(c.force[2], (upper ? 1 : -1) * above * weight, 1e-6 * weight);
  }
  EXPECT_EQ(pairs, 2);
  EXPECT_EQ(walls, 1);
}

} // namespace
} // namespace kdem::testing
