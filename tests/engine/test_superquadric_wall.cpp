// Superquadric-wall contact geometry against brute force: the support point, plane, triangle
// (face, edge, vertex) and inside-cylinder contacts, and one contact per touched feature of a
// mesh. The functions under test run in parallel_for kernels on the engine's backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "kernels/types.hpp"
#include "shapes/superquadric.hpp"
#include "shapes/surface_wall.hpp"

#include "geometry_test_support.hpp"

namespace kdem {
namespace {

double largest_semi_axis(const SuperquadricShape& s) {
  return std::max(s.a, std::max(s.b, s.c));
}

// --- Host helpers
// ---------------------------------------------------------------------------------

Vec3 unit(Vec3 v) {
  return (1.0 / norm(v)) * v;
}

bool finite(Vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool finite(const SurfaceWallContact& c) {
  return std::isfinite(c.geometry.overlap) && finite(c.geometry.normal) &&
         finite(c.geometry.point) && std::isfinite(c.curvature) && finite(c.deepest_point);
}

// F without the conditioning factor, so that it reads as a relative distance from the surface.
double shape_value(const SuperquadricShape& s, Vec3 local) {
  return superquadric_local<false>(s, local).value / s.conditioning;
}

double signed_power(double t, double e) {
  return t < 0 ? -std::pow(-t, e) : std::pow(t, e);
}

// Surface point at latitude eta in [-pi/2, pi/2] and longitude omega (Barr's parametrisation).
Vec3 surface_point(const SuperquadricShape& s, double eta, double omega) {
  const double ring = signed_power(std::cos(eta), 2.0 / s.n1);
  return {s.a * ring * signed_power(std::cos(omega), 2.0 / s.n2),
          s.b * ring * signed_power(std::sin(omega), 2.0 / s.n2),
          s.c * signed_power(std::sin(eta), 2.0 / s.n1)};
}

// Brute force: the largest `score` over surface points, from a 240 x 480 grid of the
// parametrisation refined by 12 zooms (factor 4 each) around the best sample.
template <class Score> double sampled_surface_maximum(const SuperquadricShape& s, Score score) {
  const double half_pi = 0.5 * pi;
  double best = -1e300, best_eta = 0, best_omega = 0;
  const int rows = 240, columns = 480;
  for (int i = 0; i <= rows; ++i)
    for (int j = 0; j < columns; ++j) {
      const double eta = -half_pi + pi * i / rows, omega = -pi + 2 * pi * j / columns;
      const double v = score(surface_point(s, eta, omega));
      if (v > best)
        best = v, best_eta = eta, best_omega = omega;
    }
  double span_eta = pi / rows, span_omega = 2 * pi / columns;
  for (int zoom = 0; zoom < 12; ++zoom) {
    const double centre_eta = best_eta, centre_omega = best_omega;
    for (int i = -8; i <= 8; ++i)
      for (int j = -8; j <= 8; ++j) {
        const double eta = std::max(-half_pi, std::min(half_pi, centre_eta + span_eta * i / 4));
        const double omega = centre_omega + span_omega * j / 4;
        const double v = score(surface_point(s, eta, omega));
        if (v > best)
          best = v, best_eta = eta, best_omega = omega;
      }
    span_eta /= 4, span_omega /= 4;
  }
  return best;
}

PosedSuperquadric pose(const SuperquadricShape& s, Vec3 centre, Quat q) {
  return pose_superquadric(s, centre, q);
}

// --- Support point
// ----------------------------------------------------------------------------------

struct SupportCase {
  SuperquadricShape shape;
  Vec3 direction;
};

struct SupportOfCase {
  KOKKOS_INLINE_FUNCTION Vec3 operator()(const SupportCase& c) const {
    return superquadric_support_point(c.shape, c.direction);
  }
};

// Book Eq. 2.11 as rebuilt in the digest (nx != 0, |nx| >= |ny| after swapping x and y).
Vec3 book_support_point(const SuperquadricShape& s, Vec3 n) {
  const bool swap = std::fabs(n.x) < std::fabs(n.y);
  const double a = swap ? s.b : s.a, b = swap ? s.a : s.b, nx = swap ? n.y : n.x,
               ny = swap ? n.x : n.y;
  const double n1 = s.n1, n2 = s.n2, c = s.c;
  const double alpha = std::pow(std::fabs(b * ny / (a * nx)), 1 / (n2 - 1));
  const double gamma = std::pow(1 + std::pow(alpha, n2), n1 / n2 - 1);
  const double beta = std::pow(gamma * std::fabs(c * n.z) / std::fabs(a * nx), 1 / (n1 - 1));
  const double x =
      a / std::pow(std::pow(1 + std::pow(alpha, n2), n1 / n2) + std::pow(beta, n1), 1 / n1);
  const double y = alpha * b * x / a, z = beta * c * x / a;
  const Vec3 first{std::copysign(x, nx), std::copysign(y, ny), std::copysign(z, n.z)};
  return swap ? Vec3{first.y, first.x, first.z} : first;
}

TEST(SuperquadricWall, SupportPointIsOnTheSurfaceWithTheGivenNormal) {
  std::mt19937_64 rng(7);
  std::vector<SupportCase> cases;
  for (int i = 0; i < 2500; ++i) // 2000 with n in [2, 10], 500 up to 16
    cases.push_back({random_shape(rng, i < 2000 ? 10.0 : 16.0), random_unit(rng)});
  const std::vector<Vec3> special = {
      {1, 0, 0},        {-1, 0, 0},   {0, 1, 0},        {0, -1, 0},
      {0, 0, 1},        {0, 0, -1},   {0.6, 0.8, 0},    {-0.6, 0, 0.8},
      {0, -0.28, 0.96}, {1e-9, 0, 1}, {1e-300, 1, 0},   {1, 1e-300, 1e-300},
      {0, 1e-12, -1},   {1, 1, 1},    {-1, 1e-200, -1}, {1e-20, 1e-20, 1}};
  for (int i = 0; i < 400; ++i)
    cases.push_back({random_shape(rng, i % 2 ? 16.0 : 10.0), special[i % special.size()]});
  const std::vector<Vec3> points = run_on_device<Vec3>(cases, SupportOfCase{});

  double worst_value = 0, worst_alignment = 0, worst_book = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const SuperquadricShape& s = cases[i].shape;
    const Vec3 d = unit(cases[i].direction), x = points[i];
    ASSERT_TRUE(finite(x)) << i;
    worst_value = std::max(worst_value, std::fabs(shape_value(s, x)));
    const Vec3 g = superquadric_local<false>(s, x).gradient;
    worst_alignment = std::max(worst_alignment, norm(cross(unit(g), d)));
    const bool generic = std::fabs(d.x) > 1e-3 && std::fabs(d.y) > 1e-3 && std::fabs(d.z) > 1e-3;
    if (generic)
      worst_book = std::max(worst_book, norm(x - book_support_point(s, d)) / largest_semi_axis(s));
  }
  // Rounding of a few pow calls, each a few ulps: 100 ulps of F.
  EXPECT_LT(worst_value, 2e-14);
  // The angle between the normal and the direction: rounding of the point, amplified by the
  // curvature of the sharpest corners met (n = 16): 1e-13 rad.
  EXPECT_LT(worst_alignment, 1e-13);
  // The same point as the book's formula, to rounding of the point (100 ulps of the size).
  EXPECT_LT(worst_book, 2e-14);
  std::printf("support point: |F| %.2e, angle %.2e, vs book %.2e\n", worst_value, worst_alignment,
              worst_book);
}

// --- Plane
// --------------------------------------------------------------------------------------------

struct PlaneCase {
  PosedSuperquadric particle;
  Vec3 origin, normal;
};

struct PlaneContactOfCase {
  KOKKOS_INLINE_FUNCTION SurfaceWallContact operator()(const PlaneCase& c) const {
    return surface_plane_contact(c.particle, c.origin, c.normal);
  }
};

// Depth of the particle below a plane by brute force: the largest depth of a surface sample.
double sampled_plane_overlap(const PlaneCase& c) {
  const PosedSuperquadric& p = c.particle;
  return sampled_surface_maximum(p.shape,
                                 [&](Vec3 x) { return -dot(p.to_world(x) - c.origin, c.normal); });
}

// Centre height above the plane at which the particle overlaps it by `overlap`.
Vec3 centre_for_overlap(const SuperquadricShape& s, Quat q, Vec3 origin, Vec3 normal,
                        double overlap) {
  const PosedSuperquadric at_origin = pose(s, Vec3{0, 0, 0}, q);
  const double reach = -dot(support_point_world(at_origin, -normal), normal);
  return origin + (reach - overlap) * normal;
}

std::vector<PlaneCase> plane_cases() {
  std::mt19937_64 rng(11);
  const SuperquadricShape cube16 = make_superquadric(0.5, 0.5, 0.5, 16, 16);
  const SuperquadricShape cube8 = make_superquadric(0.4, 0.6, 0.5, 8, 8);
  const SuperquadricShape cylinder = make_superquadric(0.3, 0.3, 0.9, 8, 2);
  const SuperquadricShape ellipsoid = make_superquadric(0.3, 0.5, 0.8, 2, 2);
  const double quarter = 0.5 * pi, diagonal_tilt = std::acos(1 / std::sqrt(3.0));
  struct Posed {
    SuperquadricShape shape;
    Quat q;
  };
  const std::vector<Posed> poses = {
      {cube16, Quat{}},                           // face-down
      {cube16, axis_angle({1, 0, 0}, 0.25 * pi)}, // edge-down
      {cube16, axis_angle({1, -1, 0}, diagonal_tilt) * axis_angle({0, 0, 1}, 0.25 * pi)}, // corner
      {cube8, Quat{}},
      {cube8, axis_angle({0, 1, 0}, 0.25 * pi)},
      {cube8, axis_angle({1, -1, 0}, diagonal_tilt) * axis_angle({0, 0, 1}, 0.25 * pi)},
      {cylinder, Quat{}},                         // standing on its flat end
      {cylinder, axis_angle({1, 0, 0}, quarter)}, // lying on its side
      {cylinder, axis_angle({1, 0, 0}, 0.3)},     // on its rim
      {ellipsoid, Quat{}},
  };
  std::vector<PlaneCase> cases;
  for (const Posed& posed : poses)
    for (int variant = 0; variant < 4; ++variant) {
      // The plane itself is tilted and turned, so that nothing lines up with the world axes.
      const Quat frame = variant == 0 ? Quat{} : random_rotation(rng);
      const Vec3 normal = rotate(frame, Vec3{0, 0, 1});
      const Vec3 origin{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
      const Quat q = frame * axis_angle({0, 0, 1}, variant * 0.7) * posed.q;
      const double overlap = 0.01 * (1 + variant);
      cases.push_back(
          {pose(posed.shape, centre_for_overlap(posed.shape, q, origin, normal, overlap), q),
           origin, normal});
    }
  for (int i = 0; i < 24; ++i) { // random shapes and orientations
    const SuperquadricShape s = random_shape(rng, 16.0);
    const Vec3 normal = random_unit(rng), origin{uniform(rng, -1, 1), 0, 0};
    const Quat q = random_rotation(rng);
    cases.push_back({pose(s, centre_for_overlap(s, q, origin, normal, 0.05), q), origin, normal});
  }
  return cases;
}

TEST(SuperquadricWall, PlaneOverlapMatchesBruteForce) {
  const std::vector<PlaneCase> cases = plane_cases();
  const auto contacts = run_on_device<SurfaceWallContact>(cases, PlaneContactOfCase{});
  double worst_low = 0, worst_high = 0, worst_surface = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const SurfaceWallContact& c = contacts[i];
    const PosedSuperquadric& p = cases[i].particle;
    ASSERT_TRUE(c.geometry.touching) << i;
    const double size = largest_semi_axis(p.shape);
    const double difference = (c.geometry.overlap - sampled_plane_overlap(cases[i])) / size;
    worst_low = std::min(worst_low, difference);
    worst_high = std::max(worst_high, difference);
    worst_surface =
        std::max(worst_surface, std::fabs(shape_value(p.shape, p.to_local(c.deepest_point))));
    EXPECT_EQ(norm(c.geometry.normal - cases[i].normal), 0.0); // the wall's normal itself
    const Vec3 expected_point = c.deepest_point + (0.5 * c.geometry.overlap) * cases[i].normal;
    EXPECT_LT(norm(c.geometry.point - expected_point), 1e-15 * size * 4); // 4 ulps of size
    EXPECT_GE(c.curvature, 0.0);
    EXPECT_TRUE(std::isfinite(c.curvature));
  }
  // No surface sample lies deeper than the computed point (rounding of the samples: 1e-14).
  EXPECT_GT(worst_low, -1e-14);
  // The zoomed sampling ends with angular steps of 2e-10 rad; at a smooth deepest point the
  // depth it misses is quadratic in that step, at a sharp one linear: 1e-12 of the size.
  EXPECT_LT(worst_high, 1e-12);
  EXPECT_LT(worst_surface, 2e-14); // the deepest point is on the surface (support-point bound)
  std::printf("plane: overlap - sampled in [%.2e, %.2e] of the size, |F| %.2e\n", worst_low,
              worst_high, worst_surface);
}

// A flat face lying on a plane, in frames turned at random so that the rotations round: the
// contact point stays at the face's centre (body frame: on the cylinder's mid-plane, under the
// cube's centre), where symmetry puts it, instead of sliding towards an edge by the
// (1e-16)^(1/(n - 1)) sensitivity of a blocky face's support point.
TEST(SuperquadricWall, FlatFaceOnAPlaneTouchesAtTheFaceCentre) {
  std::mt19937_64 rng(29);
  const SuperquadricShape cylinder = make_superquadric(1e-3, 1e-3, 2e-3, 8, 2);
  const SuperquadricShape cube = make_superquadric(1e-3, 1e-3, 1e-3, 8, 8);
  const Quat lying = axis_angle(Vec3{1, 0, 0}, 0.5 * M_PI); // body z horizontal, y down
  std::vector<PlaneCase> cases;
  for (int k = 0; k < 200; ++k) {
    const Quat frame = random_rotation(rng);
    const SuperquadricShape& shape = k % 2 == 0 ? cylinder : cube;
    const Quat orientation = frame * (k % 2 == 0 ? lying : Quat{1, 0, 0, 0});
    const Vec3 normal = rotate(frame, Vec3{0, 0, 1});
    const double height = 0.999e-3; // both reach 1e-3 below the centre: 1 um overlap
    cases.push_back({pose(shape, height * normal, orientation), Vec3{}, normal});
  }
  const auto contacts = run_on_device<SurfaceWallContact>(cases, PlaneContactOfCase{});
  double worst = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    ASSERT_TRUE(contacts[k].geometry.touching) << k;
    const Vec3 local = cases[k].particle.to_local(contacts[k].deepest_point);
    // The cylinder's axis is body z; the cube's face is z = -c: the centre is x = y = 0.
    const double off_centre = k % 2 == 0 ? std::fabs(local.z) : std::hypot(local.x, local.y);
    worst = std::max(worst, off_centre / 1e-3);
  }
  // Rounding of the pose only (without the snapping of rotation noise: about 5e-3).
  EXPECT_LT(worst, 1e-9);
  std::printf("flat face on a plane: contact point off the face centre by %.2e of the size\n",
              worst);
}

TEST(SuperquadricWall, PlaneCurvatureOfASphereIsItsInverseRadius) {
  const SuperquadricShape sphere = make_superquadric(0.25, 0.25, 0.25, 2, 2);
  std::vector<PlaneCase> cases;
  std::mt19937_64 rng(5);
  for (int i = 0; i < 16; ++i) {
    const Vec3 normal = random_unit(rng);
    cases.push_back({pose(sphere, 0.2 * normal, random_rotation(rng)), Vec3{0, 0, 0}, normal});
  }
  const auto contacts = run_on_device<SurfaceWallContact>(cases, PlaneContactOfCase{});
  for (const auto& c : contacts) {
    EXPECT_NEAR(c.geometry.overlap, 0.05, 1e-15); // rounding of a 0.25 m sphere
    EXPECT_NEAR(c.curvature, 4.0, 1e-13);         // mean curvature 1/R, ulps of 1/R
  }
}

// --- Triangle face, edge and vertex contacts
// -------------------------------------------------------

struct TriangleCase {
  PosedSuperquadric particle;
  Vec3 a, b, c;
};

struct FaceAndPlane {
  SurfaceWallContact triangle, plane;
};

struct FaceAndPlaneOfCase {
  KOKKOS_INLINE_FUNCTION FaceAndPlane operator()(const TriangleCase& t) const {
    const TriangleNeighbourhood alone = isolated_triangle(t.a, t.b, t.c);
    const Vec3 n = alone.normal;
    const Vec3 towards = dot(t.particle.centre - t.a, n) >= 0 ? n : -n;
    return {surface_triangle_contact(t.particle, t.a, t.b, t.c, alone),
            surface_plane_contact(t.particle, t.a, towards)};
  }
};

TEST(SuperquadricWall, FaceContactEqualsThePlaneContact) {
  std::mt19937_64 rng(13);
  std::vector<TriangleCase> cases;
  for (int i = 0; i < 400; ++i) {
    const Quat frame = random_rotation(rng);
    const Vec3 a = rotate(frame, Vec3{-20, -20, 0}), b = rotate(frame, Vec3{30, -10, 0}),
               c = rotate(frame, Vec3{0, 25, 0});
    const Vec3 normal = (i % 2 ? -1.0 : 1.0) * rotate(frame, Vec3{0, 0, 1}); // either side
    const SuperquadricShape s = random_shape(rng, 16.0);
    const Quat q = random_rotation(rng);
    const Vec3 inside = (1.0 / 3.0) * (a + b + c) +
                        rotate(frame, Vec3{uniform(rng, -3, 3), uniform(rng, -3, 3), 0});
    cases.push_back(
        {pose(s, centre_for_overlap(s, q, inside, normal, uniform(rng, 0.01, 0.2)), q), a, b, c});
  }
  const auto results = run_on_device<FaceAndPlane>(cases, FaceAndPlaneOfCase{});
  double worst = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const SurfaceWallContact &t = results[i].triangle, &p = results[i].plane;
    ASSERT_EQ(t.feature, 0) << i;
    ASSERT_TRUE(t.geometry.touching && p.geometry.touching) << i;
    const double size = largest_semi_axis(cases[i].particle.shape);
    worst = std::max(worst, std::fabs(t.geometry.overlap - p.geometry.overlap) / size);
    EXPECT_EQ(norm(t.geometry.normal - p.geometry.normal), 0.0);
    EXPECT_LT(norm(t.geometry.point - p.geometry.point), 1e-13 * size); // 30 ulps of 30 m
    EXPECT_EQ(t.curvature, p.curvature);
  }
  EXPECT_EQ(worst, 0.0); // the triangle's face contact is the plane contact, computed the same way
}

// Edge and vertex contacts, called directly on random segments through random particles.
struct EdgeCase {
  PosedSuperquadric particle;
  Vec3 u, v;
  int vertex; // -1: edge uv, else: vertex u
};

struct EdgeContactOfCase {
  KOKKOS_INLINE_FUNCTION SurfaceWallContact operator()(const EdgeCase& e) const {
    const Vec3 free_normal{0, 0, 1};
    if (e.vertex >= 0)
      return surface_vertex_contact(e.particle, e.u, free_normal, 4);
    return surface_edge_contact(e.particle, e.u, e.v, free_normal, 1);
  }
};

// Brute force: the smallest F over 20001 samples of the segment, refined by 10 zooms.
double sampled_segment_minimum(const PosedSuperquadric& p, Vec3 u, Vec3 v, double& at) {
  const Vec3 start = p.to_local(u), step = p.to_local(v) - start;
  auto value = [&](double t) { return shape_value(p.shape, start + t * step); };
  const int samples = 20000;
  double best = 1e300;
  for (int i = 0; i <= samples; ++i)
    if (value(double(i) / samples) < best)
      best = value(double(i) / samples), at = double(i) / samples;
  double span = 1.0 / samples;
  for (int zoom = 0; zoom < 10; ++zoom, span /= 8) {
    const double centre = at;
    for (int i = -16; i <= 16; ++i) {
      const double t = std::max(0.0, std::min(1.0, centre + span * i / 8));
      if (value(t) < best)
        best = value(t), at = t;
    }
  }
  return best;
}

// Brute force: the distance from a point inside along a direction to the surface, by sampling
// 20001 steps up to the bounding box and bisecting the sign change.
double sampled_depth(const SuperquadricShape& s, Vec3 from, Vec3 direction) {
  const double length = 2 * std::sqrt(s.a * s.a + s.b * s.b + s.c * s.c);
  double lo = 0, hi = length;
  for (int i = 1; i <= 20000; ++i)
    if (shape_value(s, from + (length * i / 20000) * direction) >= 0) {
      lo = length * (i - 1) / 20000, hi = length * i / 20000;
      break;
    }
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (shape_value(s, from + mid * direction) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(SuperquadricWall, EdgeAndVertexContactsMatchBruteForce) {
  std::mt19937_64 rng(17);
  std::vector<EdgeCase> cases;
  for (int i = 0; i < 300; ++i) {
    const SuperquadricShape s = random_shape(rng, i % 3 ? 10.0 : 16.0);
    const PosedSuperquadric p = pose(s, Vec3{uniform(rng, -1, 1), 0, 0}, random_rotation(rng));
    // A line through a random point inside the particle, in a random direction.
    const Vec3 inside_local{0.7 * s.a * uniform(rng, -1, 1), 0.7 * s.b * uniform(rng, -1, 1),
                            0.7 * s.c * uniform(rng, -1, 1)};
    const Vec3 through = p.to_world(0.8 * inside_local);
    const Vec3 d = random_unit(rng);
    const int kind = i % 3; // 0: long edge, 1: edge ending near the inside point, 2: vertex
    const double before =
        kind == 0 ? uniform(rng, 3, 5) : (kind == 1 ? uniform(rng, -0.3, 0.3) : 0);
    cases.push_back(
        {p, through - before * d, through + uniform(rng, 2, 6) * d, kind == 2 ? 0 : -1});
  }
  const auto contacts = run_on_device<SurfaceWallContact>(cases, EdgeContactOfCase{});
  double worst_minimum = 0, worst_depth = 0, worst_surface = 0;
  int edges = 0, vertices = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const EdgeCase& e = cases[i];
    const PosedSuperquadric& p = e.particle;
    const SurfaceWallContact& c = contacts[i];
    ASSERT_TRUE(finite(c)) << i;
    const double size = largest_semi_axis(p.shape);
    // The wall point: the contact point moved back by half the overlap along the normal.
    const Vec3 wall_point = c.geometry.point + (0.5 * c.geometry.overlap) * c.geometry.normal;
    const double f_wall = shape_value(p.shape, p.to_local(wall_point));
    if (e.vertex < 0) {
      double at = 0;
      const double sampled = sampled_segment_minimum(p, e.u, e.v, at);
      if (!(sampled < 0)) {
        EXPECT_FALSE(c.geometry.touching) << i;
        continue;
      }
      ASSERT_TRUE(c.geometry.touching) << i;
      ++edges;
      // The computed point is the minimum: never above a sample, beyond rounding.
      worst_minimum = std::max(worst_minimum, f_wall - sampled);
      const Vec3 edge = unit(e.v - e.u);
      EXPECT_LT(std::fabs(dot(c.geometry.normal, edge)), 1e-12); // normal across the edge
      // On the segment: distance of the wall point from the line, against the size.
      const Vec3 off = (wall_point - e.u) - dot(wall_point - e.u, edge) * edge;
      EXPECT_LT(norm(off), 1e-13 * size);
    } else {
      ASSERT_TRUE(c.geometry.touching) << i;
      ++vertices;
      EXPECT_LT(norm(wall_point - e.u), 1e-13 * size); // the vertex itself
    }
    const double sampled_overlap =
        sampled_depth(p.shape, p.to_local(wall_point), direction_to_local(p, -c.geometry.normal));
    worst_depth = std::max(worst_depth, std::fabs(c.geometry.overlap - sampled_overlap) / size);
    worst_surface =
        std::max(worst_surface, std::fabs(shape_value(p.shape, p.to_local(c.deepest_point))));
  }
  EXPECT_GT(edges, 100);
  EXPECT_GT(vertices, 50);
  EXPECT_LT(worst_minimum, 1e-14); // rounding of F near its minimum (conditioned to order one)
  EXPECT_LT(worst_depth, 1e-13);   // both roots converge to rounding of the size (1e-15)
  EXPECT_LT(worst_surface, 1e-13); // Newton stops within 1e-15 of the size from the surface
  std::printf("edges %d, vertices %d: F above sampled %.2e, depth %.2e, |F| %.2e\n", edges,
              vertices, worst_minimum, worst_depth, worst_surface);
}

// --- Meshes
// ------------------------------------------------------------------------------------------

struct HostMesh {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Vec3> normals; // stored per triangle; coplanar triangles share the same bits
};

struct DeviceMesh {
  int count = 0;
  Cases<Vec3> corners; // 3 per triangle
  Cases<TriangleNeighbourhood> neighbourhood;
  Cases<Vec3> rings; // what the vertex_ring pointers point into
};

bool same_normal(Vec3 m, Vec3 n) {
  return (m.x == n.x && m.y == n.y && m.z == n.z) || (m.x == -n.x && m.y == -n.y && m.z == -n.z);
}

// Topology as a mesh loader would build it: owners are the lowest-indexed triangles.
DeviceMesh upload(const HostMesh& mesh, bool with_rings) {
  const int count = int(mesh.triangles.size());
  std::map<std::pair<int, int>, std::vector<int>> edge_triangles;
  std::map<int, std::vector<int>> vertex_triangles;
  std::map<int, std::set<int>> ring;
  for (int t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.triangles[t][k], v = mesh.triangles[t][(k + 1) % 3];
      edge_triangles[{std::min(u, v), std::max(u, v)}].push_back(t);
      vertex_triangles[u].push_back(t);
      ring[u].insert(v), ring[v].insert(u);
    }
  std::vector<Vec3> ring_points;
  std::map<int, int> ring_start;
  for (const auto& [vertex, others] : ring) {
    ring_start[vertex] = int(ring_points.size());
    for (int o : others)
      ring_points.push_back(mesh.points[o]);
  }
  DeviceMesh d;
  d.count = count;
  d.rings = to_device(ring_points, "rings");
  std::vector<Vec3> corners;
  std::vector<TriangleNeighbourhood> hood(count);
  for (int t = 0; t < count; ++t) {
    TriangleNeighbourhood& h = hood[t];
    h.normal = mesh.normals[t];
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.triangles[t][k], v = mesh.triangles[t][(k + 1) % 3];
      corners.push_back(mesh.points[u]);
      const std::vector<int>& sharing = edge_triangles[{std::min(u, v), std::max(u, v)}];
      h.owns_edge[k] = sharing[0] == t;
      h.has_neighbour[k] = sharing.size() == 2;
      if (h.has_neighbour[k]) {
        const int other = sharing[0] == t ? sharing[1] : sharing[0];
        h.neighbour_normal[k] = mesh.normals[other];
        for (int j : mesh.triangles[other])
          if (j != u && j != v)
            h.neighbour_opposite[k] = mesh.points[j];
      }
      bool corner = false;
      for (int other : ring[u])
        corner |= edge_triangles[{std::min(u, other), std::max(u, other)}].size() == 1;
      for (int other : vertex_triangles[u])
        corner |= !same_normal(mesh.normals[other], mesh.normals[t]);
      h.reports_vertex[k] = vertex_triangles[u][0] == t && corner;
      if (with_rings) {
        h.vertex_ring[k] = d.rings.data() + ring_start[u];
        h.vertex_ring_size[k] = int(ring[u].size());
      }
    }
  }
  d.corners = to_device(corners, "corners");
  d.neighbourhood = to_device(hood, "neighbourhood");
  return d;
}

struct MeshResult {
  int claims = 0, touching = 0;
  int triangle = -1, feature = -1; // of the last claim
  SurfaceWallContact contact;      // of the last claim
  SurfaceWallContact plane;        // the plane of triangle 0, towards the particle
};

struct MeshContactsOfParticle {
  DeviceMesh mesh;
  KOKKOS_INLINE_FUNCTION MeshResult operator()(const PosedSuperquadric& p) const {
    MeshResult r;
    for (int t = 0; t < mesh.count; ++t) {
      const SurfaceWallContact c =
          surface_triangle_contact(p, mesh.corners(3 * t), mesh.corners(3 * t + 1),
                                   mesh.corners(3 * t + 2), mesh.neighbourhood(t));
      if (c.feature < 0)
        continue;
      ++r.claims;
      r.touching += c.geometry.touching ? 1 : 0;
      r.triangle = t, r.feature = c.feature, r.contact = c;
    }
    const Vec3 n = mesh.neighbourhood(0).normal, origin = mesh.corners(0);
    r.plane = surface_plane_contact(p, origin, dot(p.centre - origin, n) >= 0 ? n : -n);
    return r;
  }
};

struct Particle {
  SuperquadricShape shape;
  Quat q;
};

std::vector<Particle> test_particles(std::mt19937_64& rng, bool aligned) {
  std::vector<Particle> particles = {
      {make_superquadric(0.2, 0.2, 0.2, 16, 16), Quat{}},
      {make_superquadric(0.15, 0.15, 0.3, 8, 2), axis_angle({1, 0, 0}, 0.5 * pi)},
      {make_superquadric(0.3, 0.2, 0.15, 2, 2), Quat{}},
      {make_superquadric(0.25, 0.1, 0.2, 10, 4), Quat{}},
  };
  if (!aligned)
    for (Particle& particle : particles)
      particle.q = random_rotation(rng);
  return particles;
}

// A flat 2 x 2 square mesh of 8 triangles with alternating diagonals, mapped by `frame`.
HostMesh flat_mesh(Quat frame, Vec3 offset) {
  HostMesh m;
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 2; ++i)
      m.points.push_back(offset + rotate(frame, Vec3{double(i), double(j), 0}));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int p00 = 3 * j + i, p10 = p00 + 1, p01 = p00 + 3, p11 = p00 + 4;
      if ((i + j) % 2 == 0)
        m.triangles.push_back({p00, p10, p11}), m.triangles.push_back({p00, p11, p01});
      else
        m.triangles.push_back({p00, p10, p01}), m.triangles.push_back({p10, p11, p01});
    }
  const Vec3 n = unit(cross(m.points[1] - m.points[0], m.points[3] - m.points[0]));
  m.normals.assign(m.triangles.size(), n);
  return m;
}

// In-plane positions (mesh coordinates in [0.4, 1.6]^2) sweeping across the shared edges and
// the inner vertex, exactly on them and a hair beside.
std::vector<std::array<double, 2>> flat_sweep() {
  std::vector<std::array<double, 2>> at;
  for (int i = 0; i <= 60; ++i) {
    const double s = 0.4 + 1.2 * i / 60;
    at.push_back({s, 1.0}), at.push_back({1.0, s}), at.push_back({s, s}), at.push_back({s, 2 - s});
    at.push_back({s, 0.7}), at.push_back({0.5, s});
  }
  for (double hair : {0.0, 1e-15, -1e-15, 1e-12, -1e-12, 1e-9, -1e-9})
    for (auto [x, y] : std::vector<std::array<double, 2>>{
             {1, 1}, {0.5, 0.5}, {1.5, 0.5}, {0.5, 1.5}, {1.5, 1.5}, {1, 0.6}, {0.6, 1}})
      at.push_back({x + hair, y}), at.push_back({x, y + hair}), at.push_back({x + hair, y - hair});
  return at;
}

TEST(SuperquadricWall, FlatMeshGivesOneContactEqualToThePlane) {
  std::mt19937_64 rng(19);
  // 0: mesh and particles along the axes (exact ties on edges and at the inner vertex);
  // 1, 2: turned mesh, particles at random (2 with vertex rings); 3: turned mesh, particles
  // lying flat on it (their support points hang on the last bits of the normal).
  for (int variant = 0; variant < 4; ++variant) {
    const bool aligned = variant == 0 || variant == 3;
    const Quat frame = variant == 0 ? Quat{} : random_rotation(rng);
    const Vec3 offset = variant == 0 ? Vec3{0, 0, 0} : Vec3{0.3, -0.2, 0.7};
    const HostMesh host = flat_mesh(frame, offset);
    const DeviceMesh mesh = upload(host, variant == 2);
    const Vec3 normal = host.normals[0];
    std::vector<PosedSuperquadric> cases;
    for (const Particle& particle : test_particles(rng, aligned))
      for (auto [x, y] : flat_sweep()) {
        // The point where the smallest scaled copy touches the plane lies under the centre
        // for aligned particles: put the centre over the sweep point.
        const Vec3 spot = offset + rotate(frame, Vec3{x, y, 0});
        const Quat q = frame * particle.q;
        cases.push_back(
            pose(particle.shape, centre_for_overlap(particle.shape, q, spot, normal, 0.02), q));
      }
    const auto results = run_on_device<MeshResult>(cases, MeshContactsOfParticle{mesh});
    int faces = 0;
    double worst = 0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const MeshResult& r = results[i];
      ASSERT_EQ(r.claims, 1) << "variant " << variant << " case " << i;
      ASSERT_EQ(r.touching, 1) << "variant " << variant << " case " << i;
      ASSERT_EQ(r.feature, 0) << "variant " << variant << " case " << i;
      faces += 1;
      const double size = largest_semi_axis(cases[i].shape);
      worst =
          std::max(worst, std::fabs(r.contact.geometry.overlap - r.plane.geometry.overlap) / size);
      EXPECT_EQ(norm(r.contact.geometry.normal - r.plane.geometry.normal), 0.0) << i;
      EXPECT_LT(norm(r.contact.geometry.point - r.plane.geometry.point), 1e-14) << i; // ulps of 2 m
    }
    EXPECT_LT(worst, 1e-13); // only the plane origin differs: ulps of the 2 m mesh
    EXPECT_EQ(faces, int(cases.size()));
  }
}

// Brute force over a mesh: the smallest F over a 60-step barycentric grid of every triangle.
double sampled_mesh_minimum(const HostMesh& m, const PosedSuperquadric& p) {
  double best = 1e300;
  const int n = 60;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        best = std::min(best, shape_value(p.shape, p.to_local(a + (double(i) / n) * (b - a) +
                                                              (double(j) / n) * (c - a))));
  }
  return best;
}

// Minimum of a convex function on [0, 1] by golden-section search, to 1e-13 in the argument.
template <class Function> double golden_section_minimum(Function f, double& at) {
  const double g = 0.6180339887498949;
  double lo = 0, hi = 1, left = hi - g, right = g, f_left = f(left), f_right = f(right);
  while (hi - lo > 1e-13) {
    if (f_left > f_right)
      lo = left, left = right, f_left = f_right, right = lo + g * (hi - lo), f_right = f(right);
    else
      hi = right, right = left, f_right = f_left, left = hi - g * (hi - lo), f_left = f(left);
  }
  at = 0.5 * (lo + hi);
  return std::min(f(at), std::min(f(0.0), f(1.0)));
}

// The smallest F over the feature a triangle claimed, exactly: over the face's plane (where the
// scaled particle touches it, which the claim says is inside), along the edge, or at the vertex.
double claimed_feature_minimum(const HostMesh& m, const PosedSuperquadric& p, int triangle,
                               int feature, bool& inside) {
  const auto& t = m.triangles[triangle];
  const Vec3 v[3] = {m.points[t[0]], m.points[t[1]], m.points[t[2]]};
  inside = true;
  if (feature == 0) {
    const Vec3 n = unit(cross(v[1] - v[0], v[2] - v[0]));
    const Vec3 towards = dot(p.centre - v[0], n) >= 0 ? n : -n;
    const Vec3 x = support_point_world(p, -towards);
    const Vec3 minimiser =
        p.centre + (dot(p.centre - v[0], towards) / dot(p.centre - x, towards)) * (x - p.centre);
    // Barycentric coordinates of the minimiser (book Eqs. 2.14-2.19).
    const Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0], r = minimiser - v[0];
    const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
    const double det = d11 * d22 - d12 * d12;
    const double alpha = (d22 * dot(r, e1) - d12 * dot(r, e2)) / det;
    const double beta = (d11 * dot(r, e2) - d12 * dot(r, e1)) / det;
    const double margin = -1e-12; // the claim's ties on the edges
    inside = alpha >= margin && beta >= margin && alpha + beta <= 1 - margin;
    return shape_value(p.shape, p.to_local(minimiser));
  }
  if (feature <= 3) {
    const Vec3 u = p.to_local(v[feature - 1]), w = p.to_local(v[feature % 3]);
    double s = 0;
    const double smallest =
        golden_section_minimum([&](double t) { return shape_value(p.shape, u + t * (w - u)); }, s);
    inside = s > 1e-9 && s < 1 - 1e-9;
    return smallest;
  }
  return shape_value(p.shape, p.to_local(v[feature - 4]));
}

// Every case must be claimed once, by the feature holding the smallest F of the mesh surface:
// that feature's exact minimum must not lie above the sampled minimum of the whole mesh.
void expect_one_claim_at_the_minimum(const HostMesh& host,
                                     const std::vector<PosedSuperquadric>& cases,
                                     const std::vector<MeshResult>& results, const char* what) {
  std::map<int, int> features;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const MeshResult& r = results[i];
    ASSERT_EQ(r.claims, 1) << what << " case " << i;
    ASSERT_TRUE(finite(r.contact)) << what << " case " << i;
    bool inside = true;
    const double claimed = claimed_feature_minimum(host, cases[i], r.triangle, r.feature, inside);
    const double sampled = sampled_mesh_minimum(host, cases[i]);
    EXPECT_TRUE(inside) << what << " case " << i;
    // Rounding of F: 1e-14 relative.
    EXPECT_LE(claimed, sampled + 1e-14 * std::max(1.0, std::fabs(sampled)))
        << what << " case " << i << " feature " << r.feature;
    // Touching exactly when some sampled wall point is inside (samples miss by < 1e-3 in F).
    if (sampled < -1e-3) {
      EXPECT_EQ(r.touching, 1) << what << " case " << i;
    }
    if (claimed > 0) {
      EXPECT_EQ(r.touching, 0) << what << " case " << i;
    }
    if (r.touching) {
      EXPECT_GT(r.contact.geometry.overlap, 0.0);
    }
    ++features[r.feature == 0 ? 0 : (r.feature <= 3 ? 1 : 2)];
  }
  std::printf("%s: %zu cases, face %d, edge %d, vertex %d\n", what, cases.size(), features[0],
              features[1], features[2]);
  EXPECT_GT(features[0], 0);
  EXPECT_GT(features[1], 0);
}

// Two triangles meeting at a convex ridge along y, sloping down at `slope` on either side.
HostMesh ridge_mesh(double slope, Quat frame) {
  HostMesh m;
  const double x = 1.5 * std::cos(slope), z = -1.5 * std::sin(slope);
  m.points = {rotate(frame, Vec3{0, -1, 0}), rotate(frame, Vec3{0, 1, 0}),
              rotate(frame, Vec3{-x, 0, z}), rotate(frame, Vec3{x, 0, z})};
  m.triangles = {{0, 1, 2}, {1, 0, 3}};
  for (const auto& t : m.triangles)
    m.normals.push_back(
        unit(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]])));
  return m;
}

// Centres over the mesh, above every face plane, low enough near the top to touch it.
std::vector<PosedSuperquadric> sweep_over(const HostMesh& m, Quat frame, const Particle& particle,
                                          double top_overlap, std::mt19937_64& rng) {
  std::vector<PosedSuperquadric> cases;
  const Quat q = frame * particle.q;
  const Vec3 up = rotate(frame, Vec3{0, 0, 1});
  const double reach = -dot(support_point_world(pose(particle.shape, Vec3{0, 0, 0}, q), -up), up);
  for (int i = 0; i <= 40; ++i)
    for (double y : {0.0, 0.37, 0.93, 1.05}) {
      const double x = -0.8 + 1.6 * i / 40;
      for (int turn = 0; turn < 2; ++turn) {
        const double jitter = turn ? uniform(rng, -0.05, 0.05) : 0.0;
        Vec3 centre = rotate(frame, Vec3{x, y + jitter, reach - top_overlap});
        for (std::size_t t = 0; t < m.triangles.size(); ++t) { // keep above every face plane
          const Vec3 n = m.normals[t], a = m.points[m.triangles[t][0]];
          const Vec3 outward = dot(n, up) > 0 ? n : -n;
          const double height = dot(centre - a, outward);
          if (height < 1e-3)
            centre += (1e-3 - height) / dot(up, outward) * up;
        }
        cases.push_back(pose(particle.shape, centre, q));
      }
    }
  return cases;
}

TEST(SuperquadricWall, ConvexRidgeGivesOneContact) {
  std::mt19937_64 rng(23);
  for (double slope : {0.35, 0.8}) {
    const Quat frame = slope > 0.5 ? random_rotation(rng) : Quat{};
    const HostMesh host = ridge_mesh(slope, frame);
    const DeviceMesh mesh = upload(host, false);
    std::vector<PosedSuperquadric> cases;
    for (const Particle& particle : test_particles(rng, slope < 0.5))
      for (const PosedSuperquadric& p : sweep_over(host, frame, particle, 0.03, rng))
        cases.push_back(p);
    const auto results = run_on_device<MeshResult>(cases, MeshContactsOfParticle{mesh});
    expect_one_claim_at_the_minimum(host, cases, results, "ridge");
  }
}

// A hexagonal pyramid: six triangles around a convex apex.
HostMesh pyramid_mesh(Quat frame) {
  HostMesh m;
  m.points.push_back(rotate(frame, Vec3{0, 0, 0}));
  for (int k = 0; k < 6; ++k)
    m.points.push_back(rotate(frame, Vec3{std::cos(k * pi / 3), std::sin(k * pi / 3), -0.4}));
  for (int k = 0; k < 6; ++k)
    m.triangles.push_back({0, 1 + k, 1 + (k + 1) % 6});
  for (const auto& t : m.triangles)
    m.normals.push_back(
        unit(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]])));
  return m;
}

TEST(SuperquadricWall, ConvexVertexGivesOneContact) {
  std::mt19937_64 rng(29);
  for (int variant = 0; variant < 2; ++variant) {
    const Quat frame = variant ? random_rotation(rng) : Quat{};
    const HostMesh host = pyramid_mesh(frame);
    const DeviceMesh mesh = upload(host, true); // the apex has six neighbours: needs its ring
    std::vector<PosedSuperquadric> cases;
    for (const Particle& particle : test_particles(rng, variant == 0))
      for (const PosedSuperquadric& p : sweep_over(host, frame, particle, 0.03, rng))
        cases.push_back(p);
    const auto results = run_on_device<MeshResult>(cases, MeshContactsOfParticle{mesh});
    expect_one_claim_at_the_minimum(host, cases, results, "pyramid");
    // Centred over the apex, an aligned particle touches the vertex.
    if (variant == 0) {
      EXPECT_GE(results[2 * 4 * 20].feature, 4);
    }
  }
}

// --- Cylinder
// -------------------------------------------------------------------------------------------

struct CylinderCase {
  PosedSuperquadric particle;
  Vec3 axis_point, axis;
  double radius;
};

struct CylinderContactOfCase {
  KOKKOS_INLINE_FUNCTION SurfaceWallContact operator()(const CylinderCase& c) const {
    return surface_inside_cylinder_contact(c.particle, c.axis_point, c.axis, c.radius);
  }
};

double sampled_distance_from_axis(const CylinderCase& c) {
  const PosedSuperquadric& p = c.particle;
  return sampled_surface_maximum(p.shape, [&](Vec3 x) {
    const Vec3 r = p.to_world(x) - c.axis_point;
    return norm(r - dot(r, c.axis) * c.axis);
  });
}

TEST(SuperquadricWall, InsideCylinderMatchesBruteForce) {
  std::mt19937_64 rng(31);
  const std::vector<Particle> particles = {
      {make_superquadric(0.2, 0.2, 0.2, 16, 16), Quat{}}, // a face against the wall
      {make_superquadric(0.2, 0.2, 0.2, 16, 16), axis_angle({0, 0, 1}, 0.25 * pi)}, // an edge
      {make_superquadric(0.1, 0.1, 0.4, 8, 2), Quat{}},                          // along the axis
      {make_superquadric(0.1, 0.1, 0.4, 8, 2), axis_angle({1, 0, 0}, 0.5 * pi)}, // tangential
      {make_superquadric(0.1, 0.1, 0.4, 8, 2), axis_angle({0, 1, 0}, 0.5 * pi)}, // radial
      {make_superquadric(0.4, 0.1, 0.25, 2, 2), Quat{}},                         // flat side
      {make_superquadric(0.3, 0.2, 0.1, 4, 10), Quat{}},
  };
  std::vector<CylinderCase> cases;
  for (double radius : {1.0, 0.6, 5.0})
    for (int variant = 0; variant < 4; ++variant)
      for (const Particle& particle : particles) {
        const Quat frame = variant == 0 ? Quat{} : random_rotation(rng);
        const Vec3 axis = rotate(frame, Vec3{0, 0, 1}), axis_point{0.1, -0.2, 0.3};
        const Quat q = frame * (variant < 2 ? particle.q : random_rotation(rng));
        const Vec3 out = rotate(frame, Vec3{1, 0, 0});
        // The centre where the particle's reach along `out` sits 0.02 beyond the wall.
        const double reach =
            dot(support_point_world(pose(particle.shape, Vec3{0, 0, 0}, q), out), out);
        const Vec3 centre = axis_point + (radius + 0.02 - reach) * out + 0.7 * axis;
        cases.push_back({pose(particle.shape, centre, q), axis_point, axis, radius});
      }
  // The particle centred on the axis of a narrow tube: every direction is a candidate.
  cases.push_back(
      {pose(make_superquadric(0.3, 0.1, 0.1, 4, 4), Vec3{0, 0, 0}, axis_angle({0, 0, 1}, 0.3)),
       Vec3{0, 0, 0}, Vec3{0, 0, 1}, 0.2});
  const auto contacts = run_on_device<SurfaceWallContact>(cases, CylinderContactOfCase{});
  double worst = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const SurfaceWallContact& c = contacts[i];
    ASSERT_TRUE(finite(c)) << i;
    ASSERT_TRUE(c.geometry.touching) << i;
    const double size = largest_semi_axis(cases[i].particle.shape);
    const double sampled = sampled_distance_from_axis(cases[i]) - cases[i].radius;
    worst = std::max(worst, std::fabs(c.geometry.overlap - sampled) / size);
    // The normal points from the wall towards the axis, perpendicular to it.
    EXPECT_LT(std::fabs(dot(c.geometry.normal, cases[i].axis)), 4e-15); // ulps of rotated axes
    const Vec3 r = c.geometry.point - cases[i].axis_point;
    const Vec3 radial = r - dot(r, cases[i].axis) * cases[i].axis;
    EXPECT_NEAR(norm(radial), cases[i].radius + 0.5 * c.geometry.overlap, 1e-14) << i;
  }
  // The golden-section angle is exact to 1e-9 rad, where the reach is flat to 1e-18 m; the
  // zoomed sampling of the brute force reaches 1e-12 of the size (as for the plane).
  EXPECT_LT(worst, 1e-12);
  std::printf("cylinder: |overlap - sampled| %.2e of the size\n", worst);
}

// --- Degenerate input
// --------------------------------------------------------------------------------

struct DegenerateCase {
  PosedSuperquadric particle;
  Vec3 a, b, c;
  int kind; // 0 support of (a), 1 plane (a, b), 2 triangle, 3 edge ab, 4 vertex a, 5 cylinder
};

struct DegenerateOfCase {
  KOKKOS_INLINE_FUNCTION SurfaceWallContact operator()(const DegenerateCase& d) const {
    const PosedSuperquadric& p = d.particle;
    switch (d.kind) {
    case 0: {
      SurfaceWallContact c;
      c.deepest_point = superquadric_support_point(p.shape, d.a);
      return c;
    }
    case 1:
      return surface_plane_contact(p, d.a, d.b);
    case 2:
      return surface_triangle_contact(p, d.a, d.b, d.c, isolated_triangle(d.a, d.b, d.c));
    case 3:
      return surface_edge_contact(p, d.a, d.b, Vec3{0, 0, 1}, 1);
    case 4:
      return surface_vertex_contact(p, d.a, Vec3{0, 0, 1}, 4);
    default:
      return surface_inside_cylinder_contact(p, d.a, d.b, d.c.x);
    }
  }
};

TEST(SuperquadricWall, DegenerateInputGivesNoNaN) {
  std::vector<DegenerateCase> cases;
  for (const SuperquadricShape& s :
       {make_superquadric(0.2, 0.2, 0.2, 16, 16), make_superquadric(0.1, 0.3, 0.05, 2, 16),
        make_superquadric(1e-3, 2e-3, 5e-4, 16, 2), make_superquadric(0.2, 0.1, 0.3, 2, 2)}) {
    const PosedSuperquadric at_origin = pose(s, Vec3{0, 0, 0}, Quat{});
    const PosedSuperquadric far = pose(s, Vec3{1e4, -1e4, 1e4}, axis_angle({1, 2, 3}, 1));
    for (Vec3 d : {Vec3{0, 0, 0}, Vec3{1e-310, 0, 0}, Vec3{0, 0, -1e-300}, Vec3{1, 1e-310, 0}})
      cases.push_back({at_origin, d, {}, {}, 0});
    const Vec3 up{0, 0, 1}, x1{1, 0, 0}, y1{0, 1, 0};
    cases.push_back({at_origin, {0, 0, 0}, up, {}, 1}); // centre on the plane
    cases.push_back({far, {0, 0, 0}, up, {}, 1});       // far away
    cases.push_back({at_origin, {0, 0, 0}, x1, y1, 2}); // centre on a vertex, in the plane
    cases.push_back({at_origin, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 2}); // centre on the face
    cases.push_back({far, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 2});
    cases.push_back({at_origin, -1.0 * x1, x1, {}, 3});        // edge through the centre
    cases.push_back({at_origin, {0, 0, 0}, {0, 0, 0}, {}, 3}); // zero-length edge
    cases.push_back({at_origin, {0, 0, 0}, {}, {}, 4});        // vertex at the centre
    cases.push_back({far, {0, 0, 0}, x1, {}, 3});
    cases.push_back({at_origin, {0, 0, 0}, up, {0.01, 0, 0}, 5}); // centred in a thin tube
    cases.push_back({at_origin, {0, 0, 0}, up, {10, 0, 0}, 5});   // far from a wide drum
  }
  const auto contacts = run_on_device<SurfaceWallContact>(cases, DegenerateOfCase{});
  for (std::size_t i = 0; i < cases.size(); ++i)
    EXPECT_TRUE(finite(contacts[i])) << "case " << i << " kind " << cases[i].kind;
}

} // namespace
} // namespace kdem
