// Particle generation by random sequential addition (RSA): each new sphere is tried at uniformly
// random positions where it lies entirely inside the region, and kept at the first one that
// overlaps nothing placed before it. Overlap checks go through uniform grids of cell size about
// twice the largest radius, so a trial costs O(1) whatever the number of spheres already placed.
//
// Determinism: the output depends only on the rng state and the inputs, bit for bit, on every
// conforming platform. Random numbers come from raw std::mt19937_64 output (whose sequence the
// standard fixes) through our own conversions; the standard distributions are avoided because
// their algorithms are implementation-defined. Positions and orientations use only +, -, *, /
// and sqrt, which IEEE 754 rounds exactly; the Gaussian size distribution also calls std::log.
// Fused multiply-adds would round differently, so contraction is switched off in this file.
#include "generate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// Compiled with -ffp-contract=off (CMakeLists.txt): fused multiply-adds would change the bits of
// the generated positions between machines and compilers.

namespace kdem {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A truncated Gaussian whose acceptance is below one in this many draws is taken as a
// configuration error rather than sampled for ever.
constexpr long kMaxTruncatedGaussianTrials = 10'000'000;

// ---------------------------------------------------------------------------------------------
// Random numbers from raw generator output

// Uniform in [0, 1): the top 53 bits of one draw, scaled exactly.
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double uniform_between(double low, double high, std::mt19937_64& rng) {
  return low + (high - low) * uniform01(rng);
}

// A point uniform in the unit disk, by rejection from the square [-1, 1)^2. The centre itself is
// rejected too, so the point can always be normalised.
struct DiskPoint {
  double x, y;
  double squared_norm; // in (0, 1)
};

DiskPoint draw_in_unit_disk(std::mt19937_64& rng) {
  for (;;) {
    const double x = 2.0 * uniform01(rng) - 1.0;
    const double y = 2.0 * uniform01(rng) - 1.0;
    const double squared_norm = x * x + y * y;
    if (squared_norm < 1.0 && squared_norm > 0.0)
      return {x, y, squared_norm};
  }
}

// (cos t, sin t) for an angle t uniform in [0, 2 pi): a normalised uniform disk point has exactly
// that distribution, and needs no sin/cos.
struct CosSin {
  double cos, sin;
};

CosSin draw_uniform_angle(std::mt19937_64& rng) {
  const DiskPoint point = draw_in_unit_disk(rng);
  const double norm = std::sqrt(point.squared_norm);
  return {point.x / norm, point.y / norm};
}

// Standard normal by the polar form of the Box-Muller transform (Marsaglia). It yields two
// independent normals; the second is dropped so that no state is kept outside `rng`.
double draw_standard_normal(std::mt19937_64& rng) {
  const DiskPoint point = draw_in_unit_disk(rng);
  return point.x * std::sqrt(-2.0 * std::log(point.squared_norm) / point.squared_norm);
}

// Uniform random rotation, after Shoemake (Graphics Gems III, 1992):
//   q = (sqrt(1-u) sin t1, sqrt(1-u) cos t1, sqrt(u) sin t2, sqrt(u) cos t2)
// with u uniform in [0, 1) and t1, t2 uniform angles (taken without sin/cos, see above).
std::array<double, 4> draw_uniform_quaternion(std::mt19937_64& rng) {
  const double u = uniform01(rng);
  const CosSin angle1 = draw_uniform_angle(rng);
  const CosSin angle2 = draw_uniform_angle(rng);
  const double scale1 = std::sqrt(1.0 - u);
  const double scale2 = std::sqrt(u);
  return {scale1 * angle1.sin, scale1 * angle1.cos, scale2 * angle2.sin, scale2 * angle2.cos};
}

// ---------------------------------------------------------------------------------------------
// Size distributions

double sphere_volume(double radius) {
  return 4.0 / 3.0 * kPi * radius * radius * radius;
}

[[noreturn]] void throw_bad_sizes(const std::string& what) {
  throw std::invalid_argument("particle size distribution: " + what);
}

void check_radius_bounds(const SizeDistributionConfig& sizes) {
  if (!(sizes.min_radius > 0) || !(sizes.max_radius >= sizes.min_radius))
    throw_bad_sizes("needs 0 < min_radius <= max_radius");
}

void check_discrete(const SizeDistributionConfig& sizes) {
  if (sizes.radii.empty() || sizes.radii.size() != sizes.mass_fractions.size())
    throw_bad_sizes("discrete needs as many mass fractions as radii, at least one");
  double fraction_sum = 0;
  for (std::size_t k = 0; k < sizes.radii.size(); ++k) {
    if (!(sizes.radii[k] > 0))
      throw_bad_sizes("discrete radii must be positive");
    if (!(sizes.mass_fractions[k] >= 0))
      throw_bad_sizes("mass fractions must be >= 0");
    fraction_sum += sizes.mass_fractions[k];
  }
  if (!(fraction_sum > 0))
    throw_bad_sizes("mass fractions sum to zero");
}

void check_sizes(const SizeDistributionConfig& sizes) {
  using Kind = SizeDistributionConfig::Kind;
  switch (sizes.kind) {
  case Kind::Monodisperse:
    if (!(sizes.radius > 0))
      throw_bad_sizes("radius must be positive");
    return;
  case Kind::Uniform:
    check_radius_bounds(sizes);
    return;
  case Kind::Gaussian:
    check_radius_bounds(sizes);
    if (!(sizes.std_radius >= 0))
      throw_bad_sizes("std_radius must be >= 0");
    if (sizes.std_radius == 0 &&
        !(sizes.mean_radius >= sizes.min_radius && sizes.mean_radius <= sizes.max_radius))
      throw_bad_sizes("with std_radius 0, mean_radius must lie in [min_radius, max_radius]");
    return;
  case Kind::Discrete:
    check_discrete(sizes);
    return;
  }
  throw_bad_sizes("unknown kind");
}

} // namespace

// The smallest and largest radius draw_radius can return.
RadiusRange possible_radii(const SizeDistributionConfig& sizes) {
  using Kind = SizeDistributionConfig::Kind;
  switch (sizes.kind) {
  case Kind::Monodisperse:
    return {sizes.radius, sizes.radius};
  case Kind::Uniform:
  case Kind::Gaussian:
    return {sizes.min_radius, sizes.max_radius};
  case Kind::Discrete: {
    const auto [lo, hi] = std::minmax_element(sizes.radii.begin(), sizes.radii.end());
    return {*lo, *hi};
  }
  }
  return {0, 0};
}

namespace {

double draw_truncated_gaussian(const SizeDistributionConfig& sizes, std::mt19937_64& rng) {
  if (sizes.std_radius == 0)
    return sizes.mean_radius;
  for (long trial = 0; trial < kMaxTruncatedGaussianTrials; ++trial) {
    const double radius = sizes.mean_radius + sizes.std_radius * draw_standard_normal(rng);
    if (radius >= sizes.min_radius && radius <= sizes.max_radius)
      return radius;
  }
  throw_bad_sizes("Gaussian has almost no mass in [min_radius, max_radius]");
}

// Class k is drawn with probability proportional to its number share, mass_fraction_k / r_k^3.
double draw_discrete_by_mass(const SizeDistributionConfig& sizes, std::mt19937_64& rng) {
  const std::size_t class_count = sizes.radii.size();
  std::vector<double> cumulative_weight(class_count);
  double total_weight = 0;
  for (std::size_t k = 0; k < class_count; ++k) {
    const double radius = sizes.radii[k];
    total_weight += sizes.mass_fractions[k] / (radius * radius * radius);
    cumulative_weight[k] = total_weight;
  }
  const double pick = uniform01(rng) * total_weight;
  for (std::size_t k = 0; k < class_count; ++k)
    if (pick < cumulative_weight[k])
      return sizes.radii[k];
  // Only reached through rounding at the very top: the last class with any weight.
  std::size_t last = class_count - 1;
  while (last > 0 && sizes.mass_fractions[last] == 0)
    --last;
  return sizes.radii[last];
}

// ---------------------------------------------------------------------------------------------
// Regions

struct Bounds {
  Vec3d low, high;
};

Bounds region_bounds(const RegionConfig& region) {
  if (region.kind == RegionConfig::Kind::Box)
    return {region.min, region.max};
  const Vec3d& base = region.base_center;
  return {{base[0] - region.radius, base[1] - region.radius, base[2]},
          {base[0] + region.radius, base[1] + region.radius, base[2] + region.height}};
}

// Whether a sphere of `radius` fits entirely inside the region somewhere.
bool region_holds_sphere(const RegionConfig& region, double radius) {
  if (region.kind == RegionConfig::Kind::Cylinder)
    return region.radius >= radius && region.height >= 2 * radius;
  for (std::size_t axis = 0; axis < 3; ++axis)
    if (region.max[axis] - region.min[axis] < 2 * radius)
      return false;
  return true;
}

// A centre uniform over the positions where a sphere of `radius` lies entirely inside the
// region; the region must hold such a sphere.
Vec3d draw_centre_in_box(const RegionConfig& box, double radius, std::mt19937_64& rng) {
  Vec3d centre;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const double low = box.min[axis] + radius;
    const double high = box.max[axis] - radius;
    centre[axis] = std::min(uniform_between(low, high, rng), high);
  }
  return centre;
}

Vec3d draw_centre_in_cylinder(const RegionConfig& cylinder, double radius, std::mt19937_64& rng) {
  const double radial_room = cylinder.radius - radius;
  const DiskPoint offset = draw_in_unit_disk(rng);
  const Vec3d& base = cylinder.base_center;
  const double low = base[2] + radius;
  const double high = base[2] + cylinder.height - radius;
  return {base[0] + radial_room * offset.x, base[1] + radial_room * offset.y,
          std::min(uniform_between(low, high, rng), high)};
}

Vec3d draw_centre_in_region(const RegionConfig& region, double radius, std::mt19937_64& rng) {
  if (region.kind == RegionConfig::Kind::Cylinder)
    return draw_centre_in_cylinder(region, radius, rng);
  return draw_centre_in_box(region, radius, rng);
}

// ---------------------------------------------------------------------------------------------
// Uniform grid of spheres

struct alignas(32) Sphere { // 32 bytes, aligned: never straddles a cache line
  Vec3d centre;
  double radius;
};

bool spheres_overlap(const Sphere& sphere, const Vec3d& centre, double radius) {
  const double dx = sphere.centre[0] - centre[0];
  const double dy = sphere.centre[1] - centre[1];
  const double dz = sphere.centre[2] - centre[2];
  const double contact_distance = sphere.radius + radius;
  return dx * dx + dy * dy + dz * dz < contact_distance * contact_distance;
}

Bounds grown(const Bounds& bounds, double margin) {
  return {{bounds.low[0] - margin, bounds.low[1] - margin, bounds.low[2] - margin},
          {bounds.high[0] + margin, bounds.high[1] + margin, bounds.high[2] + margin}};
}

// Cells per axis of a grid of `cell_size` over `covered`.
std::array<std::int64_t, 3> cell_counts(const Bounds& covered, double cell_size) {
  std::array<std::int64_t, 3> counts;
  for (std::size_t axis = 0; axis < 3; ++axis)
    counts[axis] = static_cast<std::int64_t>(
                       std::floor((covered.high[axis] - covered.low[axis]) / cell_size)) +
                   1;
  return counts;
}

double total_cells(const Bounds& covered, double cell_size) {
  const std::array<std::int64_t, 3> counts = cell_counts(covered, cell_size);
  return static_cast<double>(counts[0]) * static_cast<double>(counts[1]) *
         static_cast<double>(counts[2]);
}

// The preferred cell size (twice the largest radius: a query then spans 3 cells per axis), made
// coarser where that would give more than a couple of cells per expected sphere, so that sparse
// fills of large regions stay small in memory. The cell size never changes the result, only
// the speed.
double choose_cell_size(const Bounds& covered, double preferred, double expected_spheres) {
  constexpr double kFewestCells = 4096, kMostCells = 1 << 25;
  const double cell_budget = std::clamp(2 * expected_spheres, kFewestCells, kMostCells);
  double cell_size = preferred;
  while (total_cells(covered, cell_size) > cell_budget)
    cell_size *= 1.25;
  return cell_size;
}

// Spheres binned by the cell that holds their centre, on a dense uniform grid over a box (a
// hash grid whose hash is the flat cell index); each cell heads a chain of its spheres. A query
// visits every cell within reach of the largest sphere stored.
class SphereGrid {
public:
  // Fastest for spheres whose centres lie in `covered`.
  SphereGrid(const Bounds& covered, double cell_size)
      : origin_(covered.low), inverse_cell_size_(1.0 / cell_size),
        cell_counts_(cell_counts(covered, cell_size)),
        first_in_cell_(static_cast<std::size_t>(total_cells(covered, cell_size)), kNone) {}

  void insert(const Sphere& sphere) {
    if (spheres_.size() >= kNone)
      throw std::length_error("particle generation: too many spheres");
    const std::size_t cell = flat_index(cell_of(sphere.centre));
    next_in_cell_.push_back(first_in_cell_[cell]);
    first_in_cell_[cell] = static_cast<std::uint32_t>(spheres_.size());
    spheres_.push_back(sphere);
    largest_radius_ = std::max(largest_radius_, sphere.radius);
  }

  // The candidate's own cell goes first: an overlap is likeliest there, which makes rejected
  // trials cheap.
  bool overlaps_any(const Vec3d& centre, double radius) const {
    if (spheres_.empty())
      return false;
    const CellIndex home = cell_of(centre);
    if (cell_overlaps_any(flat_index(home), centre, radius))
      return true;
    const double reach = radius + largest_radius_;
    const CellIndex first = cell_of({centre[0] - reach, centre[1] - reach, centre[2] - reach});
    const CellIndex last = cell_of({centre[0] + reach, centre[1] + reach, centre[2] + reach});
    for (std::int64_t k = first[2]; k <= last[2]; ++k)
      for (std::int64_t j = first[1]; j <= last[1]; ++j)
        for (std::int64_t i = first[0]; i <= last[0]; ++i) {
          const CellIndex cell{i, j, k};
          if (cell != home && cell_overlaps_any(flat_index(cell), centre, radius))
            return true;
        }
    return false;
  }

private:
  using CellIndex = std::array<std::int64_t, 3>;
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  // The cell holding `point`, clamped to the grid. Clamping is monotonic, so a clamped query
  // range still holds the (clamped) cell of every sphere within reach, even of one whose centre
  // lies outside the covered box: that box only affects speed, never the result. A NaN
  // coordinate (a particle gone wrong before the run checks see it) goes to cell 0, where it
  // overlaps nothing, rather than into an undefined conversion.
  CellIndex cell_of(const Vec3d& point) const {
    CellIndex cell;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const double scaled = std::floor((point[axis] - origin_[axis]) * inverse_cell_size_);
      const double last = static_cast<double>(cell_counts_[axis] - 1);
      cell[axis] = scaled >= 0 ? static_cast<std::int64_t>(std::min(scaled, last)) : 0;
    }
    return cell;
  }

  std::size_t flat_index(const CellIndex& cell) const {
    return static_cast<std::size_t>((cell[2] * cell_counts_[1] + cell[1]) * cell_counts_[0] +
                                    cell[0]);
  }

  bool cell_overlaps_any(std::size_t cell, const Vec3d& centre, double radius) const {
    for (std::uint32_t index = first_in_cell_[cell]; index != kNone; index = next_in_cell_[index])
      if (spheres_overlap(spheres_[index], centre, radius))
        return true;
    return false;
  }

  Vec3d origin_;
  double inverse_cell_size_;
  CellIndex cell_counts_;
  std::vector<std::uint32_t> first_in_cell_; // per cell: its latest sphere, or kNone
  std::vector<std::uint32_t> next_in_cell_;  // per sphere: the previous one in its cell, or kNone
  std::vector<Sphere> spheres_;
  double largest_radius_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Random sequential addition

// Whether an obstacle can touch a new sphere (radius at most `largest_new_radius`) inside the
// region: its centre lies within the region's bounding box grown by both radii.
bool obstacle_can_reach_region(const Bounds& region, const Sphere& obstacle,
                               double largest_new_radius) {
  const double reach = obstacle.radius + largest_new_radius;
  for (std::size_t axis = 0; axis < 3; ++axis)
    if (obstacle.centre[axis] < region.low[axis] - reach ||
        obstacle.centre[axis] > region.high[axis] + reach)
      return false;
  return true;
}

std::vector<Sphere> obstacles_reaching_region(const Obstacles& obstacles, const Bounds& region,
                                              double largest_new_radius) {
  if (obstacles.centres.size() != obstacles.radii.size())
    throw std::invalid_argument("obstacles: as many radii as centres needed");
  std::vector<Sphere> reaching;
  for (std::size_t index = 0; index < obstacles.centres.size(); ++index) {
    const Sphere obstacle{obstacles.centres[index], obstacles.radii[index]};
    if (obstacle_can_reach_region(region, obstacle, largest_new_radius))
      reaching.push_back(obstacle);
  }
  return reaching;
}

// A grid for the new particles and the obstacles no larger than the largest of them: its cells
// are sized to that radius, and it covers every centre that can touch the region.
SphereGrid make_particle_grid(const Bounds& region, double largest_new_radius,
                              double expected_new_count, const std::vector<Sphere>& obstacles) {
  std::vector<Sphere> small_obstacles;
  for (const Sphere& obstacle : obstacles)
    if (obstacle.radius <= largest_new_radius)
      small_obstacles.push_back(obstacle);
  const Bounds covered = grown(region, 2 * largest_new_radius);
  const double expected_count = expected_new_count + static_cast<double>(small_obstacles.size());
  SphereGrid grid(covered, choose_cell_size(covered, 2 * largest_new_radius, expected_count));
  for (const Sphere& obstacle : small_obstacles)
    grid.insert(obstacle);
  return grid;
}

// A grid for the obstacles larger than every new particle, sized to the largest of them, so that
// a few big spheres do not coarsen the cells of the many small ones.
SphereGrid make_large_obstacle_grid(const Bounds& region, double largest_new_radius,
                                    const std::vector<Sphere>& obstacles) {
  std::vector<Sphere> large_obstacles;
  double largest_obstacle_radius = largest_new_radius;
  for (const Sphere& obstacle : obstacles)
    if (obstacle.radius > largest_new_radius) {
      large_obstacles.push_back(obstacle);
      largest_obstacle_radius = std::max(largest_obstacle_radius, obstacle.radius);
    }
  const Bounds covered = grown(region, largest_obstacle_radius + largest_new_radius);
  const double expected_count = static_cast<double>(large_obstacles.size());
  SphereGrid grid(covered, choose_cell_size(covered, 2 * largest_obstacle_radius, expected_count));
  for (const Sphere& obstacle : large_obstacles)
    grid.insert(obstacle);
  return grid;
}

// Places spheres one at a time, each at the first free random position, checked against the
// spheres placed before it and the obstacles near the region.
class SequentialPlacer {
public:
  SequentialPlacer(const ParticleSourceConfig& source, double largest_new_radius,
                   double expected_new_count, const std::vector<Sphere>& obstacles,
                   const Obstacles& all_obstacles, std::mt19937_64& rng, int max_failed_attempts)
      : source_(source), crosses_wall_(all_obstacles.crosses_wall), rng_(rng),
        max_failed_attempts_(max_failed_attempts),
        particle_grid_(make_particle_grid(region_bounds(source.region), largest_new_radius,
                                          expected_new_count, obstacles)),
        large_obstacle_grid_(make_large_obstacle_grid(region_bounds(source.region),
                                                      largest_new_radius, obstacles)) {}

  // Places one particle of `radius`; false when it gave up (the particle is not placed).
  bool place(double radius) {
    const std::optional<Vec3d> centre = find_free_centre(radius);
    if (!centre)
      return false;
    particle_grid_.insert({*centre, radius});
    placed_.push_back(make_seed(*centre, radius));
    return true;
  }

  std::vector<ParticleSeed> take_placed() { return std::move(placed_); }

private:
  std::optional<Vec3d> find_free_centre(double radius) {
    if (!region_holds_sphere(source_.region, radius))
      return std::nullopt;
    for (int attempt = 0; attempt < max_failed_attempts_; ++attempt) {
      const Vec3d centre = draw_centre_in_region(source_.region, radius, rng_);
      if (!particle_grid_.overlaps_any(centre, radius) &&
          !large_obstacle_grid_.overlaps_any(centre, radius) &&
          !(crosses_wall_ && crosses_wall_(centre, radius)))
        return centre;
    }
    return std::nullopt;
  }

  ParticleSeed make_seed(const Vec3d& centre, double radius) {
    ParticleSeed seed;
    seed.position = centre;
    seed.velocity = source_.velocity;
    seed.angular_velocity = source_.angular_velocity;
    seed.orientation = source_.orientation;
    if (source_.random_orientation)
      seed.orientation = draw_uniform_quaternion(rng_);
    seed.radius = radius;
    return seed;
  }

  const ParticleSourceConfig& source_;
  const std::function<bool(const Vec3d&, double)>& crosses_wall_;
  std::mt19937_64& rng_;
  int max_failed_attempts_;
  SphereGrid particle_grid_;
  SphereGrid large_obstacle_grid_;
  std::vector<ParticleSeed> placed_;
};

// A bound on how many particles of `source` a call can place: `max_new`, or fewer when not
// even that many of the smallest size would fill the region. Sizes the overlap grid only.
double most_that_could_fit(const ParticleSourceConfig& source, std::int64_t max_new) {
  const double volume_bound =
      region_volume(source.region) / sphere_volume(possible_radii(source.sizes).smallest);
  return std::min(static_cast<double>(max_new), volume_bound);
}

// Radii for a volume_fraction source: drawn until their volume reaches the target (or there
// are `max_new`), then sorted largest first. Placing big spheres first lets the small ones fill
// the gaps between them, which reaches markedly higher fractions before the region jams than
// placing in drawn order; the set of radii, and so the size distribution, is unchanged. The
// placed volume thus exceeds the target by less than the last particle drawn. (Radii uniform in
// [r, 3r], for example, jam near a solid fraction of 0.23 in drawn order but reach 0.40 sorted.)
std::vector<double> draw_radii_for_volume(const ParticleSourceConfig& source, std::int64_t max_new,
                                          std::mt19937_64& rng) {
  const double target_volume = source.volume_fraction * region_volume(source.region);
  std::vector<double> radii;
  double drawn_volume = 0;
  while (drawn_volume < target_volume && static_cast<std::int64_t>(radii.size()) < max_new) {
    radii.push_back(draw_radius(source.sizes, rng));
    drawn_volume += source.particle_volume_ratio * sphere_volume(radii.back());
  }
  std::sort(radii.begin(), radii.end(), [](double a, double b) { return a > b; });
  return radii;
}

} // namespace

// ---------------------------------------------------------------------------------------------

double draw_radius(const SizeDistributionConfig& sizes, std::mt19937_64& rng) {
  check_sizes(sizes);
  using Kind = SizeDistributionConfig::Kind;
  switch (sizes.kind) {
  case Kind::Monodisperse:
    return sizes.radius;
  case Kind::Uniform:
    return std::min(uniform_between(sizes.min_radius, sizes.max_radius, rng), sizes.max_radius);
  case Kind::Gaussian:
    return draw_truncated_gaussian(sizes, rng);
  case Kind::Discrete:
    return draw_discrete_by_mass(sizes, rng);
  }
  throw_bad_sizes("unknown kind");
}

double region_volume(const RegionConfig& region) {
  if (region.kind == RegionConfig::Kind::Cylinder)
    return kPi * region.radius * region.radius * std::max(region.height, 0.0);
  double volume = 1;
  for (std::size_t axis = 0; axis < 3; ++axis)
    volume *= std::max(region.max[axis] - region.min[axis], 0.0);
  return volume;
}

// Count sources (no volume_fraction) draw each radius just before placing it, so particles come
// out in drawn order and the radii need no storage. Volume-fraction sources place largest first
// (see draw_radii_for_volume).
std::vector<ParticleSeed> generate_particles(const ParticleSourceConfig& source,
                                             std::int64_t max_new, const Obstacles& obstacles,
                                             std::mt19937_64& rng, int max_failed_attempts) {
  check_sizes(source.sizes);
  if (max_new <= 0)
    return {};
  const double largest_new_radius = possible_radii(source.sizes).largest;
  const std::vector<Sphere> obstacles_near =
      obstacles_reaching_region(obstacles, region_bounds(source.region), largest_new_radius);
  if (source.volume_fraction > 0) {
    const std::vector<double> radii = draw_radii_for_volume(source, max_new, rng);
    SequentialPlacer placer(source, largest_new_radius, static_cast<double>(radii.size()),
                            obstacles_near, obstacles, rng, max_failed_attempts);
    for (double radius : radii)
      if (!placer.place(radius))
        break;
    return placer.take_placed();
  }
  SequentialPlacer placer(source, largest_new_radius, most_that_could_fit(source, max_new),
                          obstacles_near, obstacles, rng, max_failed_attempts);
  for (std::int64_t index = 0; index < max_new; ++index)
    if (!placer.place(draw_radius(source.sizes, rng)))
      break;
  return placer.take_placed();
}

} // namespace kdem
