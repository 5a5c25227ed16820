// The host narrow phase in lanes (shapes/superquadric_lanes.hpp) against the scalar solve it
// stands in for (superquadric_pair_contact, itself tested against brute force in
// test_superquadric_contact.cpp): four pairs of one shape pair moving through contact as in a
// simulation, each step started from the last step's midway point, solved both ways from the
// same start.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "shapes/superquadric_lanes.hpp"

#include "geometry_test_support.hpp"

namespace kdem {
namespace {

#if KDEM_HOST_LANES

constexpr int width = lanes::width;

struct LanePoses {
  PosedSuperquadric i[width], j[width];
};

lanes::PairInputs lane_inputs(const LanePoses& poses, const MidwayState (&start)[width]) {
  lanes::PairInputs in;
  for (int l = 0; l < width; ++l)
    lanes::set_lane(in, l, poses.i[l], poses.j[l], start[l]);
  return in;
}

// Four pairs of shapes (si, sj): j passes i on a straight line at a lane's own offset while both
// spin, entering contact, overlapping by up to a few per cent of the size and leaving.
std::vector<LanePoses> moving_lanes(const SuperquadricShape& si, const SuperquadricShape& sj,
                                    int poses, std::mt19937_64& rng) {
  const double reach = std::sqrt(si.a * si.a + si.b * si.b + si.c * si.c) +
                       std::sqrt(sj.a * sj.a + sj.b * sj.b + sj.c * sj.c);
  const double gap = std::min({si.a, si.b, si.c}) + std::min({sj.a, sj.b, sj.c});
  std::vector<LanePoses> sequence(poses);
  for (int l = 0; l < width; ++l) {
    const Quat qi = random_rotation(rng), qj = random_rotation(rng);
    const Vec3 spin_i = 0.5 * random_unit(rng), spin_j = 0.8 * random_unit(rng);
    const Vec3 direction = random_unit(rng);
    const Vec3 offset = random_unit_perpendicular(rng, direction);
    const double miss = uniform(rng, 0.7, 1.0) * gap; // passes through the others' reach
    for (int p = 0; p < poses; ++p) {
      const double t = double(p) / (poses - 1);
      const Vec3 centre_j = miss * offset + (2.0 * reach * (t - 0.5)) * direction;
      sequence[p].i[l] =
          pose_superquadric(si, {}, normalized(quat_from_rotation_vector(t * spin_i) * qi));
      sequence[p].j[l] =
          pose_superquadric(sj, centre_j, normalized(quat_from_rotation_vector(t * spin_j) * qj));
    }
  }
  return sequence;
}

// The distance along `direction` at which body j (orientation qj) placed at centre_i + d
// direction begins to touch body i: bisection on whether the scalar solve finds a contact.
double touching_distance(const SuperquadricShape& si, Quat qi, const SuperquadricShape& sj, Quat qj,
                         Vec3 direction) {
  double touching = 0, apart = std::sqrt(si.a * si.a + si.b * si.b + si.c * si.c) +
                               std::sqrt(sj.a * sj.a + sj.b * sj.b + sj.c * sj.c);
  for (int k = 0; k < 60; ++k) {
    const double d = 0.5 * (touching + apart);
    const NarrowPhaseResult r = superquadric_pair_contact(
        pose_superquadric(si, {}, qi), pose_superquadric(sj, d * direction, qj), {}, {});
    (r.geometry.touching ? touching : apart) = d;
  }
  return apart;
}

// Four pairs of shapes (si, sj) as contacts in a bed: j comes from 3 % of the smaller size apart
// to an overlap of 5 % and back, sliding sideways by 10 % and both turning by 0.2 rad.
std::vector<LanePoses> bed_contacts(const SuperquadricShape& si, const SuperquadricShape& sj,
                                    int poses, std::mt19937_64& rng) {
  const double size = std::min({si.a, si.b, si.c, sj.a, sj.b, sj.c});
  std::vector<LanePoses> sequence(poses);
  for (int l = 0; l < width; ++l) {
    const Quat qi = random_rotation(rng), qj = random_rotation(rng);
    const Vec3 spin_i = 0.2 * random_unit(rng), spin_j = 0.2 * random_unit(rng);
    const Vec3 direction = random_unit(rng);
    const Vec3 slide = (0.1 * size) * random_unit_perpendicular(rng, direction);
    const double contact = touching_distance(si, qi, sj, qj, direction);
    for (int p = 0; p < poses; ++p) {
      const double t = double(p) / (poses - 1);
      const double d = contact + size * (0.03 - 0.08 * std::sin(pi * t));
      sequence[p].i[l] =
          pose_superquadric(si, {}, normalized(quat_from_rotation_vector(t * spin_i) * qi));
      sequence[p].j[l] = pose_superquadric(sj, d * direction + t * slide,
                                           normalized(quat_from_rotation_vector(t * spin_j) * qj));
    }
  }
  return sequence;
}

struct Comparison {
  long pairs = 0, warm = 0, solved_in_lanes = 0, touching = 0, same_iterations = 0;
  long warm_touching = 0, warm_touching_in_lanes = 0;
  double overlap = 0, normal = 0, point = 0, curvature = 0, separation = 0;
};

// A pair solved in lanes against the scalar solve of it.
void compare(const NarrowPhaseResult& r, const NarrowPhaseResult& scalar, double size,
             Comparison& c) {
  ++c.solved_in_lanes;
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(scalar.status, 0) << "the scalar solve failed where the lanes converged";
  EXPECT_EQ(r.geometry.touching, scalar.geometry.touching);
  if (r.iterations != scalar.iterations)
    return; // an iteration apart: both within the Newton tolerance of the midway point
  ++c.same_iterations;
  c.separation = std::max(c.separation, std::fabs(r.separation - scalar.separation) / size);
  c.point = std::max(c.point, norm(r.state.point - scalar.state.point) / size);
  if (!(r.geometry.touching && scalar.geometry.touching))
    return;
  ++c.touching;
  c.overlap = std::max(c.overlap, std::fabs(r.geometry.overlap - scalar.geometry.overlap) / size);
  c.normal = std::max(c.normal, norm(r.geometry.normal - scalar.geometry.normal));
  c.point = std::max(c.point, norm(r.geometry.point - scalar.geometry.point) / size);
  for (const auto& [a, b] :
       {std::pair{r.curvature_i, scalar.curvature_i}, std::pair{r.curvature_j, scalar.curvature_j}})
    c.curvature = std::max(c.curvature, std::fabs(a - b) / std::max(std::fabs(b), 1 / size));
}

// Runs a sequence both ways: every pose from the scalar solve's last state (so that both start
// from the same point), the lanes' results compared with the scalar's.
void compare_sequence(const SuperquadricShape& si, const SuperquadricShape& sj,
                      const std::vector<LanePoses>& sequence, Comparison& c) {
  NarrowPhaseControls controls;
  controls.ellipsoid_scalar_root = false; // the lanes' Newton for ellipsoids too
  const double size = std::min({si.a, si.b, si.c, sj.a, sj.b, sj.c});
  MidwayState state[width];
  for (const LanePoses& poses : sequence) {
    NarrowPhaseResult in_lanes[width];
    const int solved =
        lanes::superquadric_pair_contact(si, sj, lane_inputs(poses, state), controls, in_lanes);
    for (int l = 0; l < width; ++l) {
      const NarrowPhaseResult scalar =
          superquadric_pair_contact(poses.i[l], poses.j[l], state[l], controls);
      ++c.pairs;
      const bool warm = state[l].multiplier > 0;
      c.warm += warm;
      if (!warm)
        EXPECT_FALSE(solved & (1 << l)) << "a lane without a warm start is the scalar solve's";
      if (warm && scalar.geometry.touching) {
        ++c.warm_touching;
        c.warm_touching_in_lanes += (solved >> l) & 1;
      }
      if (solved & (1 << l))
        compare(in_lanes[l], scalar, size, c);
      state[l] = scalar.state;
    }
  }
}

struct ShapePair {
  std::string name;
  SuperquadricShape i, j;
};

// The engine's bed shapes, a size ratio of 10, and exponents that are not integers (pow in F) or
// differ between the two bodies.
std::vector<ShapePair> shape_pairs() {
  return {
      {"cubes n=8", make_superquadric(1, 1, 1, 8, 8), make_superquadric(1, 1, 1, 8, 8)},
      {"cylinders n1=8 n2=2", make_superquadric(1, 1, 1, 8, 2), make_superquadric(1, 1, 1, 8, 2)},
      {"ellipsoids 1:1:2", make_superquadric(1, 1, 2, 2, 2), make_superquadric(1, 1, 2, 2, 2)},
      {"n1=3.5 n2=5.3 against n1=6 n2=2.5", make_superquadric(1, 0.7, 1.3, 3.5, 5.3),
       make_superquadric(0.8, 1.1, 0.6, 6, 2.5)},
      {"size ratio 10, n=4", make_superquadric(1, 1, 1, 4, 4),
       make_superquadric(0.1, 0.12, 0.08, 4, 4)},
  };
}

// Tolerances: from the same start, through the same formulas in the same order and the same
// number of iterations, a lane and the scalar solve differ only where the compiler contracts
// a * b + c differently in vector and scalar code: rounding (1e-16) amplified by the 4 x 4
// solve and the crossings; the largest differences measured are 1e-14 of the size (section 22
// of docs/performance.md), so 1e-12 of the size for overlaps, points and separations and of a
// rad for normals, relative for curvatures, leaves a factor of 100. Pairs that stop an
// iteration apart (rounding deciding the convergence test; at most 1 % of them allowed) are not
// compared here: both are within the Newton tolerance of the one midway point.
void expect_agreement(const Comparison& c, const std::string& name) {
  EXPECT_GT(c.same_iterations, 0.99 * c.solved_in_lanes) << name;
  EXPECT_LT(c.overlap, 1e-12) << name;
  EXPECT_LT(c.normal, 1e-12) << name;
  EXPECT_LT(c.point, 1e-12) << name;
  EXPECT_LT(c.curvature, 1e-12) << name;
  EXPECT_LT(c.separation, 1e-12) << name;
}

void print(const Comparison& c, const std::string& name) {
  std::cout << "[ measured ] lanes, " << name << ": " << c.pairs << " pairs, " << c.warm
            << " warm, " << c.solved_in_lanes << " solved in lanes (" << c.touching << " touching; "
            << c.warm_touching_in_lanes << " of " << c.warm_touching
            << " warm touching pairs), same iterations " << c.same_iterations
            << "; largest differences: overlap " << c.overlap << ", normal " << c.normal
            << ", point " << c.point << ", curvature " << c.curvature << ", separation "
            << c.separation << "\n";
}

// Runs `groups` sequences of four pairs made by make_sequence for every shape pair.
template <class MakeSequence>
std::vector<std::pair<std::string, Comparison>> compare_shape_pairs(std::uint64_t seed, int groups,
                                                                    const std::string& what,
                                                                    MakeSequence make_sequence) {
  std::mt19937_64 rng(seed);
  std::vector<std::pair<std::string, Comparison>> all;
  for (const ShapePair& shapes : shape_pairs()) {
    Comparison c;
    for (int group = 0; group < groups; ++group)
      compare_sequence(shapes.i, shapes.j, make_sequence(shapes.i, shapes.j, 200, rng), c);
    print(c, shapes.name + " " + what);
    expect_agreement(c, shapes.name);
    all.emplace_back(shapes.name, c);
  }
  return all;
}

// Pairs passing through each other (overlaps up to a third of the size, fast turns): the lanes
// hand back much of the deep part (crossings that need more than four steps), and what they
// solve agrees with the scalar solve.
TEST(SuperquadricLanes, LanesMatchTheScalarSolveOnPairsPassingThrough) {
  for (const auto& [name, c] : compare_shape_pairs(77, 6, "passing through", moving_lanes))
    EXPECT_GT(c.touching, 500) << name << ": too few contacts to compare";
}

// Contacts as in a bed (overlaps up to 5 % of the size, slow sliding and turning): nearly every
// warm-started touching pair is solved in lanes, as in the engine's settled beds (99.7 % of the
// pairs, docs/performance.md section 22).
TEST(SuperquadricLanes, LanesSolveBedContactsAsTheScalarSolveDoes) {
  for (const auto& [name, c] : compare_shape_pairs(78, 4, "in a bed", bed_contacts)) {
    EXPECT_GT(c.warm_touching, 1000) << name << ": too few contacts to compare";
    EXPECT_GT(c.warm_touching_in_lanes, 0.95 * c.warm_touching) << name;
  }
}

// What the lanes do not solve is handed back: no warm start, a non-finite pose, a start far
// from the solution (more steps than the lanes take, or a step the line search would shorten).
TEST(SuperquadricLanes, LanesHandBackWhatTheyDoNotSolve) {
  const SuperquadricShape cube = make_superquadric(1, 1, 1, 8, 8);
  LanePoses poses;
  MidwayState start[width];
  std::mt19937_64 rng(3);
  for (int l = 0; l < width; ++l) {
    const Quat qi = random_rotation(rng), qj = random_rotation(rng);
    const Vec3 direction = random_unit(rng);
    const double overlap = 0.01; // of the size
    poses.i[l] = pose_superquadric(cube, {}, qi);
    poses.j[l] = pose_superquadric(
        cube, (touching_distance(cube, qi, cube, qj, direction) - overlap) * direction, qj);
    const NarrowPhaseResult solved =
        superquadric_pair_contact(poses.i[l], poses.j[l], MidwayState{}, NarrowPhaseControls{});
    ASSERT_EQ(solved.status, 0);
    start[l] = solved.state;
  }
  NarrowPhaseResult out[width];
  const NarrowPhaseControls controls;
  ASSERT_EQ(lanes::superquadric_pair_contact(cube, cube, lane_inputs(poses, start), controls, out),
            (1 << width) - 1)
      << "converged starts are solved in lanes";
  for (int l = 0; l < width; ++l) {
    EXPECT_EQ(out[l].iterations, 0);
    EXPECT_TRUE(out[l].geometry.touching);
  }
  start[0].multiplier = 0;                                // no warm start
  poses.j[1].centre.x = std::nan("");                     // not finite
  start[2].point = start[2].point + Vec3{0.9, -0.8, 0.7}; // far from the midway point
  start[3].multiplier = 1e-3 * start[3].multiplier;       // a poor multiplier
  const int solved =
      lanes::superquadric_pair_contact(cube, cube, lane_inputs(poses, start), controls, out);
  EXPECT_FALSE(solved & 1);
  EXPECT_FALSE(solved & 2);
  for (int l = 2; l < width; ++l) {
    if (!(solved & (1 << l)))
      continue;
    // Solved after all: then it is the scalar solve's answer.
    const NarrowPhaseResult scalar =
        superquadric_pair_contact(poses.i[l], poses.j[l], start[l], controls);
    EXPECT_NEAR(out[l].geometry.overlap, scalar.geometry.overlap, 1e-7) << "lane " << l;
  }
}

#else

TEST(SuperquadricLanes, LanesSolveBedContactsAsTheScalarSolveDoes) {
  GTEST_SKIP() << "no host lanes in this build (nvcc): the narrow phase solves one pair at a time";
}

#endif

} // namespace
} // namespace kdem
