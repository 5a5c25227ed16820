// Superquadric narrow phase: the 4 x 4 solve, the sphere limit, brute-force references
// (convex_reference.hpp) and the hard cases. The solves run in parallel_for on the backend under
// test; references run on the host.
#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <random>
#include <vector>

#include "shapes/small_solve.hpp"
#include "shapes/superquadric_contact.hpp"

#include "convex_reference.hpp"
#include "geometry_test_support.hpp"

#include <KokkosBatched_LU_Decl.hpp>
#include <KokkosBatched_LU_Serial_Impl.hpp>
#include <KokkosBatched_Trsv_Decl.hpp>
#include <KokkosBatched_Trsv_Serial_Impl.hpp>

namespace kdem {
namespace {

using namespace testing;

// ------------------------------------------------------------------ device runs

struct PairCase {
  PosedSuperquadric i, j;
  MidwayState previous;
  NarrowPhaseControls controls;
  bool sphere_i = false; // i is the sphere (i.centre, radius i.shape.a) of the sphere path
};

KOKKOS_INLINE_FUNCTION NarrowPhaseResult evaluate_case(const PairCase& c,
                                                       const MidwayState& previous) {
  if (c.sphere_i)
    return sphere_superquadric_contact(c.i.centre, c.i.shape.a, c.j, previous, c.controls);
  return superquadric_pair_contact(c.i, c.j, previous, c.controls);
}

struct EvaluatePairCase {
  KOKKOS_INLINE_FUNCTION NarrowPhaseResult operator()(const PairCase& c) const {
    return evaluate_case(c, c.previous);
  }
};

std::vector<NarrowPhaseResult> run_cases(const std::vector<PairCase>& cases) {
  return run_on_device<NarrowPhaseResult>(cases, EvaluatePairCase{});
}

// Sequences of poses evaluated in order, each with the previous pose's state when warm.
std::vector<std::vector<NarrowPhaseResult>>
run_sequences(const std::vector<std::vector<PairCase>>& sequences, bool warm) {
  const int count = int(sequences.size()), poses = int(sequences[0].size());
  Kokkos::View<PairCase**, MemSpace> device_cases("sequence_cases", count, poses);
  Kokkos::View<NarrowPhaseResult**, MemSpace> device_results("sequence_results", count, poses);
  auto host_cases = Kokkos::create_mirror_view(device_cases);
  for (int s = 0; s < count; ++s)
    for (int p = 0; p < poses; ++p)
      host_cases(s, p) = sequences[s][p];
  Kokkos::deep_copy(device_cases, host_cases);
  Kokkos::parallel_for(
      "pair_sequences", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(int s) {
        MidwayState state;
        for (int p = 0; p < poses; ++p) {
          const NarrowPhaseResult r =
              evaluate_case(device_cases(s, p), warm ? state : MidwayState{});
          device_results(s, p) = r;
          state = r.status == 2 ? MidwayState{} : r.state;
        }
      });
  auto host_results = Kokkos::create_mirror_view(device_results);
  Kokkos::deep_copy(host_results, device_results);
  std::vector<std::vector<NarrowPhaseResult>> out(count);
  for (int s = 0; s < count; ++s)
    for (int p = 0; p < poses; ++p)
      out[s].push_back(host_results(s, p));
  return out;
}

// ------------------------------------------------------------------ brute-force reference

// ------------------------------------------------------------------ scenes

PosedSuperquadric posed(double a, double b, double c, double n1, double n2, Vec3 centre, Quat q) {
  return pose_superquadric(make_superquadric(a, b, c, n1, n2), centre, q);
}

double size_of_pair(const PosedSuperquadric& i, const PosedSuperquadric& j) {
  return std::min(std::cbrt(i.shape.a * i.shape.b * i.shape.c),
                  std::cbrt(j.shape.a * j.shape.b * j.shape.c));
}

// Places j (its centre moved) so that the projections of i and j on the unit normal n (from j
// towards i) overlap by `overlap`: j's extreme point along n meets i's extreme point along -n,
// then j moves by `overlap` towards i. For small overlaps this is the contact normal and depth.
PosedSuperquadric place_in_contact(const PosedSuperquadric& i, PosedSuperquadric j, Vec3 n,
                                   double overlap) {
  const Vec3 touch_i = BruteForceBody(i).support(-n).point;
  j.centre = Vec3{0, 0, 0};
  const Vec3 touch_j = BruteForceBody(j).support(n).point;
  j.centre = touch_i - touch_j + overlap * n;
  return j;
}

PairCase pair_case(const PosedSuperquadric& i, const PosedSuperquadric& j) {
  PairCase c;
  c.i = i, c.j = j;
  return c;
}

struct Comparison {
  double depth_error = 0;  // |overlap - reference depth| / reference depth
  double normal_error = 0; // rad, against the reference normal
  double chord_excess = 0; // overlap - projected overlap along the found normal, / size
  double reference_depth = 0;
};

Comparison compare_with_reference(const PairCase& c, const NarrowPhaseResult& r) {
  const BruteForceBody bi(c.i), bj(c.j);
  const Penetration ref = penetration_depth(bi, bj);
  Comparison out;
  out.reference_depth = ref.depth;
  out.depth_error = std::fabs(r.geometry.overlap - ref.depth) / ref.depth;
  out.normal_error = angle_between(r.geometry.normal, ref.normal);
  out.chord_excess =
      (r.geometry.overlap - projected_overlap(bi, bj, r.geometry.normal)) / size_of_pair(c.i, c.j);
  return out;
}

void print_histogram(const std::string& title, const std::vector<NarrowPhaseResult>& results) {
  std::map<int, int> counts;
  int fallbacks = 0, failures = 0;
  for (const auto& r : results) {
    ++counts[r.iterations];
    fallbacks += r.status == 1;
    failures += r.status == 2;
  }
  std::cout << "[ histogram ] " << title << " (" << results.size() << " pairs, " << fallbacks
            << " through the fallback, " << failures << " failed): iterations:count";
  for (const auto& [iterations, count] : counts)
    std::cout << " " << iterations << ":" << count;
  std::cout << "\n";
}

// ------------------------------------------------------------------ 4 x 4 solve

// Solves a batch with solve_4x4 and with KokkosBatched (LU without pivoting + two Trsv).
void solve_both_ways(const std::vector<Matrix4>& matrices, const std::vector<Vector4>& rhs,
                     std::vector<Vector4>& ours, std::vector<Vector4>& batched) {
  const int n = int(matrices.size());
  Kokkos::View<double* [4][4], MemSpace> a("a", n);
  Kokkos::View<double*[4], MemSpace> b("b", n), x("x", n);
  Kokkos::View<int*, MemSpace> ok("ok", n);
  auto ha = Kokkos::create_mirror_view(a);
  auto hb = Kokkos::create_mirror_view(b);
  for (int k = 0; k < n; ++k)
    for (int r = 0; r < 4; ++r) {
      hb(k, r) = rhs[k].v[r];
      for (int c = 0; c < 4; ++c)
        ha(k, r, c) = matrices[k].m[r][c];
    }
  Kokkos::deep_copy(a, ha);
  Kokkos::deep_copy(b, hb);
  Kokkos::parallel_for(
      "solve_4x4", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int k) {
        Matrix4 m;
        Vector4 v, solution;
        for (int r = 0; r < 4; ++r) {
          v.v[r] = b(k, r);
          for (int c = 0; c < 4; ++c)
            m.m[r][c] = a(k, r, c);
        }
        ok(k) = solve_4x4(m, v, solution);
        for (int r = 0; r < 4; ++r)
          x(k, r) = solution.v[r];
        auto ak = Kokkos::subview(a, k, Kokkos::ALL(), Kokkos::ALL());
        auto bk = Kokkos::subview(b, k, Kokkos::ALL());
        using namespace KokkosBatched;
        SerialLU<Algo::LU::Unblocked>::invoke(ak);
        SerialTrsv<Uplo::Lower, Trans::NoTranspose, Diag::Unit, Algo::Trsv::Unblocked>::invoke(
            1.0, ak, bk);
        SerialTrsv<Uplo::Upper, Trans::NoTranspose, Diag::NonUnit, Algo::Trsv::Unblocked>::invoke(
            1.0, ak, bk);
      });
  auto hx = Kokkos::create_mirror_view(x);
  auto hok = Kokkos::create_mirror_view(ok);
  Kokkos::deep_copy(hx, x);
  Kokkos::deep_copy(hb, b);
  Kokkos::deep_copy(hok, ok);
  ours.assign(n, Vector4{});
  batched.assign(n, Vector4{});
  for (int k = 0; k < n; ++k) {
    EXPECT_TRUE(hok(k)) << k;
    for (int r = 0; r < 4; ++r)
      ours[k].v[r] = hx(k, r), batched[k].v[r] = hb(k, r);
  }
}

double max_difference(const Vector4& x, const Vector4& y) {
  double d = 0;
  for (int r = 0; r < 4; ++r)
    d = std::max(d, std::fabs(x.v[r] - y.v[r]));
  return d;
}

TEST(SuperquadricContact, SolveMatchesKokkosBatched) {
  std::mt19937_64 rng(7);
  std::vector<Matrix4> matrices;
  std::vector<Vector4> rhs;
  for (int k = 0; k < 200; ++k) {
    Matrix4 m;
    Vector4 b;
    for (int r = 0; r < 4; ++r) {
      b.v[r] = uniform(rng, -1, 1);
      for (int c = 0; c < 4; ++c)
        m.m[r][c] = uniform(rng, -1, 1) + (r == c ? 5.0 : 0.0); // diagonally dominant
    }
    matrices.push_back(m);
    rhs.push_back(b);
  }
  std::vector<Vector4> ours, batched;
  solve_both_ways(matrices, rhs, ours, batched);
  double worst = 0;
  for (int k = 0; k < 200; ++k)
    worst = std::max(worst, max_difference(ours[k], batched[k]));
  // Diagonally dominant (condition number below about 3): both solutions are within a few
  // n eps of the exact one, |x| < 1.
  EXPECT_LT(worst, 1e-14);
  std::cout << "[ measured ] solve_4x4 vs KokkosBatched, worst difference " << worst << "\n";
}

TEST(SuperquadricContact, SolvePivotsBadlyScaledMatrices) {
  // A tiny leading pivot: without row exchanges the multiplier 1e14 destroys the solution.
  Matrix4 m{{{1e-14, 1, 2, 0}, {1, 1, 0, 1}, {0, 3, 1, 1}, {2, 0, 1, 4}}};
  const Vector4 exact{{1, -2, 3, 0.5}};
  Vector4 b;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      b.v[r] += m.m[r][c] * exact.v[c];
  Vector4 x;
  ASSERT_TRUE(solve_4x4(m, b, x));
  EXPECT_LT(max_difference(x, exact), 1e-14); // condition number about 10: a few n eps
  std::vector<Vector4> ours, batched;
  solve_both_ways({m}, {b}, ours, batched);
  EXPECT_LT(max_difference(ours[0], exact), 1e-14);   // the same on the device
  EXPECT_GT(max_difference(batched[0], exact), 1e-6); // the non-pivoting solve loses it
  std::cout << "[ measured ] badly scaled: pivoted error " << max_difference(ours[0], exact)
            << ", unpivoted error " << max_difference(batched[0], exact) << "\n";
  // Rows of very different scale are fine with partial pivoting too.
  Matrix4 scaled = m;
  for (int c = 0; c < 4; ++c)
    scaled.m[2][c] *= 1e8;
  Vector4 scaled_b = b;
  scaled_b.v[2] *= 1e8;
  ASSERT_TRUE(solve_4x4(scaled, scaled_b, x));
  EXPECT_LT(max_difference(x, exact), 1e-13); // the row scale enters the error bound ~ 1e-15 * 10

  Matrix4 singular = m; // row 3 = row 0 + row 1
  for (int c = 0; c < 4; ++c)
    singular.m[3][c] = m.m[0][c] + m.m[1][c];
  EXPECT_FALSE(solve_4x4(singular, b, x));
  EXPECT_EQ(max_difference(x, Vector4{}), 0.0);
  Matrix4 with_nan = m;
  with_nan.m[1][2] = std::nan("");
  EXPECT_FALSE(solve_4x4(with_nan, b, x));
  EXPECT_FALSE(solve_4x4(Matrix4{}, b, x));
}

// ------------------------------------------------------------------ sphere limit

TEST(SuperquadricContact, SpheresGiveTheSphereSphereGeometry) {
  std::mt19937_64 rng(11);
  std::vector<PairCase> cases;
  std::vector<ContactGeometry> exact;
  for (int k = 0; k < 200; ++k) {
    const double ri = uniform(rng, 0.2, 2.0), rj = uniform(rng, 0.2, 2.0);
    const Vec3 xi{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
    const double gap = k < 180 ? -uniform(rng, 1e-6, 0.2) * std::min(ri, rj) : 0.05;
    const Vec3 xj = xi + (ri + rj + gap) * random_unit(rng);
    cases.push_back(pair_case(posed(ri, ri, ri, 2, 2, xi, random_rotation(rng)),
                              posed(rj, rj, rj, 2, 2, xj, random_rotation(rng))));
    exact.push_back(sphere_sphere(xi, ri, xj, rj));
  }
  const std::vector<NarrowPhaseResult> results = run_cases(cases);
  double worst_overlap = 0, worst_normal = 0, worst_point = 0;
  for (int k = 0; k < 200; ++k) {
    const NarrowPhaseResult& r = results[k];
    ASSERT_EQ(r.status, 0) << k;
    ASSERT_EQ(r.geometry.touching, exact[k].touching) << k;
    if (!exact[k].touching)
      continue;
    const double ri = cases[k].i.shape.a, rj = cases[k].j.shape.a;
    worst_overlap = std::max(worst_overlap, std::fabs(r.geometry.overlap - exact[k].overlap));
    worst_normal = std::max(worst_normal, norm(r.geometry.normal - exact[k].normal));
    worst_point = std::max(worst_point, norm(r.geometry.point - exact[k].point));
    EXPECT_NEAR(r.curvature_i, 1 / ri, 1e-9 / ri); // Goldman's formula at a root to ~1e-14
    EXPECT_NEAR(r.curvature_j, 1 / rj, 1e-9 / rj);
  }
  // The sphere start is the exact midway point: only the surface-point roots (to ~4 eps of the
  // bounding length, a few 1e-15 m here) separate the result from the closed form.
  EXPECT_LT(worst_overlap, 1e-13);
  EXPECT_LT(worst_normal, 1e-13);
  EXPECT_LT(worst_point, 1e-13);
  std::cout << "[ measured ] spheres: worst overlap " << worst_overlap << " m, normal "
            << worst_normal << ", point " << worst_point << " m\n";
}

// ------------------------------------------------------------------ brute-force comparisons

struct NamedCase {
  std::string name;
  PairCase pair;
  double design_overlap;  // projected overlap along the design normal
  bool symmetric = false; // mirror symmetry puts the midway line on the reference normal
};

// Random shapes and orientations placed with a given projected overlap along a random normal.
NamedCase random_contact(std::mt19937_64& rng, double n_lo, double n_hi, double aspect_lo,
                         double aspect_hi, double relative_overlap, const std::string& name) {
  const auto axis = [&] { return log_uniform(rng, aspect_lo, aspect_hi); };
  const PosedSuperquadric i =
      posed(1, axis(), axis(), uniform(rng, n_lo, n_hi), uniform(rng, n_lo, n_hi), {0.1, -0.2, 0.3},
            random_rotation(rng));
  PosedSuperquadric j = posed(1, axis(), axis(), uniform(rng, n_lo, n_hi), uniform(rng, n_lo, n_hi),
                              {0, 0, 0}, random_rotation(rng));
  const double overlap = relative_overlap * size_of_pair(i, j);
  j = place_in_contact(i, j, random_unit(rng), overlap);
  return {name, pair_case(i, j), overlap};
}

std::vector<NamedCase> hard_cases() {
  std::vector<NamedCase> cases;
  std::mt19937_64 rng(2024);
  const Vec3 z{0, 0, 1};
  const auto add = [&](const std::string& name, const PosedSuperquadric& i,
                       const PosedSuperquadric& j, Vec3 n, double relative_overlap) {
    const double overlap = relative_overlap * size_of_pair(i, j);
    const bool symmetric =
        name.find("on face") != std::string::npos || name.find("on edge") != std::string::npos;
    cases.push_back({name, pair_case(i, place_in_contact(i, j, n, overlap)), overlap, symmetric});
  };
  for (double n : {2.0, 4.0, 6.0, 8.0, 10.0})
    for (int k = 0; k < 3; ++k)
      add("blockiness n=" + std::to_string(int(n)),
          posed(1, 0.8, 0.6, n, n, {0, 0, 0}, random_rotation(rng)),
          posed(0.7, 1, 0.9, n, n, {}, random_rotation(rng)), random_unit(rng), 0.01);
  for (double aspect : {0.2, 0.5, 2.0, 5.0})
    for (double n : {2.0, 4.0})
      add("aspect " + std::to_string(aspect) + " n=" + std::to_string(int(n)),
          posed(1, 1, aspect, n, 2, {}, random_rotation(rng)),
          posed(1, aspect, 1, 2, n, {}, random_rotation(rng)), random_unit(rng), 0.01);
  for (double n : {2.0, 4.0, 8.0}) {
    add("size ratio 10 n=" + std::to_string(int(n)), posed(1, 1, 1, n, n, {}, random_rotation(rng)),
        posed(0.1, 0.1, 0.1, n, n, {}, random_rotation(rng)), random_unit(rng), 0.01);
    add("size ratio 10 reversed n=" + std::to_string(int(n)),
        posed(0.1, 0.08, 0.12, n, n, {}, random_rotation(rng)),
        posed(1, 1, 1, n, n, {}, random_rotation(rng)), random_unit(rng), 0.01);
  }
  const Quat identity{1, 0, 0, 0};
  for (double n : {4.0, 8.0, 10.0}) {
    const std::string tag = " n=" + std::to_string(int(n));
    add("cubes face on face" + tag, posed(1, 1, 1, n, n, {}, identity),
        posed(1, 1, 1, n, n, {}, identity), z, 0.01);
    PairCase shifted = pair_case(posed(1, 1, 1, n, n, {}, identity),
                                 posed(1, 1, 1, n, n, {0.3, -0.2, -1.99}, identity));
    cases.push_back({"cubes face on face offset" + tag, shifted, 0.01}); // point symmetric only
    add("cubes edge on edge" + tag,
        posed(1, 1, 1, n, n, {}, axis_angle_by_rotation_vector({1, 0, 0}, pi / 4)),
        posed(1, 1, 1, n, n, {}, axis_angle_by_rotation_vector({0, 1, 0}, pi / 4)), z, 0.01);
    const Quat corner_down = axis_angle_by_rotation_vector(cross(Vec3{1, 1, 1}, Vec3{0, 0, 1}),
                                                           std::acos(1 / std::sqrt(3.0)));
    add("cube corner on face" + tag, posed(1, 1, 1, n, n, {}, corner_down),
        posed(1, 1, 1, n, n, {}, identity), z, 0.01);
    add("cubes nearly parallel faces" + tag, posed(1, 1, 1, n, n, {}, identity),
        posed(1, 1, 1, n, n, {}, axis_angle_by_rotation_vector({1, 0.3, 0}, 0.01)), z, 0.01);
    add("cubes grazing" + tag,
        posed(1, 1, 1, n, n, {}, axis_angle_by_rotation_vector({0.2, 1, 0}, 0.3)),
        posed(1, 1, 1, n, n, {}, axis_angle_by_rotation_vector({1, 0, 0.4}, 0.2)), z, 1e-6);
    add("cubes deep" + tag,
        posed(1, 1, 1, n, n, {}, axis_angle_by_rotation_vector({0.2, 1, 0}, 0.3)),
        posed(1, 1, 1, n, n, {}, axis_angle_by_rotation_vector({1, 0, 0.4}, 0.2)), z, 0.1);
  }
  for (int k = 0; k < 4; ++k) {
    cases.push_back(random_contact(rng, 2, 10, 0.3, 3, 1e-6, "random grazing"));
    cases.push_back(random_contact(rng, 2, 10, 0.3, 3, 0.1, "random deep"));
    cases.push_back(random_contact(rng, 2, 2, 0.2, 5, 0.1, "ellipsoids deep"));
  }
  return cases;
}

TEST(SuperquadricContact, HardCasesMatchBruteForce) {
  const std::vector<NamedCase> cases = hard_cases();
  std::vector<PairCase> pairs;
  for (const auto& c : cases)
    pairs.push_back(c.pair);
  const std::vector<NarrowPhaseResult> results = run_cases(pairs);
  double worst_depth = 0, worst_normal = 0, worst_grazing = 0;
  for (int k = 0; k < int(cases.size()); ++k) {
    const NarrowPhaseResult& r = results[k];
    SCOPED_TRACE(cases[k].name);
    ASSERT_TRUE(finite_result(r));
    ASSERT_LE(r.status, 1);
    ASSERT_TRUE(r.geometry.touching);
    const Comparison cmp = compare_with_reference(cases[k].pair, r);
    const double relative = cmp.reference_depth / size_of_pair(cases[k].pair.i, cases[k].pair.j);
    std::cout << "[ hard case ] " << cases[k].name << ": status " << r.status << ", iterations "
              << r.iterations << ", depth/size " << relative << ", depth error " << cmp.depth_error
              << ", normal error " << cmp.normal_error << " rad, chord excess " << cmp.chord_excess
              << "\n";
    // The chord along any line is inside both projections: bounded by the reference up to its
    // own accuracy (compass search to 1e-11 of the body size).
    EXPECT_LT(cmp.chord_excess, 1e-9);
    if (cases[k].symmetric) {
      // Faces, edges and corners met symmetrically: both methods give the same line, exact up
      // to the Newton tolerance and the reference's compass search (1e-9 in the direction).
      EXPECT_LT(cmp.depth_error, 1e-8);
      EXPECT_LT(cmp.normal_error, 1e-8);
    }
    // The midway chord and the minimum-translation depth agree to first order in depth/size;
    // the difference grows with curvature times depth (worst measured ratio 1.2, aspect 5).
    EXPECT_LT(cmp.depth_error, 3 * relative);
    EXPECT_LT(cmp.normal_error, 3 * relative);
    worst_depth = std::max(worst_depth, cmp.depth_error);
    worst_normal = std::max(worst_normal, cmp.normal_error);
    if (relative < 1e-5)
      worst_grazing = std::max(worst_grazing, cmp.depth_error);
  }
  std::cout << "[ measured ] hard cases: worst depth error " << worst_depth
            << ", worst normal error " << worst_normal << " rad, worst grazing depth error "
            << worst_grazing << "\n";
}

TEST(SuperquadricContact, BlockinessSixteenIsReported) {
  std::mt19937_64 rng(16);
  std::vector<NamedCase> cases;
  for (int k = 0; k < 20; ++k)
    cases.push_back(random_contact(rng, 16, 16, 0.5, 2, k < 10 ? 0.01 : 1e-6, "n=16"));
  std::vector<PairCase> pairs;
  for (const auto& c : cases)
    pairs.push_back(c.pair);
  const std::vector<NarrowPhaseResult> results = run_cases(pairs);
  print_histogram("n = 16", results);
  double worst_depth = 0, worst_normal = 0;
  for (int k = 0; k < int(cases.size()); ++k) {
    ASSERT_TRUE(finite_result(results[k]));
    if (results[k].status == 2)
      continue; // counted in the histogram line
    const Comparison cmp = compare_with_reference(cases[k].pair, results[k]);
    EXPECT_LT(cmp.chord_excess, 1e-9); // rigorous bound, as in HardCasesMatchBruteForce
    worst_depth = std::max(worst_depth, cmp.depth_error);
    worst_normal = std::max(worst_normal, cmp.normal_error);
  }
  std::cout << "[ measured ] n = 16: worst depth error " << worst_depth << ", normal error "
            << worst_normal << " rad\n";
}

// j moves past i on a straight line while both spin: the pair enters contact, overlaps by up to
// about 5 % of the size and leaves, in 200 steps, as in a simulation.
std::vector<std::vector<PairCase>> moving_sequences(int count, int poses) {
  std::mt19937_64 rng(99);
  std::vector<std::vector<PairCase>> sequences;
  for (int s = 0; s < count; ++s) {
    const double n = uniform(rng, 2, 10);
    const SuperquadricShape si =
        make_superquadric(1, uniform(rng, 0.5, 1), uniform(rng, 0.5, 1.5), n, uniform(rng, 2, 10));
    const SuperquadricShape sj =
        make_superquadric(uniform(rng, 0.4, 1), 0.7, uniform(rng, 0.5, 2), uniform(rng, 2, 10), n);
    const Quat qi = random_rotation(rng), qj = random_rotation(rng);
    const Vec3 spin_i = 0.5 * random_unit(rng), spin_j = 0.8 * random_unit(rng);
    const Vec3 direction = random_unit(rng);
    const Vec3 offset = random_unit_perpendicular(rng, direction);
    std::vector<PairCase> sequence;
    for (int p = 0; p < poses; ++p) {
      const double t = double(p) / (poses - 1);
      const Vec3 centre_j = (1.6 * offset) + (4.0 * (t - 0.5)) * direction;
      PairCase c = pair_case(
          pose_superquadric(si, {}, normalized(quat_from_rotation_vector(t * spin_i) * qi)),
          pose_superquadric(sj, centre_j, normalized(quat_from_rotation_vector(t * spin_j) * qj)));
      sequence.push_back(c);
    }
    sequences.push_back(sequence);
  }
  return sequences;
}

TEST(SuperquadricContact, WarmStartFollowsMovingPairs) {
  const auto sequences = moving_sequences(24, 200);
  const auto cold = run_sequences(sequences, false);
  const auto warm = run_sequences(sequences, true);
  std::vector<NarrowPhaseResult> all_cold, all_warm;
  long cold_iterations = 0, warm_iterations = 0;
  int touching = 0;
  for (int s = 0; s < int(sequences.size()); ++s)
    for (int p = 0; p < int(sequences[s].size()); ++p) {
      const NarrowPhaseResult &c = cold[s][p], &w = warm[s][p];
      ASSERT_TRUE(finite_result(c) && finite_result(w));
      ASSERT_LE(c.status, 1);
      ASSERT_LE(w.status, 1);
      all_cold.push_back(c), all_warm.push_back(w);
      cold_iterations += c.iterations, warm_iterations += w.iterations;
      ASSERT_EQ(c.geometry.touching, w.geometry.touching) << s << " " << p;
      if (!c.geometry.touching)
        continue;
      ++touching;
      // One midway point solves Eq. 2.9 (the level sets are convex): both starts reach it, to
      // the Newton tolerance 1e-10 amplified by the chord's sensitivity (below 1e3 here).
      EXPECT_NEAR(w.geometry.overlap, c.geometry.overlap, 1e-7);
      EXPECT_LT(norm(w.geometry.normal - c.geometry.normal), 1e-7);
    }
  print_histogram("moving pairs, cold start", all_cold);
  print_histogram("moving pairs, warm start", all_warm);
  std::cout << "[ measured ] moving pairs: " << touching << " touching poses; mean iterations "
            << double(cold_iterations) / all_cold.size() << " cold, "
            << double(warm_iterations) / all_warm.size() << " warm\n";
  EXPECT_GT(touching, 500);
  EXPECT_LT(warm_iterations, cold_iterations / 2); // consecutive poses are close
}

TEST(SuperquadricContact, RandomPairsConvergeAndTheFallbackRecoversFailures) {
  std::mt19937_64 rng(5);
  std::vector<NamedCase> cases;
  for (int k = 0; k < 3000; ++k) {
    const double overlap = log_uniform(rng, 1e-6, 0.1);
    NamedCase c = random_contact(rng, 2, 10, 0.2, 5, overlap, "random");
    if (k % 3 == 0) { // size ratio up to 10
      const double scale = uniform(rng, 0.1, 1);
      PosedSuperquadric j = c.pair.j;
      j.shape = make_superquadric(scale * j.shape.a, scale * j.shape.b, scale * j.shape.c,
                                  j.shape.n1, j.shape.n2);
      const Vec3 n = random_unit(rng);
      c.design_overlap = overlap * size_of_pair(c.pair.i, j);
      c.pair.j = place_in_contact(c.pair.i, j, n, c.design_overlap);
    }
    cases.push_back(c);
  }
  std::vector<PairCase> plain, with_fallback;
  for (const auto& c : cases) {
    PairCase p = c.pair;
    p.controls.use_fallback = false;
    plain.push_back(p);
    with_fallback.push_back(c.pair);
  }
  const std::vector<NarrowPhaseResult> plain_results = run_cases(plain);
  const std::vector<NarrowPhaseResult> results = run_cases(with_fallback);
  print_histogram("random pairs, plain Newton", plain_results);
  print_histogram("random pairs, with fallback", results);
  int plain_failures = 0, recovered = 0, failures = 0;
  double worst_depth = 0, worst_excess = -1;
  for (int k = 0; k < int(cases.size()); ++k) {
    ASSERT_TRUE(finite_result(plain_results[k]) && finite_result(results[k]));
    plain_failures += plain_results[k].status == 2;
    failures += results[k].status == 2;
    recovered += plain_results[k].status == 2 && results[k].status == 1;
    if (results[k].status == 2)
      continue;
    EXPECT_TRUE(results[k].geometry.touching) << k;
    const double size = size_of_pair(cases[k].pair.i, cases[k].pair.j);
    const double depth_error =
        std::fabs(results[k].geometry.overlap - cases[k].design_overlap) / cases[k].design_overlap;
    // First-order agreement with the design depth, as in HardCases, scaled by the curvature
    // at the contact (aspect ratios here reach 25; measured worst ratio 1.8).
    const double curvature_scale =
        cases[k].design_overlap * (results[k].curvature_i + results[k].curvature_j);
    EXPECT_LT(depth_error, 3 * curvature_scale) << k;
    worst_depth = std::max(worst_depth, depth_error / curvature_scale);
    if (k % 10 == 0) { // the rigorous chord bound on a tenth (two brute-force supports each)
      const double excess =
          results[k].geometry.overlap - projected_overlap(BruteForceBody(cases[k].pair.i),
                                                          BruteForceBody(cases[k].pair.j),
                                                          results[k].geometry.normal);
      EXPECT_LT(excess / size, 1e-9) << k;
      worst_excess = std::max(worst_excess, excess / size);
    }
  }
  std::cout << "[ measured ] random pairs: plain Newton failed " << plain_failures
            << ", recovered by the fallback " << recovered << ", failed with fallback " << failures
            << "; worst depth error / (depth (k_i + k_j)) " << worst_depth
            << ", worst chord excess " << worst_excess << "\n";
  EXPECT_EQ(recovered, plain_failures - failures);
  EXPECT_LE(failures, 3); // at most 0.1 %
}

TEST(SuperquadricContact, SpherePathMatchesMidwayMethod) {
  std::mt19937_64 rng(3);
  std::vector<PairCase> sphere_path, midway;
  std::vector<double> designs;
  for (int k = 0; k < 300; ++k) {
    const double radius = uniform(rng, 0.1, 1.5);
    const PosedSuperquadric sphere = posed(radius, radius, radius, 2, 2, {}, Quat{});
    const PosedSuperquadric j =
        posed(1, uniform(rng, 0.3, 2), uniform(rng, 0.3, 2), uniform(rng, 2, 10),
              uniform(rng, 2, 10), {}, random_rotation(rng));
    const double relative = log_uniform(rng, 1e-6, 0.1);
    const double overlap = relative * size_of_pair(sphere, j);
    const PosedSuperquadric placed_j = place_in_contact(sphere, j, random_unit(rng), overlap);
    PairCase c = pair_case(sphere, placed_j);
    midway.push_back(c);
    c.sphere_i = true;
    sphere_path.push_back(c);
    designs.push_back(overlap);
  }
  const std::vector<NarrowPhaseResult> exact = run_cases(sphere_path);
  const std::vector<NarrowPhaseResult> pair = run_cases(midway);
  print_histogram("sphere path", exact);
  print_histogram("sphere as n = 2 superquadric", pair);
  double worst_depth = 0, worst_normal = 0, worst_reference = 0;
  for (int k = 0; k < 300; ++k) {
    ASSERT_EQ(exact[k].status, 0) << k;
    ASSERT_LE(pair[k].status, 1) << k;
    ASSERT_TRUE(exact[k].geometry.touching && pair[k].geometry.touching) << k;
    const double size = size_of_pair(midway[k].i, midway[k].j), relative = designs[k] / size;
    const double depth =
        std::fabs(exact[k].geometry.overlap - pair[k].geometry.overlap) / designs[k];
    const double normal = angle_between(exact[k].geometry.normal, pair[k].geometry.normal);
    // The two define the overlap differently (closest point vs midway chord): first order.
    EXPECT_LT(depth, 3 * relative) << k;
    EXPECT_LT(normal, 3 * relative) << k;
    EXPECT_NEAR(exact[k].curvature_i, 1 / midway[k].i.shape.a, 1e-12 / midway[k].i.shape.a);
    worst_depth = std::max(worst_depth, depth / relative);
    worst_normal = std::max(worst_normal, normal / relative);
    if (k % 10 == 0) { // the sphere path is exact: the brute-force penetration depth
      const Comparison cmp = compare_with_reference(midway[k], exact[k]);
      EXPECT_LT(cmp.depth_error * cmp.reference_depth / size, 1e-8); // reference accuracy
      worst_reference = std::max(worst_reference, cmp.depth_error * cmp.reference_depth / size);
    }
  }
  std::cout << "[ measured ] sphere path vs midway: worst depth difference / depth / (depth/size) "
            << worst_depth << ", normal " << worst_normal
            << "; sphere path vs brute force, worst depth error / size " << worst_reference << "\n";
}

TEST(SuperquadricContact, DegenerateInputsNeverGiveNaN) {
  const PosedSuperquadric cube = posed(1, 1, 1, 10, 10, {}, Quat{});
  std::vector<PairCase> cases;
  cases.push_back(pair_case(cube, cube)); // coincident centres
  cases.push_back(pair_case(cube, posed(1, 1, 1, 10, 10, {0, 0, 1e-3}, Quat{})));
  cases.push_back(pair_case(cube, posed(1, 1, 1, 10, 10, {0, 0, 30}, Quat{}))); // far apart
  PairCase nan_start = pair_case(cube, posed(1, 1, 1, 4, 4, {0, 0, 1.9}, Quat{}));
  nan_start.previous = MidwayState{{std::nan(""), 0, 0}, 1.0};
  cases.push_back(nan_start);
  PairCase sphere = pair_case(posed(0.5, 0.5, 0.5, 2, 2, {}, Quat{}), cube);
  sphere.sphere_i = true; // sphere centre at the cube's centre
  cases.push_back(sphere);
  const std::vector<NarrowPhaseResult> results = run_cases(cases);
  for (int k = 0; k < int(cases.size()); ++k) {
    EXPECT_TRUE(finite_result(results[k])) << k;
    std::cout << "[ measured ] degenerate case " << k << ": status " << results[k].status
              << ", touching " << results[k].geometry.touching << ", overlap "
              << results[k].geometry.overlap << "\n";
  }
  EXPECT_FALSE(results[2].geometry.touching); // separated: converged, not touching
  EXPECT_EQ(results[2].status, 0);
  EXPECT_LE(results[3].status, 1); // the NaN warm start is discarded for the sphere start
  EXPECT_TRUE(results[3].geometry.touching);
}

} // namespace
} // namespace kdem
