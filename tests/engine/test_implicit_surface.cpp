// The implicit-surface numerics are generic: a second surface type, a sphere written directly as
// F = (|x - c|^2 / r^2 - 1) / 2 (not as a superquadric), goes through the same midway-point
// solve, surface-point search, curvature and separation bound, which must give the closed forms
// of two spheres, and through the wall numerics (plane, triangle face, edge and vertex, inside of
// a cylinder), which must give those of a sphere against each.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry_test_support.hpp"
#include "shapes/superquadric_contact.hpp"
#include "shapes/surface_wall.hpp"

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
  KOKKOS_INLINE_FUNCTION Vec3 support_local(Vec3 direction) const {
    const double length = norm(direction);
    return length > 0 ? (radius / length) * direction : Vec3{};
  }
  KOKKOS_INLINE_FUNCTION BodyBox local_box() const {
    return BodyBox{Vec3{-radius, -radius, -radius}, Vec3{radius, radius, radius}};
  }
};

static_assert(is_implicit_surface<ImplicitSphere>::value, "the test sphere models the concept");
static_assert(is_wall_surface<ImplicitSphere>::value, "and the wall numerics' part of it");
static_assert(is_wall_surface<PosedSuperquadric>::value, "as a superquadric does");

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
      out.chord = chord_geometry(pair.i, pair.j, u.x, normal, e.fi, e.fj, out.result);
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

// A sphere against one wall feature: a plane (z = 0, normal +z), the triangle (0,0,0), (1,0,0),
// (0,1,0) lying in z = 0, or the inside of a cylinder about the z axis of radius 1.
struct WallCase {
  enum Kind { plane, triangle, cylinder } kind = plane;
  ImplicitSphere sphere;
};

struct SolveWall {
  KOKKOS_INLINE_FUNCTION SurfaceWallContact operator()(const WallCase& c) const {
    const Vec3 up{0, 0, 1}, origin{0, 0, 0};
    switch (c.kind) {
    case WallCase::plane:
      return surface_plane_contact(c.sphere, origin, up);
    case WallCase::triangle: {
      const Vec3 a{0, 0, 0}, b{1, 0, 0}, d{0, 1, 0};
      return surface_triangle_contact(c.sphere, a, b, d, isolated_triangle(a, b, d));
    }
    default:
      return surface_inside_cylinder_contact(c.sphere, origin, up, 1.0);
    }
  }
};

// The closest point x of the wall feature to the sphere's centre q, as the contact must find it:
// overlap r - |q - x|, normal (q - x) / |q - x| (cylinder: |q_perp| + r - 1 and -q_perp /
// |q_perp|), curvature 1 / r, and the feature (0 face, 1 edge ab, 3 edge ca, 4 vertex a,
// 5 vertex b).
struct ExpectedWall {
  Vec3 closest;
  int feature = 0;
};

// Root-finding and support points resolve positions to ~1e-15 of the size; the golden-section
// search of the cylinder resolves the angle to 1e-9, which moves the reach by ~1e-18.
TEST(ImplicitSurface, TheWallNumericsOfASphereGiveItsClosedForms) {
  const double r = 0.3;
  std::vector<WallCase> cases;
  std::vector<ExpectedWall> expected;
  auto add = [&](WallCase::Kind kind, Vec3 centre, Vec3 closest, int feature) {
    cases.push_back({kind, make(centre, r)});
    expected.push_back({closest, feature});
  };
  add(WallCase::plane, {0.2, -5, 0.25}, {0.2, -5, 0}, 0);
  add(WallCase::plane, {0, 0, 0.01}, {0, 0, 0}, 0);
  add(WallCase::triangle, {0.2, 0.3, 0.1}, {0.2, 0.3, 0}, 0);   // above the face
  add(WallCase::triangle, {0.5, -0.1, 0.15}, {0.5, 0, 0}, 1);   // beside edge ab
  add(WallCase::triangle, {-0.12, 0.4, -0.05}, {0, 0.4, 0}, 3); // beside edge ca, below
  add(WallCase::triangle, {-0.1, -0.15, 0.1}, {0, 0, 0}, 4);    // beyond vertex a
  add(WallCase::triangle, {1.1, -0.1, 0.05}, {1, 0, 0}, 5);     // beyond vertex b
  add(WallCase::cylinder, {0.7, 0.3, 3}, {}, 0);
  add(WallCase::cylinder, {-0.05, -0.75, -1}, {}, 0);
  const std::vector<SurfaceWallContact> found =
      run_on_device<SurfaceWallContact>(cases, SolveWall{});
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Vec3 q = cases[k].sphere.centre;
    const Vec3 across{q.x, q.y, 0}; // cylinder: from the axis to the centre
    const bool inside_cylinder = cases[k].kind == WallCase::cylinder;
    const Vec3 away = inside_cylinder ? -1.0 * across : q - expected[k].closest;
    const double overlap = inside_cylinder ? norm(across) + r - 1.0 : r - norm(away);
    const Vec3 normal = (1.0 / norm(away)) * away;
    const ContactGeometry& g = found[k].geometry;
    ASSERT_TRUE(g.touching) << k;
    EXPECT_EQ(found[k].feature, expected[k].feature) << k;
    EXPECT_NEAR(g.overlap, overlap, 1e-13) << k;
    EXPECT_NEAR(dot(g.normal, normal), 1.0, 1e-13) << k;
    EXPECT_NEAR(found[k].curvature, 1.0 / r, 1e-10) << k;
  }
}

// Just apart from each feature: no contact, and never a NaN deepest point.
TEST(ImplicitSurface, ASphereJustApartFromAWallFeatureHasNoContact) {
  const double r = 0.3, gap = 1e-9;
  std::vector<WallCase> cases{{WallCase::plane, make({0.1, 0.1, r + gap}, r)},
                              {WallCase::triangle, make({0.2, 0.2, -(r + gap)}, r)},
                              {WallCase::triangle, make({0.5, -(r + gap), 0}, r)},
                              {WallCase::cylinder, make({1.0 - r - gap, 0, 0.5}, r)}};
  const std::vector<SurfaceWallContact> found =
      run_on_device<SurfaceWallContact>(cases, SolveWall{});
  for (std::size_t k = 0; k < cases.size(); ++k) {
    EXPECT_FALSE(found[k].geometry.touching) << k;
    EXPECT_TRUE(std::isfinite(norm(found[k].deepest_point))) << k;
  }
}

} // namespace
} // namespace kdem
