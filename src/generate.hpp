#pragma once
// Particle generation: sizes from a distribution, positions in a region without overlaps.
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "scene.hpp"

namespace kdem {

struct ParticleSeed {
  Vec3d position{0, 0, 0};
  Vec3d velocity{0, 0, 0};
  Vec3d angular_velocity{0, 0, 0};
  std::array<double, 4> orientation{1, 0, 0, 0}; // unit quaternion (w, x, y, z)
  double radius = 0;
};

// Spheres already in the scene that new particles must not overlap, and the walls they must not
// cross.
struct Obstacles {
  std::vector<Vec3d> centres;
  std::vector<double> radii;
  // Whether a sphere would touch or reach through a wall's surface; empty: no walls.
  std::function<bool(const Vec3d& centre, double radius)> crosses_wall;
};

// Places up to `max_new` particles of `source` (random sequential addition) in its region, each
// entirely inside the region, overlapping neither each other nor `obstacles`, and crossing no
// wall of `obstacles.crosses_wall`. When the source has a volume_fraction, it also stops once
// the placed solid volume reaches that fraction of the region volume. It gives up after
// `max_failed_attempts` consecutive rejected trials and returns what it placed. Deterministic
// for a given rng state.
std::vector<ParticleSeed> generate_particles(const ParticleSourceConfig& source,
                                             std::int64_t max_new, const Obstacles& obstacles,
                                             std::mt19937_64& rng, int max_failed_attempts = 2000);

// Draws one radius from the source's size distribution. Discrete mixtures are given by mass
// fraction, so class k is drawn with probability proportional to fraction_k / r_k^3.
double draw_radius(const SizeDistributionConfig& sizes, std::mt19937_64& rng);

// The smallest and largest radius draw_radius can return.
struct RadiusRange {
  double smallest = 0, largest = 0;
};
RadiusRange possible_radii(const SizeDistributionConfig& sizes);

// Volume of a region, m^3.
double region_volume(const RegionConfig& region);

} // namespace kdem
