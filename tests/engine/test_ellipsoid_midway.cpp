// The midway point of two ellipsoids as the root of one scalar function
// (shapes/ellipsoid_midway.hpp) against the general midway-point Newton of the same problem,
// whose solution is unique (the minimiser of the strictly convex max(F_i, F_j)): both solve it
// to the same tolerance, so they must agree to that tolerance, in point, normal and overlap,
// for touching and separated pairs, size ratios to 10, aspect ratios to 20, cold and warm.
#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "shapes/superquadric_contact.hpp"

#include "geometry_test_support.hpp"
#include "scene_builders.hpp"
#include "superquadric_scene.hpp"

namespace kdem {
namespace {

struct EllipsoidPair {
  PosedSuperquadric i, j;
  MidwayState previous;
  NarrowPhaseControls controls;
};

struct SolvePair {
  KOKKOS_INLINE_FUNCTION NarrowPhaseResult operator()(const EllipsoidPair& c) const {
    return superquadric_pair_contact(c.i, c.j, c.previous, c.controls);
  }
};

struct ScalarRootOnly {
  int iterations = 0;
  bool found = false;
  narrow_phase::EllipsoidMidway root;
};

struct SolveScalarRoot {
  KOKKOS_INLINE_FUNCTION ScalarRootOnly operator()(const EllipsoidPair& c) const {
    ScalarRootOnly out;
    const double length = math::min(c.i.smallest_length(), c.j.smallest_length());
    out.found = narrow_phase::ellipsoid_midway(c.i, c.j, c.previous.point, c.previous.multiplier,
                                               1e-12 * length, c.controls.max_iterations, out.root,
                                               out.iterations);
    return out;
  }
};

PosedSuperquadric random_ellipsoid(std::mt19937_64& rng, double scale, double aspect, Vec3 at) {
  const auto axis = [&] { return scale * log_uniform(rng, 1.0, aspect); };
  return pose_superquadric(make_superquadric(scale, axis(), axis(), 2, 2), at,
                           random_rotation(rng));
}

// Pairs whose centres are a random fraction of their bounding reach apart: deep overlaps,
// grazing contacts and separated pairs alike.
std::vector<EllipsoidPair> random_pairs(int count, double aspect, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<EllipsoidPair> pairs;
  for (int k = 0; k < count; ++k) {
    EllipsoidPair p;
    p.i = random_ellipsoid(rng, 1.0, aspect, Vec3{0.3, -0.1, 0.2});
    const double scale = k % 3 == 0 ? uniform(rng, 0.1, 1.0) : 1.0;
    p.j = random_ellipsoid(rng, scale, aspect, Vec3{0, 0, 0});
    const double reach = p.i.reach() + p.j.reach();
    p.j.centre = p.i.centre + uniform(rng, 0.2, 1.0) * reach * random_unit(rng);
    pairs.push_back(p);
  }
  return pairs;
}

double pair_length(const EllipsoidPair& p) {
  return std::min(p.i.smallest_length(), p.j.smallest_length());
}

struct Agreement {
  double point = 0, normal = 0, overlap = 0; // point and overlap in units of the pair's length
  int touching = 0, disagreements = 0;
  int general_fallbacks = 0; // pairs the general Newton solved only through its homotopy
};

Agreement compare(const std::vector<EllipsoidPair>& pairs,
                  const std::vector<NarrowPhaseResult>& scalar,
                  const std::vector<NarrowPhaseResult>& general) {
  Agreement a;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    // The scalar root needs no fallback; the general Newton sometimes does (deep overlaps of
    // elongated bodies), and then converges to the same point.
    EXPECT_EQ(scalar[k].status, 0) << k;
    EXPECT_NE(general[k].status, 2) << k;
    a.general_fallbacks += general[k].status == 1;
    if (scalar[k].geometry.touching != general[k].geometry.touching) {
      ++a.disagreements;
      continue;
    }
    const double length = pair_length(pairs[k]);
    a.point = std::max(a.point, norm(scalar[k].state.point - general[k].state.point) / length);
    if (!scalar[k].geometry.touching)
      continue;
    ++a.touching;
    a.normal = std::max(a.normal, norm(scalar[k].geometry.normal - general[k].geometry.normal));
    a.overlap = std::max(
        a.overlap, std::fabs(scalar[k].geometry.overlap - general[k].geometry.overlap) / length);
  }
  return a;
}

std::vector<NarrowPhaseResult> solve(std::vector<EllipsoidPair> pairs, bool scalar_root) {
  for (auto& p : pairs)
    p.controls.ellipsoid_scalar_root = scalar_root;
  return run_on_device<NarrowPhaseResult>(pairs, SolvePair{});
}

// Both solvers stop where the normals' angle and the level sets' gap are below the tolerance
// (1e-10), not at the same point: the solution moves by at most about the tolerance times the
// pair's length over the conditioning of the midway system, which the aspect ratio (20 here,
// curvatures 400 apart) bounds. Measured worst: see the printed line; the bounds are 1e-7 of the
// length for points and overlaps and 1e-8 for normals (tolerance x 1000 and x 100).
TEST(EllipsoidMidway, TheScalarRootGivesTheGeneralNewtonsContact) {
  const std::vector<EllipsoidPair> pairs = random_pairs(3000, 20.0, 17);
  const Agreement a = compare(pairs, solve(pairs, true), solve(pairs, false));
  std::cout << "[ measured ] ellipsoids, scalar root against general Newton: " << a.touching
            << " touching of " << pairs.size() << ", worst point " << a.point << " L, normal "
            << a.normal << ", overlap " << a.overlap << " L; general Newton through its fallback "
            << a.general_fallbacks << "\n";
  EXPECT_EQ(a.disagreements, 0);
  EXPECT_GT(a.touching, 500); // the pairs cover contacts, not only separated pairs
  EXPECT_LT(a.point, 1e-7);
  EXPECT_LT(a.normal, 1e-8);
  EXPECT_LT(a.overlap, 1e-7);
}

// Warm starts: each pair moved slightly from a solved pose, started from that pose's multiplier
// (what the pair kernel stores from step to step), gives the general Newton's contact too.
TEST(EllipsoidMidway, WarmStartsFromAMovedPoseAgree) {
  std::vector<EllipsoidPair> pairs = random_pairs(1000, 5.0, 23);
  const std::vector<NarrowPhaseResult> first = solve(pairs, true);
  std::mt19937_64 rng(29);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    pairs[k].previous = first[k].state;
    pairs[k].j.centre = pairs[k].j.centre + 1e-3 * pair_length(pairs[k]) * random_unit(rng);
  }
  const Agreement a = compare(pairs, solve(pairs, true), solve(pairs, false));
  EXPECT_EQ(a.disagreements, 0);
  EXPECT_LT(a.point, 1e-7);
  EXPECT_LT(a.normal, 1e-8);
  EXPECT_LT(a.overlap, 1e-7);
}

// The root itself: X is stationary (normals opposite) to rounding, the gap is at the requested
// 1e-12 of the length, and Newton from the stored multiplier of a slightly moved pose needs at
// most three steps (quadratic convergence from a relative error of order the motion, 1e-3:
// 1e-6, 1e-12, then below the 1e-12 asked for).
TEST(EllipsoidMidway, TheRootIsStationaryAndWarmStartsNeedAtMostThreeSteps) {
  std::vector<EllipsoidPair> pairs = random_pairs(2000, 10.0, 31);
  const std::vector<ScalarRootOnly> cold = run_on_device<ScalarRootOnly>(pairs, SolveScalarRoot{});
  double worst_angle = 0, worst_gap = 0;
  int most_cold = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ASSERT_TRUE(cold[k].found) << k;
    const PosedSuperquadric& i = pairs[k].i;
    const PosedSuperquadric& j = pairs[k].j;
    const Vec3 x = cold[k].root.point;
    const ShapeFunction fi = i.evaluate<false>(x), fj = j.evaluate<false>(x);
    worst_angle = std::max(worst_angle, norm(narrow_phase::unit_or_zero(fi.gradient) +
                                             narrow_phase::unit_or_zero(fj.gradient)));
    worst_gap =
        std::max(worst_gap, std::fabs(fi.value - fj.value) /
                                ((norm(fi.gradient) + norm(fj.gradient)) * pair_length(pairs[k])));
    most_cold = std::max(most_cold, cold[k].iterations);
    pairs[k].previous = MidwayState{x, cold[k].root.multiplier};
  }
  std::mt19937_64 rng(37);
  for (auto& p : pairs)
    p.j.centre = p.j.centre + 1e-3 * pair_length(p) * random_unit(rng);
  const std::vector<ScalarRootOnly> warm = run_on_device<ScalarRootOnly>(pairs, SolveScalarRoot{});
  int most_warm = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ASSERT_TRUE(warm[k].found) << k;
    most_warm = std::max(most_warm, warm[k].iterations);
  }
  std::cout << "[ measured ] scalar root: worst angle " << worst_angle << " rad, gap " << worst_gap
            << " L; most Newton steps cold " << most_cold << ", warm " << most_warm << "\n";
  // Rounding of the 3 x 3 solve, amplified by the conditioning of M (curvatures 100 apart).
  EXPECT_LT(worst_angle, 1e-12);
  // The stopping test is on the same quantity, with rounding of F (a few 1e-16) on top.
  EXPECT_LT(worst_gap, 1.1e-12);
  EXPECT_LE(most_warm, 3);
  EXPECT_LE(most_cold, 40);
}

// A cluster of 27 ellipsoids (aspect 2.5) on a grid, each moving towards the centre with a
// random spin, collides for 3000 steps: the scene key reaches the pair kernel, and the run is the
// same with either solver to the Newton tolerance: positions within 1e-10 m (1e-7 of a particle
// size; measured below), the same contacts, no failure.
testing::RunOutcome run_colliding_ellipsoids(bool scalar_root) {
  SceneConfig scene =
      testing::empty_scene(5e-7, {testing::material("glass", 2500, 1e8, 0.25, 0.5, 0.4)});
  scene.shapes.push_back(superquadric_shape_config("oblate", {1.2e-3, 0.8e-3, 0.5e-3}, 2, 2));
  scene.domain_min = {-0.01, -0.01, -0.01};
  scene.domain_max = {0.01, 0.01, 0.01};
  modify_superquadric_contact(scene).ellipsoid_scalar_root = scalar_root;
  Engine engine(scene);
  std::mt19937_64 rng(41);
  std::vector<ParticleInit> cluster;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        ParticleInit p;
        p.shape = 1;
        p.position = {2.2e-3 * x, 2.2e-3 * y, 2.2e-3 * z};
        p.velocity = {-0.4 * x, -0.4 * y, -0.4 * z};
        const Quat q = random_rotation(rng);
        p.orientation = {q.w, q.x, q.y, q.z};
        p.angular_velocity = {uniform(rng, -50, 50), uniform(rng, -50, 50), uniform(rng, -50, 50)};
        cluster.push_back(p);
      }
  engine.add_particles(cluster);
  testing::RunOutcome outcome;
  int most_contacts = 0;
  for (int k = 0; k < 3000; ++k) {
    engine.step();
    if (k % 50 == 0)
      most_contacts = std::max(most_contacts, engine.diagnostics().pair_contacts);
  }
  const ParticleSnapshot snapshot = engine.snapshot();
  for (std::size_t i = 0; i < snapshot.id.size(); ++i)
    outcome.position[snapshot.id[i]] = {snapshot.position[3 * i], snapshot.position[3 * i + 1],
                                        snapshot.position[3 * i + 2]};
  outcome.totals = engine.narrow_phase_totals();
  outcome.contacts = most_contacts;
  return outcome;
}

TEST(EllipsoidMidway, CollidingEllipsoidsRunTheSameWithEitherSolver) {
  const testing::RunOutcome scalar = run_colliding_ellipsoids(true);
  const testing::RunOutcome general = run_colliding_ellipsoids(false);
  const double largest = testing::largest_position_difference(scalar, general);
  std::cout << "[ measured ] colliding ellipsoids, scalar root against general Newton: positions "
            << largest << " m apart; most contacts " << scalar.contacts << "; iterations "
            << scalar.totals.iterations << " against " << general.totals.iterations << " in "
            << scalar.totals.evaluations << " and " << general.totals.evaluations
            << " evaluations\n";
  EXPECT_LT(largest, 1e-10);
  EXPECT_GT(scalar.contacts, 5);
  EXPECT_EQ(scalar.contacts, general.contacts);
  EXPECT_EQ(scalar.totals.failures + general.totals.failures, 0);
  EXPECT_EQ(scalar.totals.fallbacks, 0);
  // Where the key did not reach the kernel, both runs would count the same iterations.
  EXPECT_NE(scalar.totals.iterations, general.totals.iterations);
}

} // namespace
} // namespace kdem
