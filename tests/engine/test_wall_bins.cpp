// The grids over mesh walls (kernels/wall_bins.hpp): the cell of a point must list every triangle
// within reach of it, in ascending order, and the binned candidate list of the wall broad phase
// must be the one that testing every element gives, entry for entry.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "mesh_test_support.hpp"
#include "scene_builders.hpp"
#include "src/host_copy.hpp"
#include "src/wall_tables.hpp"

namespace kdem::testing {
namespace {

// A closed sphere of radius `r` about `centre` as `rings` x `segments` latitude-longitude
// triangles (fans at the poles): 2 segments (rings - 1) triangles, sizes varying with latitude.
std::vector<Triangle> sphere_mesh(const Vec3d& centre, double r, int rings, int segments) {
  auto point = [&](int ring, int segment) {
    const double theta = M_PI * ring / rings, phi = 2 * M_PI * segment / segments;
    return Vec3d{centre[0] + r * std::sin(theta) * std::cos(phi),
                 centre[1] + r * std::sin(theta) * std::sin(phi), centre[2] + r * std::cos(theta)};
  };
  const Vec3d top{centre[0], centre[1], centre[2] + r}, bottom{centre[0], centre[1], centre[2] - r};
  std::vector<Triangle> t;
  for (int s = 0; s < segments; ++s) {
    const int next = (s + 1) % segments;
    t.push_back(Triangle{top, point(1, s), point(1, next)});
    for (int ring = 1; ring + 1 < rings; ++ring) {
      t.push_back(Triangle{point(ring, s), point(ring + 1, s), point(ring + 1, next)});
      t.push_back(Triangle{point(ring, s), point(ring + 1, next), point(ring, next)});
    }
    t.push_back(Triangle{bottom, point(rings - 1, next), point(rings - 1, s)});
  }
  return t;
}

Vec3 vertex(const std::array<double, 9>& g, int v) {
  return {g[3 * v], g[3 * v + 1], g[3 * v + 2]};
}

// The elements of `table` within r of p, by testing all of them.
std::vector<int> triangles_within(const WallElementTable& table, Vec3 p, double r) {
  std::vector<int> near;
  for (int e = 0; e < int(table.kind.size()); ++e) {
    const auto& g = table.geometry[e];
    if (triangle_query(vertex(g, 0), vertex(g, 1), vertex(g, 2), p).signed_distance < r)
      near.push_back(e);
  }
  return near;
}

// 4800 triangles of edges 2.6 to 16 mm; points in and around the grid (the box of the sphere
// grown by the reach), half of them within 2 cm of the surface, reaches of 0.2 to 1 times the
// grid's. The cell must list every triangle the brute force finds, ascending, and must list far
// fewer than all (it is a broad phase).
TEST(WallBins, TheCellOfAPointListsEveryTriangleWithinReach) {
  MeshFolder folder;
  const double reach = 0.012;
  const WallElementTable table = build_wall_elements(
      {mesh_wall("steel", folder.write("ball", sphere_mesh({0, 0, 0}, 0.1, 41, 60)))}, {-1, -1, -1},
      {1, 1, 1});
  ASSERT_EQ(table.kind.size(), 4800u);
  const WallBinTable bins = bin_wall_elements(table, 1, reach);
  ASSERT_TRUE(bins.walls[0].binned());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-0.125, 0.125), fraction(0.2, 1.0),
      depth(-0.02, 0.02);
  std::normal_distribution<double> gauss;
  long listed = 0, with_neighbours = 0;
  for (int k = 0; k < 4000; ++k) {
    Vec3 p{coordinate(rng), coordinate(rng), coordinate(rng)};
    if (k % 2 == 0) { // near the surface
      const Vec3 d{gauss(rng), gauss(rng), gauss(rng)};
      p = ((0.1 + depth(rng)) / norm(d)) * d;
    }
    const double r = fraction(rng) * reach;
    std::vector<int> candidates;
    for_each_candidate_on_host(bins, 0, p, r, [&](int e) { candidates.push_back(e); });
    ASSERT_TRUE(std::is_sorted(candidates.begin(), candidates.end()));
    ASSERT_EQ(std::adjacent_find(candidates.begin(), candidates.end()), candidates.end());
    const std::vector<int> near = triangles_within(table, p, r);
    ASSERT_TRUE(std::includes(candidates.begin(), candidates.end(), near.begin(), near.end()))
        << "point " << p.x << " " << p.y << " " << p.z << ", reach " << r;
    listed += long(candidates.size());
    with_neighbours += near.empty() ? 0 : 1;
  }
  EXPECT_GT(with_neighbours, 800); // the test sees points near the surface
  EXPECT_LT(double(listed) / 4000, 0.03 * 4800);
  // Beyond the grid's reach the lookup gives every element.
  int all = 0;
  for_each_candidate_on_host(bins, 0, Vec3{0, 0, 0.1}, 1.5 * reach, [&](int) { ++all; });
  EXPECT_EQ(all, 4800);
}

WallMotion moving(Vec3 pivot, Vec3 velocity, Vec3 omega) {
  WallMotion m;
  m.pivot = pivot;
  m.velocity = velocity;
  m.omega = omega;
  return m;
}

std::vector<int> host_ints(const IndexView& view) {
  return flatten_to_host(view, int(view.extent(0)));
}

// Planes and a cylinder around a turning, travelling mesh ball, 3000 spheres of radii 1 to 8 mm
// scattered around it: the binned list equals, entry for entry, the list from every element (the
// same lookup with its grid switched off); a mesh binned for a smaller reach than some particles
// need gives those particles every element.
TEST(WallBins, BinnedCandidateListIsTheListFromEveryElement) {
  MeshFolder folder;
  const std::string ball = folder.write("ball", sphere_mesh({0, 0, 0}, 0.1, 31, 48));
  std::vector<WallConfig> configs = {plane_wall("steel", {0, 0, -0.12}, {0, 0, 1}),
                                     mesh_wall("steel", ball), drum_about_y("steel", 10)};
  const WallElementTable table = build_wall_elements(configs, {-1, -1, -1}, {1, 1, 1});
  WallSet walls;
  walls.wall_count = 3;
  walls.elements = upload_wall_elements(table);
  walls.motion = upload<WallMotion>(
      "motion", std::vector<WallMotion>{moving({}, {}, {}),
                                        moving({0.01, 0, 0}, {0.02, -0.01, 0.03}, {0.4, 1.1, -0.7}),
                                        moving({}, {}, {})});
  walls.pose = DeviceView<WallPose*>("pose", 3);
  update_wall_poses(walls, 0.3);

  const int n = 3000;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(-0.14, 0.14), size(1e-3, 8e-3);
  std::vector<double> position, radius;
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a)
      position.push_back(coordinate(rng) + (a == 0 ? 0.006 : a == 1 ? -0.003 : 0.009));
    radius.push_back(size(rng));
  }
  ParticleViews p;
  p.allocate(n);
  p.position = view_from_host<Vec3View>("position", position, 3);
  p.radius = view_from_host<ScalarView>("radius", radius, 1);
  const double skin = 5e-4;
  const int no_sphere_rows = -1; // every particle gets every element within its reach

  auto candidates = [&](const WallBinTable& bins) {
    upload_wall_lookup(walls, bins);
    const WallContactList list = build_wall_contact_list(p, walls, skin, no_sphere_rows);
    return std::make_pair(host_ints(list.row_start), host_ints(list.element));
  };
  WallBinTable every_element = bin_wall_elements(table, 3, 8e-3 + skin);
  for (WallLookup& w : every_element.walls)
    w.cell_size = 0;
  const auto reference = candidates(every_element);
  ASSERT_GT(reference.second.size(), 1000u); // many particles near the ball and the walls
  EXPECT_EQ(candidates(bin_wall_elements(table, 3, 8e-3 + skin)), reference);
  EXPECT_EQ(candidates(bin_wall_elements(table, 3, 4e-3)), reference);
}

// The device tables hold every vertex ring of the host table (the neighbours that a body's
// vertex contact descends towards): a rewrite of the upload once left them out, and superquadrics
// touching a mesh vertex read through a null pointer (found by the checkpoint_reader fuzz target).
TEST(WallBins, UploadedTablesHoldTheVertexRings) {
  MeshFolder folder;
  const std::string ball = folder.write("ball", sphere_mesh({0, 0, 0}, 0.1, 7, 12));
  const WallElementTable table =
      build_wall_elements({mesh_wall("steel", ball)}, {-1, -1, -1}, {1, 1, 1});
  ASSERT_GT(table.vertex_ring.size(), 0u);
  const WallElements elements = upload_wall_elements(table);
  ASSERT_EQ(elements.vertex_ring.extent(0), table.vertex_ring.size());
  const auto ring = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), elements.vertex_ring);
  for (std::size_t k = 0; k < table.vertex_ring.size(); ++k) {
    EXPECT_EQ(ring(k).x, table.vertex_ring[k][0]) << k;
    EXPECT_EQ(ring(k).y, table.vertex_ring[k][1]) << k;
    EXPECT_EQ(ring(k).z, table.vertex_ring[k][2]) << k;
  }
  EXPECT_EQ(host_ints(elements.vertex_ring_start), table.vertex_ring_start);
}

// A reach whose grid box overflows the doubles (found by the checkpoint_reader fuzz target: a
// checkpoint with radii near the largest double) leaves the mesh without a grid, every
// element a candidate, instead of converting an infinite cell count to an integer.
TEST(WallBins, AReachBeyondTheDoublesLeavesTheMeshUnbinned) {
  MeshFolder folder;
  const std::string ball = folder.write("ball", sphere_mesh({0, 0, 0}, 0.1, 7, 12));
  const WallElementTable table =
      build_wall_elements({mesh_wall("steel", ball)}, {-1, -1, -1}, {1, 1, 1});
  const WallBinTable bins = bin_wall_elements(table, 1, 1e308);
  ASSERT_EQ(bins.walls.size(), 1u);
  EXPECT_FALSE(bins.walls[0].binned());
  const CandidateSource source = candidate_source(bins.walls[0], Vec3{5, 5, 5}, 1e308);
  EXPECT_TRUE(source.every_element);
  const WallBinTable normal = bin_wall_elements(table, 1, 0.01);
  EXPECT_TRUE(normal.walls[0].binned());
}

// A valley along y at x = x0 (concave edge), faces rising at 30 degrees to both sides.
std::vector<Triangle> valley(double x0, double h, double z) {
  const double rise = h * std::tan(M_PI / 6);
  return {Triangle{Vec3d{x0, -h, z}, Vec3d{x0 - h, 0, z + rise}, Vec3d{x0, h, z}},
          Triangle{Vec3d{x0, h, z}, Vec3d{x0 + h, 0, z + rise}, Vec3d{x0, -h, z}}};
}

// For each sphere (centre, radius), the triangles whose claimed feature it touches (at most 8),
// by testing every triangle of every wall at its pose.
struct TouchedTriangles {
  WallElements el;
  DeviceView<WallPose*> pose;
  Vec3View centre;
  ScalarView radius;
  DeviceView<int* [8]> touched;
  IndexView count;

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    int n = 0;
    const Vec3 x = load3(centre, i);
    for (int e = 0; e < el.count; ++e) {
      if (el.kind(e) != triangle_element)
        continue;
      const Vec3 p = pose(el.wall(e)).to_reference(x);
      bool applies = false;
      const SurfaceQuery q = claimed_triangle_feature(el, e, p, 1e300, applies);
      if (applies && sphere_on_surface(p, radius(i), q.signed_distance, q.free_normal).touching &&
          n < 8)
        touched(i, n++) = e;
    }
    count(i) = n;
  }
};

// Spheres of radius 1 to 3 mm near a fine flat grid, a latitude-longitude ball (convex edges and
// vertices, fans at the poles) and a valley (a concave edge), from 0.3 r inside to r outside
// their surfaces, each with `drifts` points up to one skin away from its centre.
struct SpheresNearMeshes {
  WallSet walls;
  ParticleViews p;
  Vec3View drifted;
  ScalarView drifted_radius;
  int spheres = 3000, drifts = 4;
};

SpheresNearMeshes spheres_near_meshes(const MeshFolder& folder, double skin) {
  SpheresNearMeshes s;
  const std::vector<WallConfig> configs = {
      mesh_wall("steel", folder.write("grid", flat_grid(0.05, -0.12, 25))),
      mesh_wall("steel", folder.write("ball", sphere_mesh({0, 0, 0}, 0.1, 31, 48))),
      mesh_wall("steel", folder.write("valley", valley(0.2, 0.03, 0)))};
  const WallElementTable table = build_wall_elements(configs, {-1, -1, -1}, {1, 1, 1});
  s.walls.wall_count = 3;
  s.walls.elements = upload_wall_elements(table);
  s.walls.motion = upload<WallMotion>("motion", std::vector<WallMotion>(3));
  s.walls.pose = DeviceView<WallPose*>("pose", 3);
  update_wall_poses(s.walls, 0);
  upload_wall_lookup(s.walls, bin_wall_elements(table, 3, 3e-3 + skin));

  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1), size(1e-3, 3e-3);
  std::normal_distribution<double> gauss;
  std::vector<double> centre, drifted, radius, drifted_radius;
  for (int i = 0; i < s.spheres; ++i) {
    const double r = size(rng), gap = (1.3 * unit(rng) - 0.3) * r; // surface to centre
    Vec3 c;
    if (i % 3 == 0) {
      c = {0.1 * unit(rng) - 0.05, 0.1 * unit(rng) - 0.05, -0.12 + gap};
    } else if (i % 3 == 1) {
      const Vec3 d{gauss(rng), gauss(rng), gauss(rng)};
      c = ((0.1 + gap) / norm(d)) * d;
    } else {
      const double x = 0.06 * unit(rng) - 0.03;
      c = {0.2 + x, 0.04 * unit(rng) - 0.02, std::fabs(x) * std::tan(M_PI / 6) + gap};
    }
    centre.insert(centre.end(), {c.x, c.y, c.z});
    radius.push_back(r);
    for (int k = 0; k < s.drifts; ++k) {
      const Vec3 d{gauss(rng), gauss(rng), gauss(rng)};
      const Vec3 moved = c + (skin * std::cbrt(unit(rng)) / norm(d)) * d;
      drifted.insert(drifted.end(), {moved.x, moved.y, moved.z});
      drifted_radius.push_back(r);
    }
  }
  s.p.allocate(s.spheres);
  s.p.position = view_from_host<Vec3View>("position", centre, 3);
  s.p.radius = view_from_host<ScalarView>("radius", radius, 1);
  s.drifted = view_from_host<Vec3View>("drifted", drifted, 3);
  s.drifted_radius = view_from_host<ScalarView>("drifted_radius", drifted_radius, 1);
  return s;
}

// Spheres near a fine flat grid, a latitude-longitude ball (convex edges and vertices, fans at
// the poles) and a valley (a concave edge): for each, points up to one skin away (where its centre
// may drift before the lists are built again). Every triangle whose claimed feature a sphere
// touches at such a point must be in the sphere's list from its centre, which leaves out the
// triangles that cannot claim it; and the list must be shorter than that of all triangles
// within reach (the filter does something).
TEST(WallBins, SphereListsKeepEveryTriangleThatMayClaimThemWithinTheSkin) {
  MeshFolder folder;
  const double skin = 4e-4;
  const SpheresNearMeshes s = spheres_near_meshes(folder, skin);
  const WallSet& walls = s.walls;
  const ParticleViews& p = s.p;
  const int spheres = s.spheres, drifts = s.drifts;
  const WallContactList claims = build_wall_contact_list(p, walls, skin, 0);
  const WallContactList within_reach = build_wall_contact_list(p, walls, skin, -1);

  TouchedTriangles touched{walls.elements,
                           walls.pose,
                           s.drifted,
                           s.drifted_radius,
                           DeviceView<int* [8]>("touched", spheres * drifts),
                           IndexView("touched_count", spheres * drifts)};
  Kokkos::parallel_for("kdem::test_touched_triangles", RangePolicy(0, spheres * drifts), touched);
  const std::vector<int> row_start = host_ints(claims.row_start);
  const std::vector<int> element = host_ints(claims.element);
  const std::vector<int> count = host_ints(touched.count);
  const std::vector<int> touched_by = flatten_to_host(touched.touched, spheres * drifts);
  long touching = 0;
  for (int i = 0; i < spheres; ++i)
    for (int k = 0; k < drifts; ++k) {
      const int m = i * drifts + k;
      touching += count[m];
      for (int c = 0; c < count[m]; ++c) {
        const int e = touched_by[8 * m + c];
        EXPECT_TRUE(std::binary_search(element.begin() + row_start[i],
                                       element.begin() + row_start[i + 1], e))
            << "sphere " << i << " drifted by " << k << " touches triangle " << e;
      }
    }
  EXPECT_GT(touching, spheres); // many of the drifted spheres touch
  EXPECT_LT(claims.entry_count, 0.6 * within_reach.entry_count);
}

// Compares, for each sphere of spheres_near_meshes and each of its triangle entries, the contact
// through the entry's face certificate with the contact from the full claim tests, at the
// sphere's centre (which leaves a certificate where a face claims it) and then at each drifted
// point (where the certificate is used if it holds). Counts differences and uses.
struct CertifiedAgainstFull {
  WallElements el;
  DeviceView<WallPose*> pose;
  WallContactList list;
  SphereWallContact at_centre, at_drifted;
  int drifts;
  IndexView differences, certified_uses;

  KOKKOS_INLINE_FUNCTION static bool same(const WallContactGeometry& a,
                                          const WallContactGeometry& b) {
    const ContactGeometry &g = a.geometry, &h = b.geometry;
    return g.touching == h.touching &&
           (!g.touching ||
            (g.overlap == h.overlap && g.normal.x == h.normal.x && g.normal.y == h.normal.y &&
             g.normal.z == h.normal.z && g.point.x == h.point.x && g.point.y == h.point.y &&
             g.point.z == h.point.z));
  }

  KOKKOS_INLINE_FUNCTION void compare(const SphereWallContact& contact, int m, int e, int k,
                                      const WallPose& wall, int i) const {
    const Vec3 p = wall.to_reference(load3(contact.position, m));
    if (triangle_out_of_reach(list.triangle_corners, k, p, contact.radius(m)))
      return; // the kernel asks no more of such an entry
    const double margin = list.face_certificate(k, 3);
    const Vec3 at{list.face_certificate(k, 0), list.face_certificate(k, 1),
                  list.face_certificate(k, 2)};
    if (margin > 0 && norm2(p - at) < 0.25 * margin * margin)
      ++certified_uses(i);
    const TriangleEntry entry{list.triangle_corners, list.face_certificate, k};
    if (!same(contact(m, e, wall, entry), contact(m, e, wall)))
      ++differences(i);
  }

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    for (int k = list.row_start(i); k < list.row_start(i + 1); ++k) {
      const int e = list.element(k);
      if (el.kind(e) != triangle_element)
        continue;
      const WallPose wall = pose(el.wall(e));
      compare(at_centre, i, e, k, wall, i);
      for (int d = 0; d < drifts; ++d)
        compare(at_drifted, i * drifts + d, e, k, wall, i);
    }
  }
};

// A face certificate gives the contact the full claim tests give, bit for bit, and is used:
// 3000 spheres near a flat grid, a ball and a valley, each at its centre and at four points up to
// one skin away. The certificate is a shortcut of the sphere-wall kernel on fine meshes (a face
// that claimed a centre claims every point within half its margin, without loading the
// triangle's row); a difference would change contacts.
TEST(WallBins, FaceCertificatesGiveTheContactOfTheFullClaimTests) {
  MeshFolder folder;
  const double skin = 4e-4;
  const SpheresNearMeshes s = spheres_near_meshes(folder, skin);
  WallContactList list = build_wall_contact_list(s.p, s.walls, skin, 0);
  allocate_wall_contact_results(list, s.walls.elements);
  CertifiedAgainstFull check{s.walls.elements,
                             s.walls.pose,
                             list,
                             SphereWallContact{s.walls.elements, s.p.position, s.p.radius},
                             SphereWallContact{s.walls.elements, s.drifted, s.drifted_radius},
                             s.drifts,
                             IndexView("differences", s.spheres),
                             IndexView("certified_uses", s.spheres)};
  Kokkos::parallel_for("kdem::test_certified_against_full", RangePolicy(0, s.spheres), check);
  long differences = 0, uses = 0;
  for (int n : host_ints(check.differences))
    differences += n;
  for (int n : host_ints(check.certified_uses))
    uses += n;
  EXPECT_EQ(differences, 0);
  EXPECT_GT(uses, 1000) << "the certificates were hardly used: the test would not see them";
}

} // namespace
} // namespace kdem::testing
