// Tests of the particle generator: geometry (inside, no overlap), counts and volume fraction,
// size distribution statistics, obstacles, orientations and determinism.
//
// Statistical checks compare a sample mean with its expectation within 3 standard errors. For
// a correct sampler that holds with probability 99.7%; the seeds are fixed, so each check is
// either always or never met, never flaky. A wrong sampler (no truncation, number fractions
// taken for mass fractions, ...) misses by tens to hundreds of standard errors.
#include "src/generate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace kdem {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Rounding slack for geometric checks: the generator compares squared distances exactly, but
// recomputing them here in another order may differ in the last bits.
constexpr double kRoundingSlack = 1e-12;

double sphere_volume(double radius) {
  return 4.0 / 3.0 * kPi * radius * radius * radius;
}

double distance(const Vec3d& a, const Vec3d& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

SizeDistributionConfig monodisperse(double radius) {
  SizeDistributionConfig sizes;
  sizes.kind = SizeDistributionConfig::Kind::Monodisperse;
  sizes.radius = radius;
  return sizes;
}

SizeDistributionConfig uniform_sizes(double min_radius, double max_radius) {
  SizeDistributionConfig sizes;
  sizes.kind = SizeDistributionConfig::Kind::Uniform;
  sizes.min_radius = min_radius;
  sizes.max_radius = max_radius;
  return sizes;
}

SizeDistributionConfig gaussian_sizes(double mean, double std, double min_radius,
                                      double max_radius) {
  SizeDistributionConfig sizes;
  sizes.kind = SizeDistributionConfig::Kind::Gaussian;
  sizes.mean_radius = mean;
  sizes.std_radius = std;
  sizes.min_radius = min_radius;
  sizes.max_radius = max_radius;
  return sizes;
}

SizeDistributionConfig discrete_sizes(std::vector<double> radii,
                                      std::vector<double> mass_fractions) {
  SizeDistributionConfig sizes;
  sizes.kind = SizeDistributionConfig::Kind::Discrete;
  sizes.radii = std::move(radii);
  sizes.mass_fractions = std::move(mass_fractions);
  return sizes;
}

RegionConfig box_region(const Vec3d& min, const Vec3d& max) {
  RegionConfig region;
  region.kind = RegionConfig::Kind::Box;
  region.min = min;
  region.max = max;
  return region;
}

RegionConfig cylinder_region(const Vec3d& base_center, double radius, double height) {
  RegionConfig region;
  region.kind = RegionConfig::Kind::Cylinder;
  region.base_center = base_center;
  region.radius = radius;
  region.height = height;
  return region;
}

ParticleSourceConfig source_in(const RegionConfig& region, const SizeDistributionConfig& sizes) {
  ParticleSourceConfig source;
  source.region = region;
  source.sizes = sizes;
  return source;
}

std::vector<ParticleSeed> generate(const ParticleSourceConfig& source, std::int64_t max_new,
                                   std::uint64_t seed, const Obstacles& obstacles = {}) {
  std::mt19937_64 rng(seed);
  return generate_particles(source, max_new, obstacles, rng);
}

// Brute force over all pairs.
std::int64_t count_overlapping_pairs(const std::vector<ParticleSeed>& particles) {
  std::int64_t overlapping = 0;
  for (std::size_t i = 0; i < particles.size(); ++i)
    for (std::size_t j = i + 1; j < particles.size(); ++j) {
      const double contact = particles[i].radius + particles[j].radius;
      if (distance(particles[i].position, particles[j].position) < contact * (1 - kRoundingSlack))
        ++overlapping;
    }
  return overlapping;
}

std::int64_t count_overlapping_obstacles(const std::vector<ParticleSeed>& particles,
                                         const Obstacles& obstacles) {
  std::int64_t overlapping = 0;
  for (const ParticleSeed& particle : particles)
    for (std::size_t k = 0; k < obstacles.centres.size(); ++k) {
      const double contact = particle.radius + obstacles.radii[k];
      if (distance(particle.position, obstacles.centres[k]) < contact * (1 - kRoundingSlack))
        ++overlapping;
    }
  return overlapping;
}

bool sphere_inside_box(const RegionConfig& box, const ParticleSeed& particle) {
  for (int axis = 0; axis < 3; ++axis) {
    const double slack = kRoundingSlack * (box.max[axis] - box.min[axis]);
    if (particle.position[axis] - particle.radius < box.min[axis] - slack)
      return false;
    if (particle.position[axis] + particle.radius > box.max[axis] + slack)
      return false;
  }
  return true;
}

double radial_distance(const RegionConfig& cylinder, const Vec3d& point) {
  return std::hypot(point[0] - cylinder.base_center[0], point[1] - cylinder.base_center[1]);
}

bool sphere_inside_cylinder(const RegionConfig& cylinder, const ParticleSeed& particle) {
  const double slack = kRoundingSlack * (cylinder.radius + cylinder.height);
  const double bottom = cylinder.base_center[2];
  const double top = bottom + cylinder.height;
  return radial_distance(cylinder, particle.position) + particle.radius <=
             cylinder.radius + slack &&
         particle.position[2] - particle.radius >= bottom - slack &&
         particle.position[2] + particle.radius <= top + slack;
}

std::int64_t count_outside(const RegionConfig& region, const std::vector<ParticleSeed>& particles) {
  std::int64_t outside = 0;
  for (const ParticleSeed& particle : particles) {
    const bool inside = region.kind == RegionConfig::Kind::Box
                            ? sphere_inside_box(region, particle)
                            : sphere_inside_cylinder(region, particle);
    if (!inside)
      ++outside;
  }
  return outside;
}

double total_volume(const std::vector<ParticleSeed>& particles) {
  double volume = 0;
  for (const ParticleSeed& particle : particles)
    volume += sphere_volume(particle.radius);
  return volume;
}

std::vector<double> draw_radii(const SizeDistributionConfig& sizes, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> radii(static_cast<std::size_t>(count));
  for (double& radius : radii)
    radius = draw_radius(sizes, rng);
  return radii;
}

struct SampleMoments {
  double mean;
  double variance; // unbiased
};

SampleMoments moments(const std::vector<double>& values) {
  double sum = 0;
  for (double value : values)
    sum += value;
  const double mean = sum / static_cast<double>(values.size());
  double squared_deviations = 0;
  for (double value : values)
    squared_deviations += (value - mean) * (value - mean);
  return {mean, squared_deviations / static_cast<double>(values.size() - 1)};
}

bool same_bits(const ParticleSeed& a, const ParticleSeed& b) {
  return std::memcmp(a.position.data(), b.position.data(), sizeof(a.position)) == 0 &&
         std::memcmp(a.velocity.data(), b.velocity.data(), sizeof(a.velocity)) == 0 &&
         std::memcmp(a.orientation.data(), b.orientation.data(), sizeof(a.orientation)) == 0 &&
         std::memcmp(&a.radius, &b.radius, sizeof(a.radius)) == 0;
}

// --------------------------------------------------------------------------------------------
// Geometry and counts

TEST(GenerateParticles, BoxPlacesExactCountInsideWithoutOverlap) {
  const RegionConfig box = box_region({-0.5, 0.0, 2.0}, {0.5, 1.0, 2.5});
  const ParticleSourceConfig source = source_in(box, uniform_sizes(0.01, 0.03));
  const auto particles = generate(source, 2000, 7); // solid fraction about 0.17

  ASSERT_EQ(particles.size(), 2000u);
  EXPECT_EQ(count_overlapping_pairs(particles), 0);
  EXPECT_EQ(count_outside(box, particles), 0);
  // The whole box is used: some sphere comes within 2 max radii of each face.
  for (int axis = 0; axis < 3; ++axis) {
    double lowest = 1e300, highest = -1e300;
    for (const ParticleSeed& particle : particles) {
      lowest = std::min(lowest, particle.position[axis] - particle.radius);
      highest = std::max(highest, particle.position[axis] + particle.radius);
    }
    EXPECT_LT(lowest, box.min[axis] + 0.06) << "axis " << axis;
    EXPECT_GT(highest, box.max[axis] - 0.06) << "axis " << axis;
  }
}

TEST(GenerateParticles, CylinderPlacesExactCountInsideWithoutOverlap) {
  const RegionConfig cylinder = cylinder_region({1.0, -2.0, 0.5}, 0.3, 0.8);
  const ParticleSourceConfig source = source_in(cylinder, monodisperse(0.02));
  const auto particles = generate(source, 1500, 11); // solid fraction about 0.22

  ASSERT_EQ(particles.size(), 1500u);
  EXPECT_EQ(count_overlapping_pairs(particles), 0);
  EXPECT_EQ(count_outside(cylinder, particles), 0);
  // Spread over the whole cylinder, not its bounding box or a smaller disk.
  double largest_radial = 0, lowest = 1e300, highest = -1e300;
  for (const ParticleSeed& particle : particles) {
    largest_radial = std::max(largest_radial, radial_distance(cylinder, particle.position));
    lowest = std::min(lowest, particle.position[2]);
    highest = std::max(highest, particle.position[2]);
  }
  EXPECT_GT(largest_radial, 0.3 - 0.02 - 0.02);
  EXPECT_LT(lowest, 0.5 + 0.02 + 0.02);
  EXPECT_GT(highest, 1.3 - 0.02 - 0.02);
}

TEST(GenerateParticles, EveryParticleGetsTheSourceVelocityAndRadiusFromTheDistribution) {
  ParticleSourceConfig source = source_in(box_region({0, 0, 0}, {1, 1, 1}), monodisperse(0.05));
  source.velocity = {0.5, -1.5, 2.0};
  const auto particles = generate(source, 100, 3);
  ASSERT_EQ(particles.size(), 100u);
  for (const ParticleSeed& particle : particles) {
    EXPECT_EQ(particle.velocity, source.velocity);
    EXPECT_EQ(particle.radius, 0.05);
  }
}

TEST(GenerateParticles, NothingRequestedGivesNothing) {
  const ParticleSourceConfig source =
      source_in(box_region({0, 0, 0}, {1, 1, 1}), monodisperse(0.05));
  EXPECT_TRUE(generate(source, 0, 1).empty());
}

TEST(GenerateParticles, VolumeFractionIsReachedWithinOneParticleVolume) {
  const RegionConfig box = box_region({0, 0, 0}, {1, 1, 1});
  ParticleSourceConfig source = source_in(box, uniform_sizes(0.02, 0.04));
  source.volume_fraction = 0.3;
  const auto particles = generate(source, 1'000'000, 5);

  const double target = 0.3 * region_volume(box);
  const double placed = total_volume(particles);
  EXPECT_GE(placed, target);
  EXPECT_LT(placed, target + sphere_volume(0.04));
  EXPECT_LT(particles.size(), 1'000'000u);
  EXPECT_EQ(count_overlapping_pairs(particles), 0);
  EXPECT_EQ(count_outside(box, particles), 0);
}

TEST(GenerateParticles, VolumeFractionSourceStillStopsAtMaxNew) {
  ParticleSourceConfig source = source_in(box_region({0, 0, 0}, {1, 1, 1}), monodisperse(0.02));
  source.volume_fraction = 0.3;
  EXPECT_EQ(generate(source, 50, 5).size(), 50u);
}

TEST(GenerateParticles, VolumeFractionInCylinder) {
  const RegionConfig cylinder = cylinder_region({0, 0, -1}, 0.4, 1.0);
  ParticleSourceConfig source = source_in(cylinder, discrete_sizes({0.02, 0.04}, {0.5, 0.5}));
  source.volume_fraction = 0.25;
  const auto particles = generate(source, 1'000'000, 9);

  const double target = 0.25 * region_volume(cylinder);
  EXPECT_GE(total_volume(particles), target);
  EXPECT_LT(total_volume(particles), target + sphere_volume(0.04));
  EXPECT_EQ(count_overlapping_pairs(particles), 0);
  EXPECT_EQ(count_outside(cylinder, particles), 0);
}

TEST(GenerateParticles, GivesUpWithFewerParticlesWhenTheRegionIsFull) {
  const RegionConfig box = box_region({0, 0, 0}, {0.1, 0.1, 0.1});
  const ParticleSourceConfig source = source_in(box, monodisperse(0.02));
  // At most about 0.38 / (4.19e-3 / 0.216) ~ 20 such spheres can go in at random.
  const auto particles = generate(source, 10'000, 13);

  EXPECT_GT(particles.size(), 0u);
  EXPECT_LT(particles.size(), 100u);
  EXPECT_EQ(count_overlapping_pairs(particles), 0);
  EXPECT_EQ(count_outside(box, particles), 0);
}

TEST(GenerateParticles, GivesUpAtOnceWhenNoParticleFits) {
  const ParticleSourceConfig box_source =
      source_in(box_region({0, 0, 0}, {1, 1, 0.03}), monodisperse(0.02));
  EXPECT_TRUE(generate(box_source, 10, 1).empty());
  const ParticleSourceConfig cylinder_source =
      source_in(cylinder_region({0, 0, 0}, 0.015, 1.0), monodisperse(0.02));
  EXPECT_TRUE(generate(cylinder_source, 10, 1).empty());
}

TEST(GenerateParticles, ObstaclesAreRespected) {
  const RegionConfig box = box_region({0, 0, 0}, {1, 1, 1});
  Obstacles obstacles;
  // Larger than the new particles: a big ball in the middle and one poking in through x = 1.
  obstacles.centres.push_back({0.5, 0.5, 0.5});
  obstacles.radii.push_back(0.3);
  obstacles.centres.push_back({1.1, 0.5, 0.5});
  obstacles.radii.push_back(0.25);
  // As large as the new particles: a lattice of them, some with centres just outside the box.
  for (double x = -0.01; x < 1.0; x += 0.1)
    for (double y = -0.01; y < 1.0; y += 0.1)
      for (double z = 0.05; z < 1.0; z += 0.2) {
        obstacles.centres.push_back({x, y, z});
        obstacles.radii.push_back(0.02);
      }
  // Far away: must not matter.
  obstacles.centres.push_back({50, 50, 50});
  obstacles.radii.push_back(10);

  const ParticleSourceConfig source = source_in(box, monodisperse(0.02));
  const auto particles = generate(source, 3000, 17, obstacles);

  // The big ball alone holds 11% of the box: 3000 particles placed ignoring it would hit it
  // about 300 times.
  ASSERT_EQ(particles.size(), 3000u);
  EXPECT_EQ(count_overlapping_obstacles(particles, obstacles), 0);
  EXPECT_EQ(count_overlapping_pairs(particles), 0);
  EXPECT_EQ(count_outside(box, particles), 0);
}

// A particle gone wrong (NaN position) between two run checks is an obstacle of the next
// insertion: it blocks nothing, and its cell is not an undefined conversion of NaN (found by the
// checkpoint_reader fuzz target: rain falling among NaN particles).
TEST(GenerateParticles, ObstaclesAtNaNBlockNothing) {
  const RegionConfig box = box_region({0, 0, 0}, {1, 1, 1});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Obstacles obstacles;
  for (const Vec3d& centre : {Vec3d{nan, 0.5, 0.5}, Vec3d{0.5, nan, nan}, Vec3d{nan, nan, nan}}) {
    obstacles.centres.push_back(centre);
    obstacles.radii.push_back(0.3); // larger than the new particles: binned on their own grid
  }
  const auto particles = generate(source_in(box, monodisperse(0.05)), 200, 4, obstacles);
  EXPECT_EQ(particles.size(), 200u);
  EXPECT_EQ(count_overlapping_pairs(particles), 0);
  EXPECT_EQ(count_outside(box, particles), 0);
}

TEST(GenerateParticles, ObstaclesLeaveNoRoomGivesNothing) {
  const RegionConfig box = box_region({0, 0, 0}, {1, 1, 1});
  Obstacles obstacles;
  obstacles.centres.push_back({0.5, 0.5, 0.5});
  obstacles.radii.push_back(1.0); // covers the whole box
  const auto particles = generate(source_in(box, monodisperse(0.05)), 10, 1, obstacles);
  EXPECT_TRUE(particles.empty());
}

// --------------------------------------------------------------------------------------------
// Orientations

TEST(GenerateParticles, OrientationIsIdentityWhenNotRandom) {
  ParticleSourceConfig source = source_in(box_region({0, 0, 0}, {1, 1, 1}), monodisperse(0.02));
  source.random_orientation = false;
  for (const ParticleSeed& particle : generate(source, 200, 2))
    EXPECT_EQ(particle.orientation, (std::array<double, 4>{1, 0, 0, 0}));
}

TEST(GenerateParticles, RandomOrientationsAreUniformUnitQuaternions) {
  ParticleSourceConfig source = source_in(box_region({0, 0, 0}, {10, 10, 10}), monodisperse(0.01));
  source.random_orientation = true;
  const int count = 40'000;
  const auto particles = generate(source, count, 23);
  ASSERT_EQ(particles.size(), static_cast<std::size_t>(count));

  std::array<std::vector<double>, 4> components, squares;
  for (const ParticleSeed& particle : particles) {
    const auto& q = particle.orientation;
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-14);
    for (std::size_t c = 0; c < 4; ++c) {
      components[c].push_back(q[c]);
      squares[c].push_back(q[c] * q[c]);
    }
  }
  // Uniform on the unit 3-sphere: each component has mean 0 and variance 1/4; its square has
  // mean 1/4 and variance E[q^4] - 1/16 = 3/(4*6) - 1/16 = 1/16.
  const double n = count;
  for (std::size_t c = 0; c < 4; ++c) {
    EXPECT_NEAR(moments(components[c]).mean, 0.0, 3 * std::sqrt(0.25 / n)) << "component " << c;
    EXPECT_NEAR(moments(squares[c]).mean, 0.25, 3 * std::sqrt(1.0 / 16 / n)) << "component " << c;
  }
}

// --------------------------------------------------------------------------------------------
// Size distributions

TEST(DrawRadius, MonodisperseAlwaysGivesTheRadius) {
  for (double radius : draw_radii(monodisperse(0.003), 100, 1))
    EXPECT_EQ(radius, 0.003);
}

TEST(DrawRadius, UniformMeanAndVarianceMatch) {
  const double low = 1.0, high = 3.0;
  const int n = 100'000;
  const auto radii = draw_radii(uniform_sizes(low, high), n, 29);
  for (double radius : radii) {
    ASSERT_GE(radius, low);
    ASSERT_LE(radius, high);
  }
  // Mean (a+b)/2, variance (b-a)^2/12. Standard error of the mean sqrt(var/n); of the sample
  // variance sqrt((mu4 - var^2)/n) with the fourth central moment mu4 = (b-a)^4/80.
  const double width = high - low;
  const double variance = width * width / 12;
  const double variance_error = width * width * std::sqrt((1.0 / 80 - 1.0 / 144) / n);
  const SampleMoments sample = moments(radii);
  EXPECT_NEAR(sample.mean, (low + high) / 2, 3 * std::sqrt(variance / n));
  EXPECT_NEAR(sample.variance, variance, 3 * variance_error);
}

double standard_normal_density(double x) {
  return std::exp(-0.5 * x * x) / std::sqrt(2 * kPi);
}
double standard_normal_cdf(double x) {
  return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

TEST(DrawRadius, TruncatedGaussianStaysInBoundsWithTheTruncatedMean) {
  const double mu = 1.0, sigma = 0.4, low = 0.6, high = 2.0;
  const int n = 100'000;
  const auto radii = draw_radii(gaussian_sizes(mu, sigma, low, high), n, 31);
  for (double radius : radii) {
    ASSERT_GE(radius, low);
    ASSERT_LE(radius, high);
  }
  // Truncated normal with alpha, beta the bounds in standard units and Z the mass between them:
  //   mean = mu + sigma (phi(alpha) - phi(beta)) / Z
  //   var  = sigma^2 [1 + (alpha phi(alpha) - beta phi(beta)) / Z - ((phi(alpha) - phi(beta)) /
  //   Z)^2]
  // Here the mean is 1.1075, 0.1 above the untruncated one: about 100 standard errors.
  const double alpha = (low - mu) / sigma, beta = (high - mu) / sigma;
  const double mass = standard_normal_cdf(beta) - standard_normal_cdf(alpha);
  const double density_gap =
      (standard_normal_density(alpha) - standard_normal_density(beta)) / mass;
  const double truncated_mean = mu + sigma * density_gap;
  const double truncated_variance =
      sigma * sigma *
      (1 + (alpha * standard_normal_density(alpha) - beta * standard_normal_density(beta)) / mass -
       density_gap * density_gap);
  EXPECT_NEAR(moments(radii).mean, truncated_mean, 3 * std::sqrt(truncated_variance / n));
  // The sample variance has a standard error of about var * sqrt(2/n) = 0.45% of var (near
  // normal fourth moment); 2% is over 4 of those, and far below the 30% by which ignoring the
  // truncation (variance 0.16 instead of about 0.11) would miss.
  EXPECT_NEAR(moments(radii).variance, truncated_variance, 0.02 * truncated_variance);
}

TEST(DrawRadius, DiscreteMixtureHasTheRequestedMassFractions) {
  const std::vector<double> class_radii{0.5, 1.0, 2.0};
  const std::vector<double> mass_fractions{0.2, 0.3, 0.5};
  const int n = 100'000;
  const auto radii = draw_radii(discrete_sizes(class_radii, mass_fractions), n, 37);

  std::vector<double> class_counts(class_radii.size(), 0.0);
  for (double radius : radii) {
    std::size_t k = 0;
    while (k < class_radii.size() && class_radii[k] != radius)
      ++k;
    ASSERT_LT(k, class_radii.size()) << "radius " << radius << " is no class";
    class_counts[k] += 1;
  }
  // Class volumes v_k and number probabilities p_k proportional to fraction_k / v_k.
  std::vector<double> volumes, probabilities;
  double weight_sum = 0;
  for (std::size_t k = 0; k < class_radii.size(); ++k) {
    volumes.push_back(sphere_volume(class_radii[k]));
    probabilities.push_back(mass_fractions[k] / volumes[k]);
    weight_sum += probabilities[k];
  }
  double expected_volume = 0; // M = sum_j p_j v_j
  for (std::size_t k = 0; k < class_radii.size(); ++k) {
    probabilities[k] /= weight_sum;
    expected_volume += probabilities[k] * volumes[k];
  }
  double sampled_volume = 0;
  for (std::size_t k = 0; k < class_radii.size(); ++k)
    sampled_volume += class_counts[k] * volumes[k];

  // The sampled mass fraction F_k = n_k v_k / sum_j n_j v_j is a function of the class
  // proportions; by the delta method its variance is (sum_j p_j g_j^2 - (sum_j p_j g_j)^2) / n
  // with g_j = dF_k/dp_j = (delta_kj v_k M - p_k v_k v_j) / M^2 (multinomial covariance).
  for (std::size_t k = 0; k < class_radii.size(); ++k) {
    double mean_gradient = 0, mean_squared_gradient = 0;
    for (std::size_t j = 0; j < class_radii.size(); ++j) {
      const double gradient = ((j == k ? volumes[k] * expected_volume : 0.0) -
                               probabilities[k] * volumes[k] * volumes[j]) /
                              (expected_volume * expected_volume);
      mean_gradient += probabilities[j] * gradient;
      mean_squared_gradient += probabilities[j] * gradient * gradient;
    }
    const double standard_error =
        std::sqrt((mean_squared_gradient - mean_gradient * mean_gradient) / n);
    EXPECT_NEAR(class_counts[k] * volumes[k] / sampled_volume, mass_fractions[k],
                3 * standard_error)
        << "class " << k;
  }
}

TEST(DrawRadius, UniformRadiusUsesTheTop53BitsOfOneRawDraw) {
  std::mt19937_64 rng(2024), reference(2024);
  for (int i = 0; i < 10; ++i) {
    const double expected = 1.0 + 2.0 * (static_cast<double>(reference() >> 11) * 0x1.0p-53);
    EXPECT_EQ(draw_radius(uniform_sizes(1.0, 3.0), rng), expected);
  }
}

TEST(DrawRadius, InvalidDistributionsAreRejected) {
  std::mt19937_64 rng(1);
  EXPECT_THROW(draw_radius(monodisperse(0.0), rng), std::invalid_argument);
  EXPECT_THROW(draw_radius(uniform_sizes(0.2, 0.1), rng), std::invalid_argument);
  EXPECT_THROW(draw_radius(discrete_sizes({0.1, 0.2}, {1.0}), rng), std::invalid_argument);
  EXPECT_THROW(draw_radius(discrete_sizes({}, {}), rng), std::invalid_argument);
}

TEST(RegionVolume, BoxAndCylinder) {
  EXPECT_DOUBLE_EQ(region_volume(box_region({-1, 0, 2}, {1, 0.5, 5})), 2 * 0.5 * 3);
  EXPECT_DOUBLE_EQ(region_volume(cylinder_region({3, 3, 3}, 0.5, 2)), kPi * 0.25 * 2);
}

// --------------------------------------------------------------------------------------------
// Determinism

TEST(GenerateParticles, SameSeedGivesIdenticalBits) {
  ParticleSourceConfig source =
      source_in(cylinder_region({0, 0, 0}, 0.5, 1.0), gaussian_sizes(0.02, 0.005, 0.01, 0.03));
  source.random_orientation = true;
  Obstacles obstacles;
  obstacles.centres.push_back({0, 0, 0.5});
  obstacles.radii.push_back(0.2);

  std::mt19937_64 first_rng(99), second_rng(99);
  const auto first = generate_particles(source, 2000, obstacles, first_rng);
  const auto second = generate_particles(source, 2000, obstacles, second_rng);
  ASSERT_EQ(first.size(), 2000u);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i)
    ASSERT_TRUE(same_bits(first[i], second[i])) << "particle " << i;
  EXPECT_EQ(first_rng, second_rng);

  const auto other_seed = generate(source, 2000, 100, obstacles);
  EXPECT_FALSE(same_bits(first.front(), other_seed.front()));
}

} // namespace
} // namespace kdem
