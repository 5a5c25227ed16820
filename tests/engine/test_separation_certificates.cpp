// Separation certificates of superquadric pairs: the gap bound of the narrow phase against
// spheres (closed form) and sampled surfaces, the promise that a pair moved within its margin
// cannot touch, the turned-angle bound of the integrator, and whole runs with and without them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "kernels/integrate.hpp"
#include "shapes/superquadric_contact.hpp"
#include "src/scene_loader.hpp"

#include "checkpoint_test_support.hpp"
#include "geometry_test_support.hpp"
#include "scene_builders.hpp"

namespace kdem {
namespace {

constexpr double pi = 3.14159265358979323846;

struct SeparatedCase {
  PosedSuperquadric i, j;
};

struct ColdContact {
  KOKKOS_INLINE_FUNCTION NarrowPhaseResult operator()(const SeparatedCase& c) const {
    NarrowPhaseControls controls;
    controls.tolerance = 1e-13;
    controls.max_iterations = 200;
    return superquadric_pair_contact(c.i, c.j, MidwayState{}, controls);
  }
};

// Signed power sgn(t) |t|^e of the parametric superquadric surface.
double signed_power(double t, double e) {
  return (t < 0 ? -1.0 : 1.0) * std::pow(std::fabs(t), e);
}

// Surface points on a parameter grid: x = a C(eta)^(2/n1) C(omega)^(2/n2), y = b C(eta)^(2/n1)
// S(omega)^(2/n2), z = c S(eta)^(2/n1), which gives F = 0 for the F of superquadric.hpp.
std::vector<Vec3> sampled_surface(const PosedSuperquadric& body, int steps) {
  const SuperquadricShape& s = body.shape;
  std::vector<Vec3> points;
  for (int a = 0; a <= steps; ++a) {
    const double eta = -0.5 * pi + pi * a / steps;
    for (int b = 0; b < 2 * steps; ++b) {
      const double omega = -pi + pi * b / steps;
      const double ring = signed_power(std::cos(eta), 2.0 / s.n1);
      const Vec3 local{s.a * ring * signed_power(std::cos(omega), 2.0 / s.n2),
                       s.b * ring * signed_power(std::sin(omega), 2.0 / s.n2),
                       s.c * signed_power(std::sin(eta), 2.0 / s.n1)};
      points.push_back(body.to_world(local));
    }
  }
  return points;
}

// The smallest distance between sample points of the two surfaces: never below the true gap.
double sampled_gap(const PosedSuperquadric& i, const PosedSuperquadric& j, int steps) {
  const std::vector<Vec3> pi_ = sampled_surface(i, steps), pj = sampled_surface(j, steps);
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& a : pi_)
    for (const Vec3& b : pj)
      best = std::min(best, norm2(a - b));
  return std::sqrt(best);
}

double bounding_radius_bound(const SuperquadricShape& s) {
  return std::sqrt(s.a * s.a + s.b * s.b + s.c * s.c);
}

// Random separated-or-touching pairs: i at the origin, j at a random direction and a distance
// between 0.5 and 1.1 times the sum of the bounding radii, both turned at random.
std::vector<SeparatedCase> random_pairs(std::uint64_t seed, int count, double n_max) {
  std::mt19937_64 rng(seed);
  std::vector<SeparatedCase> cases;
  for (int k = 0; k < count; ++k) {
    const SuperquadricShape si = random_shape(rng, n_max), sj = random_shape(rng, n_max);
    const double reach = bounding_radius_bound(si) + bounding_radius_bound(sj);
    const Vec3 centre_j = (uniform(rng, 0.5, 1.1) * reach) * random_unit(rng);
    cases.push_back({pose_superquadric(si, {0, 0, 0}, random_rotation(rng)),
                     pose_superquadric(sj, centre_j, random_rotation(rng))});
  }
  return cases;
}

// Two spheres of radii 1 and 0.5 at gap g: the bound is (d^2 - r^2) / (2 d) per side at the
// midway point (d its distance from the centre), so it lies below g by a factor 1 - O(g / r).
TEST(SeparationCertificates, SphereGapBoundIsBelowTheGapAndTight) {
  std::vector<SeparatedCase> cases;
  const std::vector<double> gaps{1e-8, 1e-6, 1e-4, 1e-2, 0.1};
  for (double g : gaps)
    cases.push_back(
        {pose_superquadric(make_superquadric(1, 1, 1, 2, 2), {0, 0, 0}, Quat{}),
         pose_superquadric(make_superquadric(0.5, 0.5, 0.5, 2, 2), {1.5 + g, 0, 0}, Quat{})});
  const std::vector<NarrowPhaseResult> results =
      run_on_device<NarrowPhaseResult>(cases, ColdContact{});
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    SCOPED_TRACE("gap " + std::to_string(gaps[k]));
    ASSERT_EQ(results[k].status, 0);
    EXPECT_FALSE(results[k].geometry.touching);
    EXPECT_LE(results[k].separation, gaps[k]);
    // 1e-9 L is subtracted for rounding: the smallest gap keeps 0.8 of itself.
    EXPECT_GE(results[k].separation, (gaps[k] < 1e-7 ? 0.8 : 0.9) * gaps[k]);
  }
}

// For random pairs that do not touch, the bound never exceeds the sampled gap (which is at or
// above the true gap), and it is not vacuous: it is positive for every separated pair whose
// sampled gap exceeds 1 % of the size, and at least 1/4 of that gap for most.
TEST(SeparationCertificates, GapBoundNeverExceedsTheSampledGap) {
  const std::vector<SeparatedCase> cases = random_pairs(41, 300, 10.0);
  const std::vector<NarrowPhaseResult> results =
      run_on_device<NarrowPhaseResult>(cases, ColdContact{});
  int separated = 0, tight = 0, checked = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const NarrowPhaseResult& r = results[k];
    if (r.status != 0 || r.geometry.touching)
      continue;
    ++separated;
    const double gap = sampled_gap(cases[k].i, cases[k].j, 30);
    EXPECT_LE(r.separation, gap) << "pair " << k;
    const double size = std::min(narrow_phase::smallest_semi_axis(cases[k].i.shape),
                                 narrow_phase::smallest_semi_axis(cases[k].j.shape));
    if (gap > 0.01 * size) {
      ++checked;
      EXPECT_GT(r.separation, 0) << "pair " << k;
      tight += r.separation >= 0.25 * gap;
    }
  }
  EXPECT_GT(separated, 100);
  EXPECT_GT(tight, 0.8 * checked) << tight << " of " << checked;
}

// A certificate's promise: move j towards i along the normal and turn both bodies about their
// centres, using up to 99 % of the margin (|shift| + theta_i r_i + theta_j r_j), and the cold
// narrow phase still finds them apart.
TEST(SeparationCertificates, PairsMovedWithinTheirMarginDoNotTouch) {
  const std::vector<SeparatedCase> cases = random_pairs(43, 400, 10.0);
  const std::vector<NarrowPhaseResult> first =
      run_on_device<NarrowPhaseResult>(cases, ColdContact{});
  std::mt19937_64 rng(44);
  std::vector<SeparatedCase> moved;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const NarrowPhaseResult& r = first[k];
    if (r.status != 0 || r.geometry.touching || !(r.separation > 0))
      continue;
    const double budget = 0.99 * r.separation;
    const double share_shift = uniform(rng, 0, 1), share_i = uniform(rng, 0, 1 - share_shift);
    const double share_j = 1 - share_shift - share_i;
    const double ri = bounding_radius_bound(cases[k].i.shape);
    const double rj = bounding_radius_bound(cases[k].j.shape);
    const Vec3 towards_i = r.state.point - cases[k].j.centre; // roughly; any direction is allowed
    SeparatedCase c = cases[k];
    c.j.centre = c.j.centre + (share_shift * budget / norm(towards_i)) * towards_i;
    const Mat3 turn_i = rotation_matrix(axis_angle(random_unit(rng), share_i * budget / ri));
    const Mat3 turn_j = rotation_matrix(axis_angle(random_unit(rng), share_j * budget / rj));
    c.i.rotation = turn_i * c.i.rotation;
    c.j.rotation = turn_j * c.j.rotation;
    moved.push_back(c);
  }
  ASSERT_GT(moved.size(), 100u);
  const std::vector<NarrowPhaseResult> after =
      run_on_device<NarrowPhaseResult>(moved, ColdContact{});
  for (std::size_t k = 0; k < moved.size(); ++k) {
    EXPECT_EQ(after[k].status, 0) << "pair " << k;
    EXPECT_FALSE(after[k].geometry.touching) << "pair " << k;
  }
}

// The same for a sphere against a superquadric (the closest-point path).
TEST(SeparationCertificates, SphereSuperquadricBoundIsBelowTheSampledGap) {
  std::mt19937_64 rng(45);
  int separated = 0;
  for (int k = 0; k < 200; ++k) {
    const SuperquadricShape s = random_shape(rng, 10.0);
    const double radius = log_uniform(rng, 0.1, 2.0);
    const PosedSuperquadric body = pose_superquadric(s, {0, 0, 0}, random_rotation(rng));
    const Vec3 centre =
        (uniform(rng, 0.6, 1.2) * (bounding_radius_bound(s) + radius)) * random_unit(rng);
    const NarrowPhaseResult r =
        sphere_superquadric_contact(centre, radius, body, MidwayState{}, NarrowPhaseControls{});
    if (r.status != 0 || r.geometry.touching)
      continue;
    ++separated;
    const PosedSuperquadric sphere =
        pose_superquadric(make_superquadric(radius, radius, radius, 2, 2), centre, Quat{});
    EXPECT_LE(r.separation, sampled_gap(sphere, body, 30)) << "pair " << k;
    EXPECT_GT(r.separation, 0) << "pair " << k;
  }
  EXPECT_GT(separated, 50);
}

// 2 tan(theta / 2) >= theta: an upper bound, within theta^3 / 12 of the angle; pi at most.
TEST(SeparationCertificates, RotationAngleBoundIsAnUpperBound) {
  std::mt19937_64 rng(46);
  for (int k = 0; k < 2000; ++k) {
    const double angle = k < 1000 ? log_uniform(rng, 1e-9, 0.1) : uniform(rng, 0.1, pi);
    const Quat a = random_rotation(rng);
    const Quat b = normalized(axis_angle(random_unit(rng), angle) * a);
    const double bound = rotation_angle_bound(a, b);
    // Rounding of the quaternion components (4e-16) is the bound's absolute floor.
    EXPECT_GE(bound, angle * (1 - 1e-9) - 4e-16) << angle;
    EXPECT_LE(bound, pi);
    if (angle < 0.1)
      EXPECT_LE(bound, angle * (1 + angle * angle / 12 * 1.01) + 1e-15) << angle;
  }
}

// The rigid-body drift adds to turned_angle at least the angle each particle turned.
// Three rigid bodies at rest orientation (identity), unit mass, inertia (1, 2, 3), with the given
// velocities, spins and bounding radii, at distinct positions.
ParticleViews three_bodies(const double (&velocity)[3][3], const double (&spin)[3][3],
                           const double (&radii)[3]) {
  ParticleViews p;
  p.allocate(3);
  auto x = Kokkos::create_mirror_view(p.position);
  auto v = Kokkos::create_mirror_view(p.velocity);
  auto w = Kokkos::create_mirror_view(p.angular_velocity);
  auto q = Kokkos::create_mirror_view(p.orientation);
  auto inertia = Kokkos::create_mirror_view(p.inertia);
  auto mass = Kokkos::create_mirror_view(p.mass);
  auto radius = Kokkos::create_mirror_view(p.radius);
  for (int i = 0; i < 3; ++i) {
    for (int c = 0; c < 3; ++c) {
      x(i, c) = 0.1 * (i + 1) + 0.01 * c;
      v(i, c) = velocity[i][c];
      w(i, c) = spin[i][c];
    }
    q(i, 0) = 1, q(i, 1) = q(i, 2) = q(i, 3) = 0;
    inertia(i, 0) = 1, inertia(i, 1) = 2, inertia(i, 2) = 3;
    mass(i) = 1;
    radius(i) = radii[i];
  }
  Kokkos::deep_copy(p.position, x);
  Kokkos::deep_copy(p.velocity, v);
  Kokkos::deep_copy(p.angular_velocity, w);
  Kokkos::deep_copy(p.orientation, q);
  Kokkos::deep_copy(p.inertia, inertia);
  Kokkos::deep_copy(p.mass, mass);
  Kokkos::deep_copy(p.radius, radius);
  return p;
}

TEST(SeparationCertificates, DriftAccumulatesTheTurnedAngle) {
  const double at_rest[3][3] = {};
  const double spin[3][3] = {{0, 0, 100}, {30, -40, 0}, {1e-3, 2e-3, 0}};
  ParticleViews p = three_bodies(at_rest, spin, {1, 1, 1});
  const double dt = 1e-4;
  for (int step = 0; step < 50; ++step)
    kick_and_drift_rigid(p, dt);
  auto q = Kokkos::create_mirror_view(p.orientation);
  Kokkos::deep_copy(q, p.orientation);
  auto turned = Kokkos::create_mirror_view(p.turned_angle);
  Kokkos::deep_copy(turned, p.turned_angle);
  for (int i = 0; i < 3; ++i) {
    const double net =
        2 * std::atan2(std::sqrt(q(i, 1) * q(i, 1) + q(i, 2) * q(i, 2) + q(i, 3) * q(i, 3)),
                       std::fabs(q(i, 0)));
    EXPECT_GE(turned(i), net * (1 - 1e-12)) << i;
    // Free rotation at constant |omega| turns about |omega| dt per step.
    const double speed =
        std::sqrt(spin[i][0] * spin[i][0] + spin[i][1] * spin[i][1] + spin[i][2] * spin[i][2]);
    EXPECT_LE(turned(i), 1.5 * speed * 50 * dt) << i;
  }
}

// The drift returns how far any surface point moved: |x_after - x_before| + turned angle x
// bounding radius, the largest over the particles. Particle 1 translates slowly but spins a large
// radius, so that the largest comes from turning (a drift that left turning out would return
// particle 0's 1e-4 m); agreement to 1e-12 (the rounding of a few operations).
TEST(SeparationCertificates, DriftReturnsHowFarAnySurfacePointMoved) {
  const double velocity[3][3] = {{1, 0, 0}, {0, 0.5, 0}, {1e-3, 0, -2e-3}};
  const double spin[3][3] = {{0, 0, 0}, {0, 0, 100}, {3, -4, 0}};
  const double radii[3] = {1e-3, 0.02, 5e-3};
  ParticleViews p = three_bodies(velocity, spin, radii);
  auto x = Kokkos::create_mirror_view(p.position);
  Kokkos::deep_copy(x, p.position);
  double before[3][3]; // the mirror may be the View itself
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c)
      before[i][c] = x(i, c);
  const double farthest = kick_and_drift_rigid(p, 1e-4);
  auto after = Kokkos::create_mirror_view(p.position);
  auto turned = Kokkos::create_mirror_view(p.turned_angle);
  Kokkos::deep_copy(after, p.position);
  Kokkos::deep_copy(turned, p.turned_angle);
  double largest = 0;
  int which = -1;
  for (int i = 0; i < 3; ++i) {
    const Vec3 moved{after(i, 0) - before[i][0], after(i, 1) - before[i][1],
                     after(i, 2) - before[i][2]};
    const double travel = norm(moved) + turned(i) * radii[i];
    if (travel > largest)
      largest = travel, which = i;
  }
  EXPECT_EQ(which, 1);
  EXPECT_NEAR(farthest, largest, 1e-12 * largest);
}

// A particle gone wrong (NaN velocity) has no bound on its travel: the drift returns
// unbounded_travel, which expires every certificate, rather than a maximum that skips the NaN.
TEST(SeparationCertificates, DriftOfANaNParticleExpiresEveryCertificate) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double velocity[3][3] = {{1, 0, 0}, {nan, 0, 0}, {0, 0, 1}};
  const double spin[3][3] = {};
  ParticleViews p = three_bodies(velocity, spin, {1e-3, 1e-3, 1e-3});
  EXPECT_EQ(kick_and_drift_rigid(p, 1e-4), unbounded_travel);
}

// Over no particles (a scene that rains them in starts empty) the drift moves nothing: it returns
// 0, not the maximum's identity (-inf), which would hold the surface travel, and every
// certificate measured against it, for good.
TEST(SeparationCertificates, DriftOfNoParticlesReturnsZero) {
  ParticleViews p;
  p.allocate(0);
  EXPECT_EQ(kick_and_drift_rigid(p, 1e-4), 0.0);
}

} // namespace

namespace testing {
namespace {

RunOutcome run_small_superquadrics(bool certificates, int steps, bool extrapolate = true,
                                   bool box_certificates = true, bool rained = false) {
  SceneConfig scene = cli_scene("small_superquadrics");
  if (rained)
    for (ParticleSourceConfig& source : scene.sources) {
      source.rate = double(source.count) / 0.002; // two batches, the first at t = 0
      source.interval = 0.001;
    }
  SuperquadricContactConfig& contact = modify_superquadric_contact(scene);
  contact.separation_certificates = certificates;
  contact.box_certificates = box_certificates;
  contact.extrapolate_start = extrapolate;
  return run_steps(scene, steps);
}

// Certificates only skip pairs that cannot touch, so a run differs only through the later warm
// starts of the skipped pairs (Newton converges to 1e-10 of the size from any start). After 4000
// steps of the pouring scene positions agree to 1e-9 m (1e-6 of a particle size; measured
// 2.7e-10 m with extrapolated starts, 3.4e-12 m without) and closer than the same run does with
// Newton started from the last points instead of extrapolated ones (measured 9.9e-9 m): the
// certificates change the run less than a change of the starts does, which is all they change.
// (Before the starts were extrapolated, the yardstick was a tolerance of 1e-12, which moved the
// run by 1e-8 m; from extrapolated starts one iteration lands far below the tolerance, and the
// tighter tolerance moves it by 1.8e-10 m only.)
TEST(SeparationCertificates, RunsAgreeWithAndWithoutCertificates) {
  const int steps = 4000;
  const RunOutcome with = run_small_superquadrics(true, steps);
  const RunOutcome without = run_small_superquadrics(false, steps);
  const RunOutcome other_starts = run_small_superquadrics(false, steps, false);
  const double natural = largest_position_difference(other_starts, without);
  const double largest = largest_position_difference(with, without);
  EXPECT_LT(largest, 1e-9);
  EXPECT_LT(largest, natural);
  EXPECT_GT(with.contacts, 0);
  EXPECT_EQ(with.contacts, without.contacts);
  EXPECT_EQ(with.totals.failures, 0);
  EXPECT_LT(with.totals.evaluations, without.totals.evaluations);
  std::ostringstream difference;
  difference << largest;
  RecordProperty("largest_position_difference", difference.str());
  RecordProperty("evaluations_with", std::to_string(with.totals.evaluations));
  RecordProperty("evaluations_without", std::to_string(without.totals.evaluations));
}

// The same with every source raining, so that the run starts without particles: the surface
// travel must start from the first batch (it once stayed at -inf, the empty drift's maximum,
// and every superquadric pair was held apart by its certificate for good).
TEST(SeparationCertificates, RainedRunsAgreeWithAndWithoutCertificates) {
  const int steps = 4000;
  const RunOutcome with = run_small_superquadrics(true, steps, true, true, true);
  const RunOutcome without = run_small_superquadrics(false, steps, true, true, true);
  EXPECT_LT(largest_position_difference(with, without), 1e-9);
  EXPECT_GT(with.contacts, 0);
  EXPECT_EQ(with.contacts, without.contacts);
  EXPECT_EQ(with.totals.failures, 0);
  EXPECT_GT(with.totals.evaluations, 0);
}

// The pairs that hold a separation certificate in an engine's checkpoint (margin > 0).
int certified_pairs(const Engine& engine) {
  const std::string path = (std::filesystem::path(::testing::TempDir()) /
                            ("kdem_certificates_" + std::to_string(::getpid()) + ".h5"))
                               .string();
  engine.write_checkpoint(path);
  const std::vector<double> margin =
      read_checkpoint_dataset<double>(path, "pairs/separation_margin", H5T_NATIVE_DOUBLE);
  std::remove(path.c_str());
  return int(std::count_if(margin.begin(), margin.end(), [](double m) { return m > 0; }));
}

// A box certificate (the boxes' gap along their separating axis) bounds the bodies' gap, so it
// only skips pairs that cannot touch: the same contacts, no failure, positions within the
// agreement of the test above (the bodies' bounding radius is below the box's half-diagonal, so
// a certified pair's boxes may come to overlap before its certificate runs out; without the
// certificate the narrow phase then evaluates it, finds it apart and leaves it another warm
// start; measured: none did in this scene, the runs were bit for bit the same). The pairs whose
// boxes are apart hold certificates with them (counted in the checkpoint), and not without.
TEST(SeparationCertificates, RunsAgreeWithAndWithoutBoxCertificates) {
  const int steps = 4000;
  SceneConfig scene = cli_scene("small_superquadrics");
  Engine with(scene);
  modify_superquadric_contact(scene).box_certificates = false;
  Engine without(scene);
  with.advance(steps);
  without.advance(steps);
  const RunOutcome a = outcome_of(with), b = outcome_of(without);
  EXPECT_LT(largest_position_difference(a, b), 1e-9);
  EXPECT_GT(a.contacts, 0);
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.totals.failures, 0);
  EXPECT_EQ(b.totals.failures, 0);
  EXPECT_LE(a.totals.evaluations, b.totals.evaluations);
  const int certified_with = certified_pairs(with), certified_without = certified_pairs(without);
  EXPECT_GT(certified_with, certified_without + 10);
  RecordProperty("certified_pairs_with", std::to_string(certified_with));
  RecordProperty("certified_pairs_without", std::to_string(certified_without));
}

// The pour of small_superquadrics after 4000 steps: the engine's certificates keep the bound that
// makes the one-number test safe (expiry at most S + G / 2, with S the surface travel) and many of
// them hold by it (a certificate that never got an expiry would count none).
TEST(SeparationCertificates, CertificatesHoldByTheSurfaceTravelWithinHalfTheirGap) {
  Engine engine(cli_scene("small_superquadrics"));
  engine.advance(4000);
  const std::string path = (std::filesystem::path(::testing::TempDir()) /
                            ("kdem_expiry_" + std::to_string(::getpid()) + ".h5"))
                               .string();
  engine.write_checkpoint(path);
  const auto travel = read_checkpoint_dataset<double>(path, "surface_travel", H5T_NATIVE_DOUBLE);
  const auto margin =
      read_checkpoint_dataset<double>(path, "pairs/separation_margin", H5T_NATIVE_DOUBLE);
  const auto expiry =
      read_checkpoint_dataset<double>(path, "pairs/separation_expiry", H5T_NATIVE_DOUBLE);
  std::remove(path.c_str());
  ASSERT_EQ(travel.size(), 1u);
  ASSERT_EQ(margin.size(), expiry.size());
  EXPECT_GT(travel[0], 0);
  int held = 0, certified = 0;
  for (std::size_t k = 0; k < expiry.size(); ++k) {
    certified += margin[k] > 0;
    held += expiry[k] > travel[0];
    if (expiry[k] != 0)
      EXPECT_LE(expiry[k], travel[0] + 0.5 * margin[k]) << "row " << k;
    if (margin[k] == 0)
      EXPECT_EQ(expiry[k], 0) << "row " << k;
  }
  EXPECT_GT(held, 0);
  RecordProperty("certified_pairs", std::to_string(certified));
  RecordProperty("held_by_surface_travel", std::to_string(held));
}

// An expiry beyond S + G / 2 would let a pair pass through its partner unseen: a checkpoint that
// holds one is refused, naming the dataset.
TEST(SeparationCertificates, AnExpiryBeyondHalfTheGapIsRefused) {
  const SceneConfig scene = cli_scene("small_superquadrics");
  Engine engine(scene);
  engine.advance(2000);
  const std::string path = (std::filesystem::path(::testing::TempDir()) /
                            ("kdem_bad_expiry_" + std::to_string(::getpid()) + ".h5"))
                               .string();
  engine.write_checkpoint(path);
  const double travel =
      read_checkpoint_dataset<double>(path, "surface_travel", H5T_NATIVE_DOUBLE).at(0);
  const auto margin =
      read_checkpoint_dataset<double>(path, "pairs/separation_margin", H5T_NATIVE_DOUBLE);
  const auto certified = std::find_if(margin.begin(), margin.end(), [](double m) { return m > 0; });
  ASSERT_NE(certified, margin.end()) << "the run must hold a certificate";
  const std::size_t row = std::size_t(certified - margin.begin());
  ASSERT_TRUE(edit_checkpoint_dataset<double>(
      path, "pairs/separation_expiry", H5T_NATIVE_DOUBLE,
      [&](std::vector<double>& expiry) { expiry[row] = travel + margin[row]; }));
  Engine restarted(scene);
  try {
    restarted.read_checkpoint(path);
    ADD_FAILURE() << "a checkpoint with an expiry beyond its gap was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("pairs/separation_expiry of row " + std::to_string(row)),
              std::string::npos)
        << e.what();
  }
  std::remove(path.c_str());
}

} // namespace
} // namespace testing
} // namespace kdem
