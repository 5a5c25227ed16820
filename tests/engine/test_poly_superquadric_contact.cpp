// Poly-superquadric narrow phases (shapes/poly_superquadric_contact.hpp) against brute-force
// references (convex_reference.hpp, on radial surface points that pick each octant's semi-axes)
// and the hard cases of the book's chapter 3: contacts on octant planes and axes, the rim of a
// thin hemisphere, poor starts, warm starts along moving pairs. Solves run in parallel_for on the
// backend under test; references run on the host.
#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "kernels/families/narrow_phase_tally.hpp"
#include "shapes/poly_superquadric_contact.hpp"
#include "shapes/surface_wall.hpp"

#include "convex_reference.hpp"
#include "geometry_test_support.hpp"

namespace kdem {
namespace {

using namespace testing;

PosedPolySuperquadric posed_poly(Vec3 plus, Vec3 minus, double n1, double n2, Vec3 origin, Quat q) {
  return PosedPolySuperquadric{make_poly_superquadric(plus, minus, n1, n2), origin,
                               rotation_matrix(q)};
}

// The reference body: the radial point along u of the superquadric of u's octant.
BruteForceBody reference_body(const PosedPolySuperquadric& body) {
  return BruteForceBody(body.centre, body.rotation, [shape = body.shape](Vec3 u) {
    return radial_surface_point(octant_shape(shape, octant_of(u)), u);
  });
}

double size_of(const PosedPolySuperquadric& b) {
  return b.equivalent_radius();
}

// Moves j so that the projections of i and j on the unit normal n (from j towards i) overlap by
// `overlap`.
PosedPolySuperquadric place_in_contact(const PosedPolySuperquadric& i, PosedPolySuperquadric j,
                                       Vec3 n, double overlap) {
  const Vec3 touch_i = reference_body(i).support(-n).point;
  j.centre = Vec3{0, 0, 0};
  const Vec3 touch_j = reference_body(j).support(n).point;
  j.centre = touch_i - touch_j + overlap * n;
  return j;
}

struct PolyCase {
  PosedPolySuperquadric i, j;
  MidwayState previous;
  NarrowPhaseControls controls;
};

struct EvaluatePolyCase {
  KOKKOS_INLINE_FUNCTION NarrowPhaseResult operator()(const PolyCase& c) const {
    return piecewise_pair_contact(c.i, c.j, c.previous, c.controls);
  }
};

// Every octant pair solved from the cold start: how many are accepted by the octant tests, and
// the largest distance of their points from the first accepted one.
struct AcceptedPairs {
  int count = 0;
  double spread = 0;
};

struct CountAcceptedPairs {
  KOKKOS_INLINE_FUNCTION AcceptedPairs operator()(const PolyCase& c) const {
    AcceptedPairs out;
    Vec3 first;
    for (int a = 0; a < octant_count; ++a)
      for (int b = 0; b < octant_count; ++b) {
        const NarrowPhaseResult r =
            superquadric_pair_contact(c.i.element(a), c.j.element(b), MidwayState{}, c.controls);
        if (r.status == 2 || !piecewise::in_piece(c.i, r.state.point, a) ||
            !piecewise::in_piece(c.j, r.state.point, b))
          continue;
        if (out.count == 0)
          first = r.state.point;
        out.spread = math::max(out.spread, norm(r.state.point - first));
        ++out.count;
      }
    return out;
  }
};

struct Comparison {
  double depth_error = 0;  // |overlap - reference depth| / reference depth
  double normal_error = 0; // rad
  double chord_excess = 0; // overlap - projected overlap along the found normal, / size
  double relative_depth = 0;
};

Comparison compare_with_reference(const PolyCase& c, const NarrowPhaseResult& r) {
  const BruteForceBody bi = reference_body(c.i), bj = reference_body(c.j);
  // The normal to 1e-6 rad: the depth is stationary there (its error is ~1e-12 of the size), and
  // a finer search only follows the support searches' rounding (and takes minutes).
  const Penetration ref = penetration_depth(bi, bj, 1e-6);
  const double size = std::min(size_of(c.i), size_of(c.j));
  Comparison out;
  out.relative_depth = ref.depth / size;
  out.depth_error = std::fabs(r.geometry.overlap - ref.depth) / ref.depth;
  out.normal_error = angle_between(r.geometry.normal, ref.normal);
  out.chord_excess = (r.geometry.overlap - projected_overlap(bi, bj, r.geometry.normal)) / size;
  return out;
}

Vec3 random_extents(std::mt19937_64& rng) {
  return {uniform(rng, 0.5, 1.5), uniform(rng, 0.5, 1.5), uniform(rng, 0.5, 1.5)};
}

PosedPolySuperquadric random_poly(std::mt19937_64& rng, Vec3 origin) {
  const double n[] = {2, 3, 4};
  const double n1 = n[rng() % 3], n2 = n[rng() % 3];
  return posed_poly(random_extents(rng), random_extents(rng), n1, n2, origin, random_rotation(rng));
}

struct NamedCase {
  std::string name;
  PolyCase pair;
};

// Random shapes; contact normals random, in an octant plane of i (a zero local component) or
// along an octant axis of i (four octants meet), at 1 % of the size.
std::vector<NamedCase> random_cases(int count, std::mt19937_64& rng) {
  std::vector<NamedCase> cases;
  for (int k = 0; k < count; ++k) {
    PolyCase c;
    c.i = random_poly(rng, {0.1, -0.2, 0.3});
    c.j = random_poly(rng, {});
    Vec3 local = random_unit(rng);
    std::string name = "random normal";
    if (k % 3 == 1) {
      local = Vec3{local.x, local.y, 0}, name = "normal in an octant plane";
    } else if (k % 3 == 2) {
      local = Vec3{0, 0, local.z > 0 ? 1.0 : -1.0}, name = "normal along an octant axis";
    }
    const Vec3 n = c.i.rotation * ((1.0 / norm(local)) * local); // from j towards i
    c.j = place_in_contact(c.i, c.j, n, 0.01 * std::min(size_of(c.i), size_of(c.j)));
    cases.push_back({name, c});
  }
  return cases;
}

TEST(PolySuperquadricContact, SymmetricPiecesGiveTheSuperquadricContact) {
  // r+ = r- in every axis is a plain superquadric: the octant search must find what the
  // superquadric narrow phase finds, to the Newton tolerance (1e-10 of the size).
  std::mt19937_64 rng(31);
  std::vector<PolyCase> poly;
  std::vector<NarrowPhaseResult> plain;
  for (int k = 0; k < 40; ++k) {
    const Vec3 ai = random_extents(rng), aj = random_extents(rng);
    const double n1 = uniform(rng, 2, 6), n2 = uniform(rng, 2, 6);
    PolyCase c;
    c.i = posed_poly(ai, ai, n1, n2, {}, random_rotation(rng));
    c.j = posed_poly(aj, aj, n2, n1, {}, random_rotation(rng));
    c.j = place_in_contact(c.i, c.j, random_unit(rng), 0.01);
    poly.push_back(c);
  }
  const auto results = run_on_device<NarrowPhaseResult>(poly, EvaluatePolyCase{});
  double worst = 0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const NarrowPhaseResult sq = superquadric_pair_contact(
        PosedSuperquadric{octant_shape(poly[k].i.shape, 0), poly[k].i.centre, poly[k].i.rotation},
        PosedSuperquadric{octant_shape(poly[k].j.shape, 0), poly[k].j.centre, poly[k].j.rotation},
        MidwayState{}, NarrowPhaseControls{});
    ASSERT_TRUE(sq.geometry.touching && results[k].geometry.touching);
    EXPECT_EQ(results[k].status, 0);
    const double error = std::fabs(results[k].geometry.overlap - sq.geometry.overlap) / 0.01 +
                         angle_between(results[k].geometry.normal, sq.geometry.normal);
    worst = std::max(worst, error);
  }
  EXPECT_LT(worst, 1e-7);
  std::cout << "[ measured ] symmetric poly vs superquadric: worst relative difference " << worst
            << "\n";
}

TEST(PolySuperquadricContact, RandomPairsMatchBruteForceWithOneAcceptedOctantPair) {
  std::mt19937_64 rng(7);
  const std::vector<NamedCase> cases = random_cases(30, rng);
  std::vector<PolyCase> pairs;
  for (const auto& c : cases)
    pairs.push_back(c.pair);
  const auto results = run_on_device<NarrowPhaseResult>(pairs, EvaluatePolyCase{});
  const auto accepted = run_on_device<AcceptedPairs>(pairs, CountAcceptedPairs{});
  double worst_depth = 0, worst_normal = 0;
  int fallbacks = 0, several = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(cases[k].name + " #" + std::to_string(k));
    const NarrowPhaseResult& r = results[k];
    ASSERT_TRUE(finite_result(r));
    ASSERT_LE(r.status, 1);
    ASSERT_TRUE(r.geometry.touching);
    fallbacks += r.status;
    const Comparison cmp = compare_with_reference(pairs[k], r);
    // As for superquadrics: the chord along any line lies inside both projections (the
    // reference's compass search is good to 1e-11 of the size), and the midway chord and the
    // minimum-translation depth agree to first order in depth / size.
    EXPECT_LT(cmp.chord_excess, 1e-9);
    EXPECT_LT(cmp.depth_error, 3 * cmp.relative_depth);
    EXPECT_LT(cmp.normal_error, 3 * cmp.relative_depth);
    worst_depth = std::max(worst_depth, cmp.depth_error);
    worst_normal = std::max(worst_normal, cmp.normal_error);
    // Every octant pair solved alone: at least one is accepted, and where several are (a point
    // on an octant plane) they give the same point, to the Newton tolerance.
    EXPECT_GE(accepted[k].count, 1);
    EXPECT_LT(accepted[k].spread, 1e-8);
    several += accepted[k].count > 1 ? 1 : 0;
  }
  std::cout << "[ measured ] random poly pairs: worst depth error " << worst_depth
            << ", worst normal error " << worst_normal << " rad, " << fallbacks << " fallbacks, "
            << several << " of " << cases.size() << " with several accepted octant pairs\n";
}

// The book's thin hemisphere (r_x- = r0 / 600): against a sphere-like poly-superquadric, at
// contact angles from the pole (four octants meet) to the rim on the x = 0 plane, where the
// curvature radius changes by five orders of magnitude.
TEST(PolySuperquadricContact, ThinHemisphereFromPoleToRim) {
  const double r0 = 6e-3;
  const PosedPolySuperquadric hemisphere =
      posed_poly({r0, r0, r0}, {r0 / 600, r0, r0}, 2, 2, {}, Quat{1, 0, 0, 0});
  const PosedPolySuperquadric ball =
      posed_poly({2e-3, 2e-3, 2e-3}, {2e-3, 2e-3, 2e-3}, 2, 2, {}, Quat{1, 0, 0, 0});
  std::vector<PolyCase> pairs;
  std::vector<double> angles;
  for (double phi_degrees : {90.0, 60.0, 30.0, 5.0, 1.0, 0.0}) {
    // The ball touches the dome at angle phi from the flat face's plane (x = 0), in the xz plane.
    const double phi = phi_degrees * pi / 180;
    const Vec3 n{std::sin(phi), 0, std::cos(phi)}; // outward from the dome
    PolyCase c;
    c.i = hemisphere;
    c.j = place_in_contact(hemisphere, ball, -1.0 * n, 1e-5);
    if (phi_degrees == 90.0) // exactly on the axis, so that the contact lies on both planes
      c.j.centre = Vec3{r0 + 2e-3 - 1e-5, 0, 0};
    pairs.push_back(c);
    angles.push_back(phi_degrees);
  }
  const auto results = run_on_device<NarrowPhaseResult>(pairs, EvaluatePolyCase{});
  const auto accepted = run_on_device<AcceptedPairs>(pairs, CountAcceptedPairs{});
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    SCOPED_TRACE("phi = " + std::to_string(angles[k]) + " degrees");
    // On the pole four octants of each body meet: each of the 16 pairs accepts the same point.
    EXPECT_GE(accepted[k].count, angles[k] == 90.0 ? 16 : 1);
    EXPECT_LT(accepted[k].spread, 1e-8 * r0);
    const NarrowPhaseResult& r = results[k];
    ASSERT_TRUE(finite_result(r));
    ASSERT_LE(r.status, 1);
    ASSERT_TRUE(r.geometry.touching);
    const Comparison cmp = compare_with_reference(pairs[k], r);
    std::cout << "[ hard case ] hemisphere phi " << angles[k] << ": status " << r.status
              << ", iterations " << r.iterations << ", depth error " << cmp.depth_error
              << ", normal error " << cmp.normal_error << "\n";
    EXPECT_LT(cmp.chord_excess, 1e-9);
    // Depth 1e-5 / 2e-3 of the ball: first-order agreement, 3 x that.
    EXPECT_LT(cmp.depth_error, 3 * cmp.relative_depth + 1e-6);
    EXPECT_LT(cmp.normal_error, 3 * cmp.relative_depth + 1e-6);
  }
}

TEST(PolySuperquadricContact, ThinHemispheresFlatFaceToFlatFace) {
  // The book's hemisphere (cap r0/600) against another, flat face on flat face, laterally offset
  // and slightly turned, from the cold start and from a start a body size away: the contact lies
  // on the caps, pieces 1/600 of the bodies' size thick, whose own Newton (in units of their
  // thickness) could not reach it from there.
  const double r0 = 6e-3, cap = r0 / 600;
  const PosedPolySuperquadric face_up =
      posed_poly({r0, r0, r0}, {cap, r0, r0}, 2, 2, {}, Quat{1, 0, 0, 0});
  std::vector<PolyCase> pairs;
  std::vector<std::string> names;
  for (double offset : {0.0, 0.3, 0.7})
    for (double tilt_degrees : {0.0, 2.0}) {
      // j: the same body turned by 180 degrees about z (its dome towards -x) and tilted about y.
      const double tilt = tilt_degrees * pi / 180;
      const Quat flip{0, 0, 0, 1};
      const Quat turn{std::cos(tilt / 2), 0, std::sin(tilt / 2), 0};
      PosedPolySuperquadric face_down =
          posed_poly({r0, r0, r0}, {cap, r0, r0}, 2, 2, {}, turn * flip);
      const Vec3 n = rotation_matrix(turn) * Vec3{1, 0, 0}; // j's face normal, towards i
      PolyCase c;
      c.i = face_up;
      // Overlapping by 1e-6 where the shifted caps meet (each cap is a thin ellipsoid: at a
      // lateral distance y from its axis it is thinner by the factor sqrt(1 - (y / r0)^2)).
      const double half = 0.5 * offset;
      c.j = place_in_contact(face_up, face_down, n,
                             1e-6 + 2 * cap * (1 - std::sqrt(1 - half * half)));
      c.j.centre += Vec3{0, offset * r0, 0};
      // Tilted, the rim meets the face and the caps' thinning is not what decides: one correction
      // along n to a penetration depth of 1e-6 (the depth changes one for one with it).
      const double depth = penetration_depth(reference_body(c.i), reference_body(c.j), 1e-6).depth;
      c.j.centre += (1e-6 - depth) * n;
      for (bool far_start : {false, true}) {
        c.previous = far_start ? MidwayState{c.i.centre + Vec3{r0, 0, 0}, 1.0} : MidwayState{};
        pairs.push_back(c);
        names.push_back("offset " + std::to_string(offset) + " tilt " +
                        std::to_string(tilt_degrees) + (far_start ? " far start" : " cold"));
      }
    }
  const auto results = run_on_device<NarrowPhaseResult>(pairs, EvaluatePolyCase{});
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    SCOPED_TRACE(names[k]);
    const NarrowPhaseResult& r = results[k];
    ASSERT_TRUE(finite_result(r));
    ASSERT_LE(r.status, 1);
    ASSERT_TRUE(r.geometry.touching);
    if (k % 2 == 1) { // the far start ends where the cold start did (the midway point is unique)
      EXPECT_NEAR(r.geometry.overlap, results[k - 1].geometry.overlap, 1e-9 * r0);
      EXPECT_LT(norm(r.state.point - results[k - 1].state.point), 1e-9 * r0);
      continue;
    }
    const Comparison cmp = compare_with_reference(pairs[k], r);
    std::cout << "[ hard case ] flat faces " << names[k] << ": status " << r.status
              << ", iterations " << r.iterations << ", depth error " << cmp.depth_error
              << ", normal error " << cmp.normal_error << "\n";
    EXPECT_LT(cmp.chord_excess, 1e-9);
    EXPECT_LT(cmp.normal_error, 1e-4);
    // Face on face the overlap is the penetration depth (measured 1e-15 to 6e-10). Tilted, the
    // cap's rim (curvature radius r_x-^2 / r0 = 1.7e-8 m) digs into the other face, and the
    // midway chord is 0.64 of the depth: the cap's shape function grows by ~0.1 over the
    // micrometre of overlap, so its level set through the midway point is the cap shrunk by a
    // few per cent, whose rim lies off the deepest point, and the chord is taken there. A property
    // of the midway-point overlap for pieces this thin, not of convergence (the normal is right).
    EXPECT_LT(cmp.depth_error, names[k].find("tilt 0") != std::string::npos ? 1e-6 : 0.4);
  }
}

TEST(PolySuperquadricContact, PoorStartsConverge) {
  // Starts far from the contact (at a body's origin, or beyond the other body, with a wrong
  // multiplier) must still end at the contact: the walk, or the cold fallback; never missed.
  std::mt19937_64 rng(11);
  std::vector<NamedCase> cases = random_cases(30, rng);
  std::vector<PolyCase> pairs;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    PolyCase c = cases[k].pair;
    c.previous = MidwayState{k % 2 ? c.i.centre : 2.0 * c.j.centre - c.i.centre, 5.0};
    pairs.push_back(c);
  }
  const auto results = run_on_device<NarrowPhaseResult>(pairs, EvaluatePolyCase{});
  for (auto& c : pairs)
    c.previous = MidwayState{};
  const auto cold = run_on_device<NarrowPhaseResult>(pairs, EvaluatePolyCase{});
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    SCOPED_TRACE(cases[k].name + " #" + std::to_string(k));
    ASSERT_LE(results[k].status, 1);
    ASSERT_TRUE(results[k].geometry.touching);
    // The contact is unique: the same overlap as from the cold start, to the tolerance.
    EXPECT_NEAR(results[k].geometry.overlap, cold[k].geometry.overlap, 1e-9);
  }
}

// A pair moving through a sequence of poses, each solved from the last state: the contact stays
// found, and once warm a step costs one element solve of few iterations.
struct MovingPair {
  PolyCase poses[40];
};

struct SolveMovingPair {
  KOKKOS_INLINE_FUNCTION NarrowPhaseTally operator()(const MovingPair& m) const {
    NarrowPhaseTally tally;
    MidwayState state;
    for (const PolyCase& c : m.poses) {
      const NarrowPhaseResult r = piecewise_pair_contact(c.i, c.j, state, c.controls);
      if (!r.geometry.touching)
        tally.failures += 1; // every pose is in contact
      tally.add(r);
      state = r.state;
    }
    return tally;
  }
};

TEST(PolySuperquadricContact, WarmStartsFollowPairsRollingAcrossOctantPlanes) {
  std::mt19937_64 rng(5);
  std::vector<MovingPair> moving(12);
  for (MovingPair& m : moving) {
    const PosedPolySuperquadric i0 = random_poly(rng, {}), j0 = random_poly(rng, {});
    const Vec3 axis_i = random_unit(rng), axis_j = random_unit(rng);
    const Vec3 n = random_unit(rng);
    for (int p = 0; p < 40; ++p) {
      // Each body turns by 90 degrees over the sequence, so the contact crosses octant planes.
      PolyCase& c = m.poses[p];
      c.i = i0, c.j = j0;
      c.i.rotation = rotation_matrix(axis_angle_by_rotation_vector(axis_i, 0.04 * p)) * i0.rotation;
      c.j.rotation = rotation_matrix(axis_angle_by_rotation_vector(axis_j, 0.04 * p)) * j0.rotation;
      c.j = place_in_contact(c.i, c.j, n, 0.01 * std::min(size_of(c.i), size_of(c.j)));
    }
  }
  const auto tallies = run_on_device<NarrowPhaseTally>(moving, SolveMovingPair{});
  NarrowPhaseTally total;
  for (const auto& t : tallies)
    total += t;
  EXPECT_EQ(total.failures, 0);
  // Measured 3.2 Newton iterations per evaluation (every element solve of the walk counted).
  const double per_evaluation = double(total.iterations) / double(total.evaluations);
  EXPECT_LT(per_evaluation, 6.0);
  std::cout << "[ measured ] moving poly pairs: " << per_evaluation
            << " Newton iterations per evaluation, " << total.fallbacks << " fallbacks in "
            << total.evaluations << "\n";
}

// ------------------------------------------------------------------ sphere against a poly

struct SphereCase {
  Vec3 centre;
  double radius = 0;
  PosedPolySuperquadric body;
  MidwayState previous;
};

struct EvaluateSphereCase {
  KOKKOS_INLINE_FUNCTION NarrowPhaseResult operator()(const SphereCase& c) const {
    return sphere_poly_superquadric_contact(c.centre, c.radius, c.body, c.previous,
                                            NarrowPhaseControls{});
  }
};

TEST(PolySuperquadricContact, SphereOverlapIsRadiusMinusDistanceToTheSurface) {
  // Reference: the sphere touching the body's support plane along -n (exact for a sphere: the
  // closest point to its centre is the support point when the centre lies on the normal line).
  std::mt19937_64 rng(3);
  std::vector<SphereCase> cases;
  std::vector<double> expected;
  for (int k = 0; k < 60; ++k) {
    SphereCase c;
    c.body = random_poly(rng, {0.2, 0.1, -0.3});
    Vec3 local = random_unit(rng);
    if (k % 3 == 1)
      local = Vec3{0, local.y, local.z}; // on an octant plane
    if (k % 3 == 2)
      local = Vec3{0, 0, -1};                                       // on an octant axis
    const Vec3 n = c.body.rotation * ((1.0 / norm(local)) * local); // outward from the body
    const Support touch = reference_body(c.body).support(n);
    c.radius = uniform(rng, 0.05, 2.0);
    const double overlap = 0.01 * c.radius;
    c.centre = touch.point + (c.radius - overlap) * n;
    cases.push_back(c);
    expected.push_back(overlap);
  }
  const auto results = run_on_device<NarrowPhaseResult>(cases, EvaluateSphereCase{});
  double worst = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(k);
    ASSERT_TRUE(finite_result(results[k]));
    ASSERT_LE(results[k].status, 1);
    ASSERT_TRUE(results[k].geometry.touching);
    // The reference support point is good to 1e-11 of the size (compass search).
    const double error = std::fabs(results[k].geometry.overlap - expected[k]) / expected[k];
    EXPECT_LT(error, 1e-6);
    worst = std::max(worst, error);
  }
  std::cout << "[ measured ] sphere against poly: worst relative overlap error " << worst << "\n";
}

// ------------------------------------------------------------------ walls

struct PlaneCase {
  PosedPolySuperquadric body;
  Vec3 point, normal;
};

struct EvaluatePlaneCase {
  KOKKOS_INLINE_FUNCTION SurfaceWallContact operator()(const PlaneCase& c) const {
    return surface_plane_contact(c.body, c.point, c.normal);
  }
};

TEST(PolySuperquadricContact, PlaneDepthIsTheSupportAlongTheInwardNormal) {
  // Against a plane the overlap is how far the body reaches beyond it: its support along -n
  // (reference: radial samples and compass search), including the hemisphere landing on its
  // pole, where four octants meet at the deepest point.
  std::mt19937_64 rng(17);
  std::vector<PlaneCase> cases;
  cases.push_back({posed_poly({6, 6, 6}, {0.01, 6, 6}, 2, 2, {0, 0, 5.99},
                              axis_angle_by_rotation_vector({0, 1, 0}, pi / 2)),
                   {0, 0, 0},
                   {0, 0, 1}});
  for (int k = 0; k < 40; ++k)
    cases.push_back({random_poly(rng, {0, 0, uniform(rng, 0.3, 1.0)}), {0, 0, 0}, {0, 0, 1}});
  const auto results = run_on_device<SurfaceWallContact>(cases, EvaluatePlaneCase{});
  for (std::size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(k);
    const Support deepest = reference_body(cases[k].body).support({0, 0, -1});
    const double depth = deepest.value; // how far below z = 0 the body reaches
    if (depth <= 0) {
      EXPECT_FALSE(results[k].geometry.touching);
      continue;
    }
    ASSERT_TRUE(results[k].geometry.touching);
    EXPECT_NEAR(results[k].geometry.overlap, depth, 1e-9 * size_of(cases[k].body));
    EXPECT_NEAR(results[k].geometry.normal.z, 1.0, 1e-12);
  }
  EXPECT_NEAR(results[0].geometry.overlap, 0.01, 1e-12); // the pole, exactly
}

} // namespace
} // namespace kdem
