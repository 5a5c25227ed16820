// The normal-cone caps of the dilated cores' sphere trees: a node pair whose caps cannot hold a
// contact direction is skipped. Pruning may only skip face pairs that make no contact, so the
// walks with and without caps must give the same contacts, bit for bit and in the same order,
// for every shape the family meets (fine lattices, non-convex lattices with saddle vertices and
// reflex edges, flat-faced boxes, sharp tetrahedra, a concave prism), against another core, a
// sphere and a plane, with the default slack and with a fade.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "dilated_test_support.hpp"
#include "src/core_builders.hpp"

namespace kdem::testing {
namespace {

test::CoreMesh lattice(double a, double b, double c, double n, int nodes) {
  const TriangleMesh m = superquadric_core(a, b, c, n, n, nodes);
  test::CoreMesh mesh;
  for (const auto& p : m.points)
    mesh.points.push_back(Vec3{p[0], p[1], p[2]});
  mesh.triangles = m.triangles;
  return mesh;
}

DilatedCore without_caps(DilatedCore core) {
  core.caps_reach = -1;
  return core;
}

void expect_same_contacts(const test::ContactList& pruned, const test::ContactList& all,
                          const std::string& where) {
  ASSERT_EQ(pruned.contacts.size(), all.contacts.size()) << where;
  for (std::size_t c = 0; c < all.contacts.size(); ++c) {
    const FeatureContact &p = pruned.contacts[c], &a = all.contacts[c];
    EXPECT_EQ(p.feature_a, a.feature_a) << where << " contact " << c;
    EXPECT_EQ(p.feature_b, a.feature_b) << where << " contact " << c;
    EXPECT_EQ(p.overlap, a.overlap) << where << " contact " << c;
    EXPECT_EQ(p.cone_weight, a.cone_weight) << where << " contact " << c;
    EXPECT_EQ(p.normal.x, a.normal.x) << where << " contact " << c;
  }
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g;
  double q[4] = {g(rng), g(rng), g(rng), g(rng)};
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return rotation_matrix(Quat{q[0] / n, q[1] / n, q[2] / n, q[3] / n});
}

Vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> g;
  const Vec3 u{g(rng), g(rng), g(rng)};
  return (1.0 / norm(u)) * u;
}

struct Shape {
  const char* name;
  test::CoreMesh mesh;
  double radius;
};

std::vector<Shape> shapes() {
  return {{"ellipsoid lattice", lattice(1.0, 0.7, 0.5, 2, 200), 0.05},
          {"blocky lattice (saddles, reflex edges)", lattice(1.4, 1.0, 0.8, 3, 200), 0.1},
          {"box", test::box_mesh(1.0, 0.6, 0.4), 0.05},
          {"tetrahedron", test::tetrahedron_mesh(1.0), 0.01},
          {"U prism", test::u_prism_mesh(0.5, 0.6), 0.05}};
}

// B placed along a random direction from A at a random orientation, moved in from afar in
// steps of a quarter of the reach until the deepest contact of the unpruned walk exceeds
// `depth_fraction` of the reach, then bisected to that depth.
RelativePose touching_pose(const DilatedCore& a, const DilatedCore& b, std::mt19937& rng,
                           double depth_fraction) {
  RelativePose pose{random_rotation(rng), Vec3{}};
  const Vec3 u = random_direction(rng);
  const double reach = a.dilation() + b.dilation(), wanted = depth_fraction * reach;
  const auto deeper_than = [&](double t, double depth) {
    pose.translation = t * u;
    test::ContactList found;
    dilated_pair_contacts(a, b, pose, ConeSlack{}, found);
    return found.deepest() > depth;
  };
  const auto deep_enough = [&](double t) { return deeper_than(t, wanted); };
  const auto extent = [](const DilatedCore& c) {
    return norm(c.node(0).centre) + c.node(0).radius + c.dilation();
  };
  // A step moves the cores' distance by at most its length: steps of a quarter of the reach
  // cannot pass over the first contact, nor steps of half the wanted window over it.
  double out = extent(a) + extent(b), in = out;
  while (!deeper_than(in, 0.0) && in > 0)
    out = in, in -= 0.25 * reach;
  while (!deep_enough(in)) {
    out = in, in -= 0.5 * (reach - wanted);
    EXPECT_GT(in, 0.0) << "no contact along the way";
    if (!(in > 0))
      break;
  }
  for (int step = 0; step < 40; ++step) {
    const double middle = 0.5 * (in + out);
    (deep_enough(middle) ? in : out) = middle;
  }
  pose.translation = in * u;
  return pose;
}

int face_pairs_visited(const DilatedCore& a, const DilatedCore& b, const RelativePose& pose,
                       bool caps) {
  int pairs = 0;
  for_each_face_pair_near(
      a, b, pose, a.dilation() + b.dilation(), [&](int, int) { ++pairs; }, caps);
  return pairs;
}

TEST(DilatedConeCaps, PairContactsAreThoseOfTheFullWalk) {
  const std::vector<Shape> all = shapes();
  const ConeSlack faded = ConeSlack::of_angle(1e-6, 0.002);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> depth(0.02, 0.98);
  long pruned_pairs = 0, full_pairs = 0;
  for (const Shape& sa : all)
    for (const Shape& sb : all) {
      const DilatedCore a = test::core_of(sa.mesh, sa.radius),
                        b = test::core_of(sb.mesh, sb.radius);
      DilatedCore a_faded = a, b_faded = b;
      bound_normal_cones(a_faded, faded);
      bound_normal_cones(b_faded, faded);
      const DilatedCore a_full = without_caps(a), b_full = without_caps(b);
      for (int k = 0; k < 12; ++k) {
        const RelativePose pose = touching_pose(a_full, b_full, rng, depth(rng));
        const std::string where =
            std::string(sa.name) + " on " + sb.name + ", pose " + std::to_string(k);
        test::ContactList pruned, full, pruned_faded, full_faded;
        ASSERT_TRUE(dilated_pair_contacts(a, b, pose, ConeSlack{}, pruned));
        ASSERT_TRUE(dilated_pair_contacts(a_full, b_full, pose, ConeSlack{}, full));
        ASSERT_TRUE(dilated_pair_contacts(a_faded, b_faded, pose, faded, pruned_faded));
        ASSERT_TRUE(dilated_pair_contacts(a_full, b_full, pose, faded, full_faded));
        ASSERT_FALSE(full.contacts.empty()) << where;
        expect_same_contacts(pruned, full, where);
        expect_same_contacts(pruned_faded, full_faded, where + " (fade)");
        pruned_pairs += face_pairs_visited(a, b, pose, true);
        full_pairs += face_pairs_visited(a, b, pose, false);
      }
    }
  RecordProperty("face_pairs_with_caps", std::to_string(pruned_pairs));
  RecordProperty("face_pairs_without_caps", std::to_string(full_pairs));
  EXPECT_LT(pruned_pairs, full_pairs); // the caps do prune
}

TEST(DilatedConeCaps, CapsBoundForANarrowerSlackAreNotUsed) {
  // Caps bound for the default slack (reach 1e-6) hold no faded contact: with a fade they must
  // be ignored, and a walk given them still finds every contact.
  const DilatedCore core = test::core_of(lattice(1.0, 0.7, 0.5, 2, 200), 0.05);
  const ConeSlack faded = ConeSlack::of_angle(1e-6, 0.02);
  EXPECT_LT(core.cap_reach(), cone_reach(faded));
  std::mt19937 rng(5);
  for (int k = 0; k < 20; ++k) {
    const RelativePose pose = touching_pose(without_caps(core), without_caps(core), rng, 0.5);
    test::ContactList with_narrow_caps, full;
    dilated_pair_contacts(core, core, pose, faded, with_narrow_caps);
    dilated_pair_contacts(without_caps(core), without_caps(core), pose, faded, full);
    expect_same_contacts(with_narrow_caps, full, "pose " + std::to_string(k));
  }
}

TEST(DilatedConeCaps, SphereAndPlaneContactsAreThoseOfTheFullWalk) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> size(0.01, 0.5), unit(0.0, 1.0);
  for (const Shape& s : shapes()) {
    const DilatedCore core = test::core_of(s.mesh, s.radius), full = without_caps(core);
    for (int k = 0; k < 200; ++k) {
      const std::string where = std::string(s.name) + ", probe " + std::to_string(k);
      // A sphere moved in from far along a random direction until it overlaps by a random
      // fraction of the reach.
      const Vec3 u = random_direction(rng);
      const double radius = size(rng), depth = unit(rng) * (core.dilation() + radius);
      double lo = 0, hi = 10;
      for (int step = 0; step < 50; ++step) {
        test::ContactList found;
        dilated_sphere_contacts(full, (0.5 * (lo + hi)) * u, radius, ConeSlack{}, found);
        (found.deepest() > depth ? lo : hi) = 0.5 * (lo + hi);
      }
      test::ContactList pruned, all;
      ASSERT_TRUE(
          dilated_sphere_contacts(core, (0.5 * (lo + hi)) * u, radius, ConeSlack{}, pruned));
      ASSERT_TRUE(dilated_sphere_contacts(full, (0.5 * (lo + hi)) * u, radius, ConeSlack{}, all));
      expect_same_contacts(pruned, all, where + " (sphere)");
      // A plane of normal -u through a point of the core's reach.
      const Vec3 origin = (0.5 * (lo + hi) - radius) * u;
      test::ContactList plane_pruned, plane_all;
      ASSERT_TRUE(dilated_plane_contacts(core, origin, -1.0 * u, ConeSlack{}, plane_pruned));
      ASSERT_TRUE(dilated_plane_contacts(full, origin, -1.0 * u, ConeSlack{}, plane_all));
      expect_same_contacts(plane_pruned, plane_all, where + " (plane)");
    }
  }
}

TEST(DilatedConeCaps, LargestAngleOfARegionMatchesSampling) {
  // Regions of 1 to 6 random half-spaces of directions, against 200,000 directions spread
  // evenly over the sphere (about 0.008 rad apart): no sampled direction in the region lies
  // farther from the axis than the bound, and the farthest lies near it: within 0.01 rad (the
  // spacing) for nine regions in ten, within 0.05 rad for all (a thin tip of a region may hold no
  // sample near its end). Regions with too few samples to tell are skipped, and there must be
  // many of the rest.
  constexpr int samples = 200000;
  std::vector<Vec3> sphere;
  for (int k = 0; k < samples; ++k) {
    const double z = 1 - (2 * k + 1.0) / samples, rho = std::sqrt(1 - z * z);
    const double phi = k * 2.399963229728653;
    sphere.push_back(Vec3{rho * std::cos(phi), rho * std::sin(phi), z});
  }
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> limit(-0.6, 0.6);
  std::uniform_int_distribution<int> count(1, 6);
  int checked = 0, empty = 0, close = 0;
  for (int r = 0; r < 150; ++r) {
    dilated_build::DirectionRegion region;
    const int bounds = count(rng);
    for (int k = 0; k < bounds; ++k)
      region.push_back({random_direction(rng), limit(rng)});
    const Vec3 axis = random_direction(rng);
    const double least = dilated_build::least_cosine_from(axis, region);
    double sampled = 2;
    int inside = 0;
    for (const Vec3& d : sphere)
      if (dilated_build::in_region(d, region)) {
        ++inside;
        sampled = std::min(sampled, dot(d, axis));
      }
    if (least > 1) {
      ++empty;
      EXPECT_EQ(inside, 0) << "region " << r;
      continue;
    }
    if (inside < 100)
      continue;
    ++checked;
    const double bound = std::acos(std::max(-1.0, least));
    const double farthest = std::acos(std::max(-1.0, sampled));
    EXPECT_LE(farthest, bound + 1e-9) << "region " << r;
    EXPECT_GE(farthest, bound - 0.05) << "region " << r;
    close += farthest >= bound - 0.01 ? 1 : 0;
  }
  EXPECT_GE(checked, 60);
  EXPECT_GE(close, 0.9 * checked);
  RecordProperty("regions_checked", std::to_string(checked));
  RecordProperty("regions_empty", std::to_string(empty));
}

} // namespace
} // namespace kdem::testing
