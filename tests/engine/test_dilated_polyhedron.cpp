// Dilated polyhedra (book chapter 4): the core's construction and its checks, mass properties of
// core plus dilation against closed forms, and the contacts of cores with spheres, planes and
// each other against brute-force distances. Host code: the same header functions run on the
// device in the engine's kernels.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "shapes/dilated_polyhedron_properties.hpp"
#include "shapes/sphere.hpp"

#include "dilated_test_support.hpp"
#include "geometry_test_support.hpp"

namespace kdem::test {
namespace {

std::string build_error(CoreMesh m, double radius) {
  try {
    build_dilated_core(m.points, m.triangles, radius);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(DilatedCore, BoxHasItsFeaturesOwnersAndCones) {
  const DilatedCore core = core_of(box_mesh(1.0, 0.7, 0.4), 0.1);
  EXPECT_EQ(core.vertices.size(), 8u);
  EXPECT_EQ(core.edges.size(), 18u); // 12 box edges and 6 face diagonals
  EXPECT_EQ(core.faces.size(), 12u);
  for (const CoreEdge& e : core.edges)
    EXPECT_EQ(e.convex, 1);
  for (const CoreVertex& v : core.vertices) {
    EXPECT_EQ(v.convex, 1);
    EXPECT_GE(v.cone_count, 3);
    EXPECT_LT(v.owner, 12);
  }
  // Every face's vertices and edges name it or a lower face as owner.
  for (std::size_t f = 0; f < core.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(core.vertex(core.faces[f].vertex[k]).owner, int(f));
      EXPECT_LE(core.edge(core.faces[f].edge[k]).owner, int(f));
    }
  // A tree of 12 leaves: 23 nodes, each sphere holding its leaves' corners.
  EXPECT_EQ(core.nodes.size(), 23u);
  EXPECT_LE(sphere_tree_depth(core), 5);
}

TEST(DilatedCore, InwardMeshIsTurnedOutward) {
  CoreMesh m = box_mesh(1.0, 1.0, 1.0);
  for (auto& t : m.triangles)
    std::swap(t[1], t[2]);
  const DilatedCore core = core_of(m, 0.1);
  for (const CoreFace& f : core.faces) {
    const Vec3 centroid =
        (1.0 / 3.0) * (core.vertex(f.vertex[0]).position + core.vertex(f.vertex[1]).position +
                       core.vertex(f.vertex[2]).position);
    EXPECT_GT(dot(f.normal, centroid), 0);
  }
}

TEST(DilatedCore, BadMeshesAreRefusedWithTheReason) {
  CoreMesh open = box_mesh(1, 1, 1);
  open.triangles.pop_back();
  EXPECT_NE(build_error(open, 0.1).find("open"), std::string::npos) << build_error(open, 0.1);
  CoreMesh flipped = box_mesh(1, 1, 1);
  std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
  EXPECT_NE(build_error(flipped, 0.1).find("consistently oriented"), std::string::npos);
  // Two tetrahedra sharing one vertex: a closed surface, but not a manifold at that vertex.
  CoreMesh pinched = tetrahedron_mesh(1.0);
  const CoreMesh second = tetrahedron_mesh(1.0);
  for (int k = 1; k < 4; ++k)
    pinched.points.push_back(2.0 * second.points[0] - second.points[std::size_t(k)]);
  // The reflected tetrahedron's vertex 0 is shared; its others are 4, 5, 6 (orientation kept by
  // the point reflection through vertex 0).
  for (const auto& t : second.triangles) {
    std::array<int, 3> u;
    for (int k = 0; k < 3; ++k)
      u[k] = t[k] == 0 ? 0 : 3 + t[k];
    pinched.triangles.push_back(u);
  }
  EXPECT_NE(build_error(pinched, 0.1).find("vertex 0"), std::string::npos)
      << build_error(pinched, 0.1);
  EXPECT_NE(build_error(box_mesh(1, 1, 1), 0.0).find("dilation radius"), std::string::npos);
  CoreMesh degenerate = box_mesh(1, 1, 1);
  degenerate.triangles[0] = {0, 0, 1};
  EXPECT_NE(build_error(degenerate, 0.1).find("zero area"), std::string::npos);
}

// --- Mass properties --------------------------------------------------------------------------

// Second moments (integrals of x^2, y^2, z^2) of the box [-a, a] x [-b, b] x [-c, c] dilated by
// r, summed over its exact pieces: the box, six slabs, twelve quarter cylinders along its edges
// and eight eighth spheres at its corners.
Vec3 dilated_box_second_moments(double a, double b, double c, double r, double& volume) {
  const double h[3] = {a, b, c};
  const double quarter_disc = pi * r * r / 4.0;
  volume = 8 * a * b * c + 8 * r * (a * b + b * c + c * a) + 2 * pi * r * r * (a + b + c) +
           4.0 / 3.0 * pi * r * r * r;
  double s[3];
  for (int i = 0; i < 3; ++i) {
    const double x = h[i], y = h[(i + 1) % 3], z = h[(i + 2) % 3];
    const double box = 8 * x * y * z * x * x / 3;
    const double own_slabs = 8 * y * z * (std::pow(x + r, 3) - x * x * x) / 3;
    const double side_slabs = 2 * (2 * r * 2 * z + 2 * r * 2 * y) * (2 * x * x * x / 3) / 2;
    // Quarter cylinders along the two other axes (4 each, lengths 2y and 2z) sit at distance x
    // off this axis; those along this axis (4, length 2x) carry x^2 along their length.
    const double off_axis =
        4 * (2 * y + 2 * z) *
        (x * x * quarter_disc + 2 * x * r * r * r / 3 + pi * std::pow(r, 4) / 16);
    const double along_axis = 4 * quarter_disc * (2 * x * x * x / 3);
    const double corners =
        8 * (x * x * pi * r * r * r / 6 + x * pi * std::pow(r, 4) / 8 + pi * std::pow(r, 5) / 30);
    s[i] = box + own_slabs + side_slabs + off_axis + along_axis + corners;
  }
  return Vec3{s[0], s[1], s[2]};
}

TEST(DilatedMass, BoxAgainstItsClosedForm) {
  const double a = 1.0, b = 0.7, c = 0.4;
  for (double r : {0.05, 0.3, 1.0}) {
    const BodyMassProperties props = dilated_mass_properties(core_of(box_mesh(a, b, c), r));
    double volume = 0;
    const Vec3 s = dilated_box_second_moments(a, b, c, r, volume);
    const Vec3 inertia{s.y + s.z, s.z + s.x, s.x + s.y};
    const double trace_i = inertia.x + inertia.y + inertia.z;
    // Stated precision: relative_precision, the last refinement's change, bounds the error (the
    // rule is second order: the change is about 3 times the finer level's error).
    const double allowed = props.relative_precision;
    EXPECT_LT(props.relative_precision, 1e-4) << r;
    EXPECT_NEAR(props.volume, volume, allowed * volume) << r;
    EXPECT_LT(norm(props.centroid), allowed * std::sqrt(trace_i / (2 * volume))) << r;
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(props.inertia_per_density.m[k][k], inertia[k], allowed * trace_i) << r << k;
    EXPECT_NEAR(props.inertia_per_density.m[0][1], 0, allowed * trace_i);
  }
}

// Steiner's formula for a convex core: V + A r + (1/2) sum_edges l_e psi_e r^2 + 4/3 pi r^3,
// psi_e the exterior dihedral angle (flat edges add nothing).
double steiner_volume(const DilatedCore& core) {
  double volume = 0, area = 0, edge_term = 0;
  for (const CoreFace& f : core.faces) {
    const Vec3 p0 = core.vertex(f.vertex[0]).position, p1 = core.vertex(f.vertex[1]).position,
               p2 = core.vertex(f.vertex[2]).position;
    volume += dot(p0, cross(p1, p2)) / 6;
    area += 0.5 * norm(cross(p1 - p0, p2 - p0));
  }
  for (std::size_t e = 0; e < core.edges.size(); ++e) {
    const CoreEdge& edge = core.edges[e];
    const double length =
        norm(core.vertex(edge.vertex[1]).position - core.vertex(edge.vertex[0]).position);
    // The exterior angle between the faces' normals: pi minus the angle between the inward
    // directions.
    const double exterior =
        pi - std::acos(std::clamp(dot(edge.inward[0], edge.inward[1]), -1.0, 1.0));
    edge_term += 0.5 * length * exterior;
  }
  const double r = core.radius;
  return volume + area * r + edge_term * r * r + 4.0 / 3.0 * pi * r * r * r;
}

TEST(DilatedMass, TetrahedronVolumeBySteinerCentroidAndIsotropy) {
  for (double r : {0.02, 0.2, 0.8}) {
    const DilatedCore core = core_of(tetrahedron_mesh(1.0), r);
    const BodyMassProperties props = dilated_mass_properties(core);
    const double volume = steiner_volume(core);
    const double allowed = props.relative_precision;
    EXPECT_NEAR(props.volume, volume, allowed * volume) << r;
    // Tetrahedral symmetry: centroid at the origin, inertia a multiple of the identity.
    const double trace_i = trace(props.inertia_per_density);
    EXPECT_LT(norm(props.centroid), allowed * std::sqrt(trace_i / (2 * volume))) << r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(props.inertia_per_density.m[i][j], i == j ? trace_i / 3 : 0.0,
                    allowed * trace_i)
            << r;
  }
}

TEST(DilatedMass, SphereLimitOfATinyCore) {
  const double r = 1.0, core_size = 1e-4;
  const BodyMassProperties props = dilated_mass_properties(core_of(octahedron_mesh(core_size), r));
  const double volume = 4.0 / 3.0 * pi * r * r * r;
  // The core adds its Steiner terms, below 3 core_size / r of the sphere's volume.
  EXPECT_NEAR(props.volume, volume, (props.relative_precision + 3 * core_size) * volume);
  const double inertia = 0.4 * volume * r * r;
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(props.principal_inertia_per_density[k], inertia,
                (props.relative_precision + 5 * core_size) * inertia);
}

TEST(DilatedMass, ShiftedCoreHasItsCentroidMoved) {
  CoreMesh m = box_mesh(1.0, 0.5, 0.25);
  const Vec3 shift{0.3, -0.2, 0.7};
  for (Vec3& p : m.points)
    p = p + shift;
  const BodyMassProperties props = dilated_mass_properties(core_of(m, 0.2));
  EXPECT_LT(norm(props.centroid - shift), props.relative_precision * 1.0);
}

// --- Contacts --------------------------------------------------------------------------------

const ConeSlack slack{};

TEST(DilatedContact, SphereAgainstABoxMatchesTheDistanceToTheCore) {
  const DilatedCore core = core_of(box_mesh(1.0, 0.7, 0.4), 0.1);
  std::mt19937_64 rng(7);
  int touching = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 x{uniform(rng, -1.6, 1.6), uniform(rng, -1.3, 1.3), uniform(rng, -1.0, 1.0)};
    const double radius = uniform(rng, 0.05, 0.5);
    const CoreDistance d = core_distance(core, x);
    if (d.signed_distance <= 0)
      continue; // centre inside the core: no local minimum of the distance
    ContactList found;
    ASSERT_TRUE(dilated_sphere_contacts(core, x, radius, slack, found));
    const double overlap = core.radius + radius - d.signed_distance;
    if (overlap <= 0) {
      EXPECT_TRUE(found.contacts.empty()) << trial;
      continue;
    }
    ++touching;
    // A convex core: one local minimum, the closest point (a second only where the direction
    // lies within the cone slack, 1e-6, of two features, and then both agree to the slack).
    ASSERT_GE(found.contacts.size(), 1u) << trial;
    ASSERT_LE(found.contacts.size(), 3u) << trial;
    EXPECT_NEAR(found.deepest(), overlap, 1e-12) << trial;
    for (const FeatureContact& c : found.contacts) {
      EXPECT_NEAR(c.overlap, overlap, 1e-11) << trial;
      EXPECT_NEAR(norm(c.normal - (-1.0) * d.outward), 0, 2e-6) << trial;
    }
  }
  EXPECT_GT(touching, 300);
}

TEST(DilatedContact, SphereInTheNotchOfAConcaveCoreTouchesBothWalls) {
  const double r = 0.05;
  const DilatedCore core = core_of(u_prism_mesh(1.0, 1.0), r);
  // The notch spans x in [1, 2] above y = 1: a sphere centred in it, wider than the gap left
  // between the dilated walls, touches both, with normals +x and -x.
  const double radius = 0.5 - r + 0.01;
  ContactList found;
  ASSERT_TRUE(dilated_sphere_contacts(core, Vec3{1.5, 1.7, 0.5}, radius, slack, found));
  ASSERT_EQ(found.contacts.size(), 2u);
  double sum_x = 0;
  for (const FeatureContact& c : found.contacts) {
    EXPECT_NEAR(c.overlap, 0.01, 1e-12);
    EXPECT_NEAR(std::fabs(c.normal.x), 1.0, 1e-12);
    sum_x += c.normal.x;
  }
  EXPECT_NEAR(sum_x, 0, 1e-12);
}

TEST(DilatedContact, PlaneTouchesTheLowestVerticesOnly) {
  const double r = 0.1;
  const DilatedCore core = core_of(box_mesh(1.0, 0.7, 0.4), r);
  // A plane 0.02 into the dilation below the box's bottom face: its four corners touch.
  ContactList flat;
  ASSERT_TRUE(
      dilated_plane_contacts(core, Vec3{0, 0, -0.4 - r + 0.02}, Vec3{0, 0, 1}, slack, flat));
  ASSERT_EQ(flat.contacts.size(), 4u);
  for (const FeatureContact& c : flat.contacts)
    EXPECT_NEAR(c.overlap, 0.02, 1e-12);
  // A plane tilted about a general axis: the one lowest corner touches.
  ContactList tilted;
  const Vec3 n = dilated_build::unit(Vec3{0.3, 0.2, 1.0});
  const double lowest = -(1.0 * 0.3 + 0.7 * 0.2 + 0.4 * 1.0) / norm(Vec3{0.3, 0.2, 1.0});
  ASSERT_TRUE(dilated_plane_contacts(core, (lowest - r + 0.01) * n, n, slack, tilted));
  ASSERT_EQ(tilted.contacts.size(), 1u);
  EXPECT_NEAR(tilted.contacts[0].overlap, 0.01, 1e-12);
}

TEST(DilatedContact, ConvexPairsMatchTheBruteForceDistance) {
  const double ra = 0.1, rb = 0.05;
  const DilatedCore a = core_of(box_mesh(1.0, 0.7, 0.4), ra);
  const DilatedCore b = core_of(tetrahedron_mesh(0.8), rb);
  std::mt19937_64 rng(11);
  int touching = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const RelativePose pose{rotation_matrix(random_rotation(rng)),
                            uniform(rng, 1.0, 2.2) * random_unit(rng)};
    const double distance = core_core_distance(a, b, pose);
    ContactList found;
    ASSERT_TRUE(dilated_pair_contacts(a, b, pose, slack, found));
    const double overlap = ra + rb - distance;
    if (distance == 0)
      continue; // the cores intersect: no local minimum of their distance (see docs)
    if (overlap <= 0) {
      EXPECT_TRUE(found.contacts.empty()) << trial;
      continue;
    }
    ++touching;
    ASSERT_FALSE(found.contacts.empty()) << trial << " overlap " << overlap;
    EXPECT_NEAR(found.deepest(), overlap, 1e-9) << trial;
  }
  EXPECT_GT(touching, 30);
}

TEST(DilatedContact, ParallelFacesTouchAtTheCornersOfTheirOverlap) {
  const double r = 0.1;
  const DilatedCore a = core_of(box_mesh(1.0, 1.0, 0.5), r);
  const DilatedCore b = core_of(box_mesh(1.0, 1.0, 0.5), r);
  // B below A, shifted sideways by (0.6, 0.4): the overlap of the faces is the rectangle
  // x in [-0.4, 1], y in [-0.6, 1] of A's bottom face, at a gap of 0.15 between the cores.
  const RelativePose pose{identity3(), Vec3{0.6, 0.4, -1.15}};
  ContactList found;
  ASSERT_TRUE(dilated_pair_contacts(a, b, pose, slack, found));
  ASSERT_GE(found.contacts.size(), 4u);
  int corners = 0;
  for (const FeatureContact& c : found.contacts) {
    EXPECT_NEAR(c.overlap, 0.05, 1e-12);
    EXPECT_NEAR(c.normal.z, 1.0, 1e-12);
    EXPECT_GE(c.point.x, -0.4 - 1e-12);
    EXPECT_LE(c.point.y, 1.0 + 1e-12);
    const bool corner_x = std::fabs(c.point.x + 0.4) < 1e-12 || std::fabs(c.point.x - 1) < 1e-12;
    const bool corner_y = std::fabs(c.point.y + 0.6) < 1e-12 || std::fabs(c.point.y - 1) < 1e-12;
    corners += corner_x && corner_y;
  }
  EXPECT_EQ(corners, 4);
}

TEST(DilatedContact, EdgeOnEdgeAndVertexOnFace) {
  const double r = 0.1;
  const DilatedCore a = core_of(box_mesh(1.0, 1.0, 1.0), r);
  const Mat3 about_x = rotation_matrix(axis_angle(Vec3{1, 0, 0}, pi / 4));
  const Mat3 about_y = rotation_matrix(axis_angle(Vec3{0, 1, 0}, pi / 4));
  const DilatedCore b = core_of(box_mesh(1.0, 1.0, 1.0), r);
  const double gap = 0.15;
  const double half_diagonal = std::sqrt(2.0);
  // B turned 45 degrees about x has an edge along x at its bottom, sqrt 2 below its centre;
  // placed above A's top face, 0.15 off it.
  const RelativePose edge_down{about_x, Vec3{0, 0, 1 + gap + half_diagonal}};
  ContactList face;
  ASSERT_TRUE(dilated_pair_contacts(a, b, edge_down, slack, face));
  // B's lowest edge lies on A's top face across its whole width: its two end vertices touch the
  // face (vertex-face), and where it crosses A's face diagonal, an edge-edge point.
  ASSERT_GE(face.contacts.size(), 2u);
  for (const FeatureContact& c : face.contacts) {
    EXPECT_NEAR(c.overlap, 2 * r - gap, 1e-12);
    EXPECT_NEAR(c.normal.z, -1.0, 1e-12);
  }
  // Crossed edges: A turned about y (edge along y on top) against B turned about x (edge along
  // x at the bottom): one edge-edge contact.
  const RelativePose crossed{transpose(about_y) * about_x,
                             transpose(about_y) * Vec3{0, 0, 2 * half_diagonal + gap}};
  ContactList cross_found;
  ASSERT_TRUE(dilated_pair_contacts(a, b, crossed, slack, cross_found));
  ASSERT_EQ(cross_found.contacts.size(), 1u);
  EXPECT_NEAR(cross_found.contacts[0].overlap, 2 * r - gap, 1e-12);
  const int edge_keys = int(a.vertices.size());
  EXPECT_GE(cross_found.contacts[0].feature_a, edge_keys);
  EXPECT_LT(cross_found.contacts[0].feature_a, edge_keys + int(a.edges.size()));
}

} // namespace
} // namespace kdem::test
