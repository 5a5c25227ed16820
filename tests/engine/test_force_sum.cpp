// The force sum owns each particle's force and torque: gravity, wall contacts and pair contacts
// of hand-made lists against the sums written out, and nothing of an earlier step survives.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/force_sum.hpp"
#include "src/host_copy.hpp"

namespace kdem {
namespace {

template <class View>
View rows_of(const std::string& label, const std::vector<typename View::non_const_value_type>& v,
             int columns) {
  return view_from_host<View>(label, v, columns);
}

Vec3 host_row(const Vec3View& view, int i) {
  const std::vector<double> flat = flatten_to_host(view, int(view.extent(0)));
  return {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
}

// Three particles: 0 touches a wall (entry 0) and not another (entry 1), 1 has no wall entry;
// pairs (0, 1) touching and (0, 2) within reach but apart; particle 2 has stale force and torque.
struct ThreeParticles {
  ParticleViews p;
  WallContactList walls;
  PairList pairs;
  Vec3 gravity{0, 0, -9.81};
  Vec3 wall_force{0.5, 0, 3}, wall_torque{0, -0.25, 0};
  Vec3 pair_force{-2, 1, 0.5}, pair_torque{0.1, 0.2, -0.3}, pair_torque_j{-0.4, 0.05, 0.7};

  ThreeParticles() {
    p.allocate(3);
    p.position = rows_of<Vec3View>("position", {0, 0, 0, 1, 0, 0, 0, 1, 0}, 3);
    p.mass = rows_of<ScalarView>("mass", {1.5, 2.0, 0.5}, 1);
    p.force = rows_of<Vec3View>("force", {7, 7, 7, 7, 7, 7, 7, 7, 7}, 3);
    p.torque = rows_of<Vec3View>("torque", {5, 5, 5, 5, 5, 5, 5, 5, 5}, 3);
    walls.entry_count = 2;
    walls.row_start = rows_of<IndexView>("row_start", {0, 2, 2, 2}, 1);
    walls.overlap = rows_of<ScalarView>("overlap", {1e-4, 0}, 1);
    walls.force_on_i =
        rows_of<Vec3View>("wall_force", {wall_force.x, wall_force.y, wall_force.z, 0, 0, 0}, 3);
    walls.torque_on_i =
        rows_of<Vec3View>("wall_torque", {wall_torque.x, wall_torque.y, wall_torque.z, 0, 0, 0}, 3);
    pairs.pair_count = 2;
    pairs.row_start = rows_of<IndexView>("row_start", {0, 2, 2, 2}, 1);
    pairs.pair_i = rows_of<IndexView>("pair_i", {0, 0}, 1);
    pairs.pair_j = rows_of<IndexView>("pair_j", {1, 2}, 1);
    pairs.reverse_start = rows_of<IndexView>("reverse_start", {0, 0, 1, 2}, 1);
    pairs.reverse_pair = rows_of<IndexView>("reverse_pair", {0, 1}, 1);
    pairs.force_on_i =
        rows_of<Vec3View>("pair_force", {pair_force.x, pair_force.y, pair_force.z, 0, 0, 0}, 3);
    pairs.torque_on_i =
        rows_of<Vec3View>("pair_torque", {pair_torque.x, pair_torque.y, pair_torque.z, 0, 0, 0}, 3);
    pairs.torque_on_j = rows_of<Vec3View>(
        "pair_torque_j", {pair_torque_j.x, pair_torque_j.y, pair_torque_j.z, 0, 0, 0}, 3);
  }
};

// Each sum has at most three terms of magnitude ~10: the tolerance is a few ulps of that.
constexpr double tolerance = 1e-14;

void expect_near(Vec3 a, Vec3 b) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(ForceSum, AddsGravityWallsAndPairsAndKeepsNothingOfEarlierSteps) {
  ThreeParticles s;
  sum_forces(s.p, s.gravity, s.walls, s.pairs);
  expect_near(host_row(s.p.force, 0), 1.5 * s.gravity + s.wall_force + s.pair_force);
  expect_near(host_row(s.p.torque, 0), s.wall_torque + s.pair_torque);
  expect_near(host_row(s.p.force, 1), 2.0 * s.gravity - s.pair_force);
  expect_near(host_row(s.p.torque, 1), s.pair_torque_j);
  // Particle 2 is j of a pair that does not touch: gravity alone, no torque.
  expect_near(host_row(s.p.force, 2), 0.5 * s.gravity);
  expect_near(host_row(s.p.torque, 2), Vec3{});
}

TEST(ForceSum, RepeatedSumsAreBitIdentical) {
  ThreeParticles s;
  sum_forces(s.p, s.gravity, s.walls, s.pairs);
  const std::vector<double> first = flatten_to_host(s.p.force, 3);
  sum_forces(s.p, s.gravity, s.walls, s.pairs);
  EXPECT_EQ(flatten_to_host(s.p.force, 3), first);
}

TEST(ForceSum, ParticlesWithoutContactsGetGravityOnly) {
  ThreeParticles s;
  s.walls.row_start = rows_of<IndexView>("row_start", {0, 0, 0, 0}, 1);
  s.pairs.row_start = rows_of<IndexView>("row_start", {0, 0, 0, 0}, 1);
  s.pairs.reverse_start = rows_of<IndexView>("reverse_start", {0, 0, 0, 0}, 1);
  sum_forces(s.p, s.gravity, s.walls, s.pairs);
  const std::vector<double> masses{1.5, 2.0, 0.5};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(host_row(s.p.force, i).z, masses[i] * s.gravity.z);
    expect_near(host_row(s.p.torque, i), Vec3{});
  }
}

} // namespace
} // namespace kdem
