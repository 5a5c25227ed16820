// Flat faces of dilated polyhedra resting on each other: the contacts are the corners of the
// faces, and a tilt of the order of overlap / face size takes every corner but the lowest out of
// its normal cone while its overlap is still large. The cone weight (ConeSlack::fade) makes such
// a corner fade out, so that the pair's force is continuous in the pose; cut at the slack it
// jumps, which fed a rocking of stacked plates that never died out (cases/stack).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "dilated_test_support.hpp"
#include "kernels/dilated_polyhedron/family.hpp"

namespace kdem::testing {
namespace {

TEST(ConeSlackWeight, IsASmoothStepFromTheSlackToTheFade) {
  const ConeSlack s = ConeSlack::of_angle(1e-6, 0.02);
  const double fade = std::sin(0.02);
  EXPECT_EQ(s.weight(-1.0), 1.0);
  EXPECT_EQ(s.weight(s.sine), 1.0);
  EXPECT_NEAR(s.weight(s.sine + 0.5 * fade), 0.5, 1e-15); // 1 - 3/4 + 2/8
  EXPECT_NEAR(s.weight(s.sine + 0.25 * fade), 1.0 - 3.0 / 16 + 2.0 / 64, 1e-15);
  EXPECT_EQ(s.weight(s.sine + fade), 0.0);
  EXPECT_EQ(s.weight(1.0), 0.0);
  // Monotone and continuous: neighbouring samples 1e-4 of the fade apart differ by at most the
  // steepest slope (3/2 per fade) times the spacing.
  double before = 1.0;
  for (int k = 0; k <= 12000; ++k) {
    const double w = s.weight(s.sine + (k * 1e-4 - 0.1) * fade);
    EXPECT_LE(w, before);
    EXPECT_LE(before - w, 1.5e-4 + 1e-15);
    before = w;
  }
  // No fade: the cut at the slack.
  const ConeSlack cut = ConeSlack::of_angle(1e-6);
  EXPECT_EQ(cut.weight(cut.sine), 1.0);
  EXPECT_EQ(cut.weight(cut.sine * (1 + 1e-9)), 0.0);
}

// The pair's force (Hertz shape: weight x overlap^1.5 along the normal, stiffness 1) and its
// moment about B's centre, B placed by `pose` in A's frame.
struct PairWrench {
  Vec3 force, moment;
  int contacts = 0;
};

PairWrench pair_wrench(const DilatedCore& a, const DilatedCore& b, const RelativePose& pose,
                       const DilatedContactSettings& settings) {
  DeepestContacts<16> deepest(settings, std::min(a.dilation(), b.dilation()));
  EXPECT_TRUE(dilated_pair_contacts(a, b, pose, settings.slack, deepest));
  PairWrench w;
  w.contacts = deepest.count;
  EXPECT_EQ(deepest.missed, 0);
  deepest.weights(settings.averaging, [&](int c, double weight) {
    const FeatureContact& f = deepest.contact[c];
    // Normals from B towards A: the force on B is against it.
    const Vec3 on_b = (-weight * std::pow(f.overlap, 1.5)) * f.normal;
    w.force = w.force + on_b;
    w.moment = w.moment + cross(f.point - pose.translation, on_b);
  });
  return w;
}

// The engine's defaults (docs/scene.md, dilated_polyhedron_contact): slack 1e-6 rad, fade
// 0.002 rad, contacts within half the dilation radius merged; and the cut without merging.
DilatedContactSettings engine_defaults() {
  DilatedContactSettings s;
  s.slack = ConeSlack::of_angle(1e-6, 0.002);
  s.merge = 0.5;
  return s;
}

DilatedContactSettings cut_at_the_slack() {
  DilatedContactSettings s;
  s.slack = ConeSlack::of_angle(1e-6);
  s.merge = 0;
  return s;
}

Mat3 turn_about_x(double angle) {
  return rotation_matrix(Quat{std::cos(0.5 * angle), std::sin(0.5 * angle), 0, 0});
}

// The largest change of the force and of the moment between neighbouring poses of a sweep
// (pose_of(t), t from 0 to 1 in `samples` steps), each against the largest force (moment) met.
struct SweepJumps {
  double force = 0, moment = 0;
};

template <class PoseOf>
SweepJumps sweep(const DilatedCore& a, const DilatedCore& b, int samples, const PoseOf& pose_of,
                 const DilatedContactSettings& settings) {
  double largest_force = 0, largest_moment = 0, force_jump = 0, moment_jump = 0;
  PairWrench before = pair_wrench(a, b, pose_of(0.0), settings);
  for (int k = 1; k <= samples; ++k) {
    const PairWrench now = pair_wrench(a, b, pose_of(double(k) / samples), settings);
    EXPECT_GE(now.contacts, 1) << k;
    force_jump = std::max(force_jump, norm(now.force - before.force));
    moment_jump = std::max(moment_jump, norm(now.moment - before.moment));
    largest_force = std::max(largest_force, norm(now.force));
    largest_moment = std::max(largest_moment, norm(now.moment));
    before = now;
  }
  return SweepJumps{force_jump / largest_force, moment_jump / largest_moment};
}

// A sweep at two resolutions, the second 4 times finer: a continuous force changes by about a
// quarter as much per finer step, a jump by as much.
struct Refinement {
  SweepJumps coarse, fine;
  double force_ratio() const { return fine.force / coarse.force; }
  double moment_ratio() const { return fine.moment / coarse.moment; }
};

template <class PoseOf>
Refinement refine(const DilatedCore& a, const DilatedCore& b, int samples, const PoseOf& pose_of,
                  const DilatedContactSettings& settings) {
  return Refinement{sweep(a, b, samples, pose_of, settings),
                    sweep(a, b, 4 * samples, pose_of, settings)};
}

// Two equal plates (core 2 x 2 x 0.2, r = 0.05), B on A, aligned: their corners coincide.
// Overlap 0.01 (a fifth of r), so that the corners leave their cones at a tilt of 1e-6 rad and
// their overlap at 5e-3.
struct Plates {
  double half = 1.0, thickness = 0.1, r = 0.05, overlap = 0.01;
  DilatedCore a = test::core_of(test::box_mesh(half, half, thickness), r);
  DilatedCore b = a;
  double height() const { return 2 * thickness + 2 * r - overlap; }
};

void record(const std::string& name, const Refinement& r) {
  ::testing::Test::RecordProperty(name + "_force_jump", std::to_string(r.coarse.force));
  ::testing::Test::RecordProperty(name + "_moment_jump", std::to_string(r.coarse.moment));
  ::testing::Test::RecordProperty(name + "_moment_ratio", std::to_string(r.moment_ratio()));
}

// Cut at the slack without merging, the moment jumps by more than 10 % of its largest at both
// resolutions (a discontinuity: the ratio stays near 1).
void expect_the_cut_jumps(const Refinement& cut) {
  EXPECT_GT(cut.coarse.moment, 0.1);
  EXPECT_GT(cut.fine.moment, 0.1);
}

TEST(DilatedFlatContacts, TiltedPlateOnPlateGivesAContinuousForce) {
  // B tilted about x from -0.01 to 0.01 rad, through parallel, where all four corners carry it,
  // to where one edge alone does (1000 and 4000 steps).
  const Plates plates;
  const auto tilted = [&](double t) {
    return RelativePose{turn_about_x(-0.01 + 0.02 * t), Vec3{0, 0, plates.height()}};
  };
  const Refinement faded = refine(plates.a, plates.b, 1000, tilted, engine_defaults());
  const Refinement cut = refine(plates.a, plates.b, 1000, tilted, cut_at_the_slack());
  record("faded", faded);
  record("cut", cut);
  // Stated: with the engine's defaults the largest change per step falls at least 2.5 times
  // (4 expected of a continuous force) with a 4 times finer step, and is below 2 % of the
  // largest at the coarse step (the fade's slope, 3/2 per 0.002 rad, over 2e-5 rad: 1.5 % of a
  // corner's share). Measured: 3.5e-3 (force) and 6.2e-3 (moment), ratio 0.25; cut 0.36, 1.0.
  EXPECT_LT(faded.coarse.force, 0.02);
  EXPECT_LT(faded.coarse.moment, 0.02);
  EXPECT_LT(faded.force_ratio(), 0.4);
  EXPECT_LT(faded.moment_ratio(), 0.4);
  expect_the_cut_jumps(cut);
}

TEST(DilatedFlatContacts, ShiftedPlateOnPlateGivesAContinuousForce) {
  // B tilted by 1e-3 rad about x and slid along x through the aligned pose, -0.01 to 0.01 of
  // the half-width (500 and 2000 steps): the corners' contacts change kind (vertex on vertex,
  // vertex on edge, vertex on face, edge on edge) as B's corners pass A's.
  const Plates plates;
  const auto shifted = [&](double t) {
    return RelativePose{turn_about_x(1e-3), Vec3{-0.01 + 0.02 * t, 0, plates.height()}};
  };
  const Refinement faded = refine(plates.a, plates.b, 500, shifted, engine_defaults());
  const Refinement cut = refine(plates.a, plates.b, 500, shifted, cut_at_the_slack());
  record("faded", faded);
  record("cut", cut);
  // Stated: with the engine's defaults the moment's change per step falls at least 2 times with
  // a 4 times finer step and stays below 10 % of the largest (measured 7.7e-2, ratio 0.38: the
  // fade is steep for a slide of 4e-5 per step at a 0.19 gap). The force keeps a step of at
  // most 2e-3 of the largest at any resolution (measured 7.6e-4): where several feature pairs
  // merge into one contact the strongest is kept, and they differ slightly in point and normal
  // when the strongest changes. Cut: the moment jumps by 0.32 at both resolutions.
  EXPECT_LT(faded.coarse.moment, 0.1);
  EXPECT_LT(faded.moment_ratio(), 0.5);
  EXPECT_LT(faded.coarse.force, 2e-3);
  EXPECT_LT(faded.fine.force, 2e-3);
  expect_the_cut_jumps(cut);
}

} // namespace
} // namespace kdem::testing
