// The implicit-surface numerics are generic: a second surface type, a sphere written directly as
// F = (|x - c|^2 / r^2 - 1) / 2 (not as a superquadric), goes through the same midway-point
// solve, surface-point search, curvature and separation bound, which must give the closed forms
// of two spheres.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry_test_support.hpp"
#include "shapes/superquadric_contact.hpp"

namespace kdem {
namespace {

struct ImplicitSphere {
  Vec3 centre;
  Mat3 rotation; // identity (set by make)
  double radius = 1;

  KOKKOS_INLINE_FUNCTION Vec3 to_local(Vec3 x) const { return x - centre; }
  KOKKOS_INLINE_FUNCTION Vec3 to_world(Vec3 x_local) const { return centre + x_local; }
  template <bool WithHessian> KOKKOS_INLINE_FUNCTION ShapeFunction local(Vec3 x) const {
    ShapeFunction f;
    const double r2 = radius * radius;
    f.value = 0.5 * (norm2(x) / r2 - 1.0);
    f.gradient = (1.0 / r2) * x;
    if (WithHessian)
      for (int k = 0; k < 3; ++k)
        f.hessian.m[k][k] = 1.0 / r2;
    return f;
  }
  template <bool WithHessian = true>
  KOKKOS_INLINE_FUNCTION ShapeFunction evaluate_with_body_hessian(Vec3 x) const {
    return local<WithHessian>(to_local(x));
  }
  template <bool WithHessian = true> KOKKOS_INLINE_FUNCTION ShapeFunction evaluate(Vec3 x) const {
    return local<WithHessian>(to_local(x));
  }
  KOKKOS_INLINE_FUNCTION Mat3 world_hessian(const Mat3& body) const { return body; }
  KOKKOS_INLINE_FUNCTION double value(Vec3 x) const { return local<false>(to_local(x)).value; }
  KOKKOS_INLINE_FUNCTION double smallest_length() const { return radius; }
  KOKKOS_INLINE_FUNCTION double reach() const { return radius; }
  KOKKOS_INLINE_FUNCTION double equivalent_radius() const { return radius; }
};

static_assert(is_implicit_surface<ImplicitSphere>::value, "the test sphere models the concept");

ImplicitSphere make(Vec3 centre, double radius) {
  ImplicitSphere s;
  s.centre = centre;
  s.radius = radius;
  for (int k = 0; k < 3; ++k)
    s.rotation.m[k][k] = 1;
  return s;
}

struct SpherePair {
  ImplicitSphere i, j;
};

struct SolvedPair {
  bool converged = false, chord = false;
  NarrowPhaseResult result;
  double separation = 0;
};

struct SolveMidway {
  KOKKOS_INLINE_FUNCTION SolvedPair operator()(const SpherePair& pair) const {
    using namespace narrow_phase;
    SolvedPair out;
    const auto problem = make_midway_problem(pair.i, pair.j, 1e-12);
    Unknowns u = start_with_initial_multiplier(problem, sphere_midway_point(pair.i, pair.j) +
                                                            Vec3{0, 1e-3 * pair.i.radius, 0});
    auto e = problem.evaluate(u);
    int iterations = 0;
    out.converged = newton_solve(problem, u, e, 40, iterations);
    if (!out.converged)
      return out;
    const Vec3 normal = unit_or_zero(unit_or_zero(e.fj.gradient) - unit_or_zero(e.fi.gradient));
    if (e.fi.value < 0 && e.fj.value < 0) // inside both: the bodies overlap
      out.chord = chord_geometry(pair.i, pair.j, u.x, normal, out.result);
    else
      out.separation = separation_bound(pair.i, pair.j, u.x, e.fi, e.fj);
    return out;
  }
};

// Overlap, normal and curvatures of two overlapping spheres against the closed form r_i + r_j - d,
// the line of centres and 1 / r; the Newton tolerance 1e-12 bounds the errors at ~1e-12 r.
TEST(ImplicitSurface, TheMidwaySolveOfTwoSpheresGivesTheirClosedForm) {
  std::vector<SpherePair> cases;
  for (double gap : {-0.2, -0.05, -1e-4})
    for (double rj : {0.5, 1.0, 3.0})
      cases.push_back(
          {make({0, 0, 0}, 1.0), make(((1.0 + rj + gap) / std::sqrt(1.09)) * Vec3{0.3, 0, 1}, rj)});
  const std::vector<SolvedPair> solved = run_on_device<SolvedPair>(cases, SolveMidway{});
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const SpherePair& c = cases[k];
    const Vec3 d = c.i.centre - c.j.centre;
    ASSERT_TRUE(solved[k].converged) << k;
    ASSERT_TRUE(solved[k].chord) << k;
    const NarrowPhaseResult& r = solved[k].result;
    EXPECT_NEAR(r.geometry.overlap, c.i.radius + c.j.radius - norm(d), 1e-9) << k;
    EXPECT_NEAR(dot(r.geometry.normal, (1.0 / norm(d)) * d), 1.0, 1e-10) << k;
    EXPECT_NEAR(r.curvature_i, 1.0 / c.i.radius, 1e-9) << k;
    EXPECT_NEAR(r.curvature_j, 1.0 / c.j.radius, 1e-9) << k;
  }
}

// Apart: the separation bound is a lower bound on the gap d - r_i - r_j. For this F, F / |grad F|
// at a distance s outside is s (2 r + s) / (2 (r + s)), between s / 2 and s, so the bound is at
// least half the gap (the normals at the midway point are antiparallel: no tilt term).
TEST(ImplicitSurface, TheSeparationBoundOfTwoSpheresIsTheirGap) {
  std::vector<SpherePair> cases;
  for (double gap : {1e-3, 0.1, 1.0})
    for (double rj : {0.5, 2.0})
      cases.push_back({make({0, 0, 0}, 1.0), make({0, 0.2 * rj, 1.0 + rj + gap}, rj)});
  const std::vector<SolvedPair> solved = run_on_device<SolvedPair>(cases, SolveMidway{});
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const SpherePair& c = cases[k];
    const double gap = norm(c.i.centre - c.j.centre) - c.i.radius - c.j.radius;
    ASSERT_TRUE(solved[k].converged) << k;
    EXPECT_LE(solved[k].separation, gap) << k;
    EXPECT_GT(solved[k].separation, 0.49 * gap) << k;
  }
}

} // namespace
} // namespace kdem
