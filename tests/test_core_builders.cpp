// Builders of dilated-polyhedron cores (src/core_builders.hpp): the Fibonacci lattice and its hull,
// the superquadric and spherical-harmonic radial maps against closed forms, convex hulls,
// simplification, and the scene keys that call them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "shapes/dilated_polyhedron_build.hpp"
#include "shapes/superquadric.hpp"
#include "shapes/superquadric_properties.hpp"
#include "src/core_builders.hpp"
#include "src/dilated_polyhedron_scene.hpp"
#include "src/scene_loader.hpp"

namespace {

namespace fs = std::filesystem;
using kdem::Point3;
using kdem::TriangleMesh;

constexpr double pi = 3.14159265358979323846;

double distance(const Point3& p, const Point3& q) {
  return std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
}

double norm(const Point3& p) {
  return std::hypot(p[0], p[1], p[2]);
}

// Every undirected edge in exactly two triangles, run along in opposite directions.
testing::AssertionResult closed_and_consistently_wound(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, std::vector<bool>> uses; // per edge: runs from lower to higher?
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
      uses[{std::min(a, b), std::max(a, b)}].push_back(a < b);
    }
  for (const auto& [edge, directions] : uses) {
    if (directions.size() != 2)
      return testing::AssertionFailure() << "edge " << edge.first << "-" << edge.second << " is in "
                                         << directions.size() << " triangles";
    if (directions[0] == directions[1])
      return testing::AssertionFailure()
             << "edge " << edge.first << "-" << edge.second << " is run along twice alike";
  }
  return testing::AssertionSuccess();
}

// The mesh through the engine's own check (closed, manifold, consistently oriented, no zero-area
// triangle); build_dilated_core throws otherwise.
kdem::DilatedCore engine_core(const TriangleMesh& mesh, double dilation = 0.01) {
  std::vector<kdem::Vec3> points;
  for (const Point3& p : mesh.points)
    points.push_back(kdem::Vec3{p[0], p[1], p[2]});
  return kdem::build_dilated_core(points, mesh.triangles, dilation);
}

double nearest_neighbour_distance(const std::vector<Point3>& points, std::size_t k) {
  double nearest = 1e300;
  for (std::size_t j = 0; j < points.size(); ++j)
    if (j != k)
      nearest = std::min(nearest, distance(points[k], points[j]));
  return nearest;
}

// ---- lattice ------------------------------------------------------------------------------------

TEST(FibonacciLattice, UnitDirectionsSymmetricAboutTheEquator) {
  for (int count : {4, 200, 2000}) {
    const std::vector<Point3> directions = kdem::fibonacci_directions(count);
    ASSERT_EQ(directions.size(), std::size_t(count));
    for (std::size_t k = 0; k < directions.size(); ++k) {
      EXPECT_NEAR(norm(directions[k]), 1, 1e-15) << k; // rounding of sin, cos and a sqrt
      // Eq. 4.3: z_i = (M - 1 - 2i) / (M - 1 + 2 eps), so z_i = -z_(M-1-i), decreasing in i.
      EXPECT_NEAR(directions[k][2], -directions[directions.size() - 1 - k][2], 1e-15) << k;
      if (k > 0)
        EXPECT_LT(directions[k][2], directions[k - 1][2]) << k;
    }
  }
}

TEST(FibonacciLattice, NearestNeighbourSpacingIsNearlyUniform) {
  for (int count : {200, 2000}) {
    const std::vector<Point3> directions = kdem::fibonacci_directions(count);
    double smallest = 1e300, largest = 0;
    for (std::size_t k = 0; k < directions.size(); ++k) {
      const double nearest = nearest_neighbour_distance(directions, k);
      smallest = std::min(smallest, nearest);
      largest = std::max(largest, nearest);
    }
    // Measured: largest / smallest 1.141 (200) and 1.139 (2000), the smallest 0.87 of the spacing
    // sqrt(4 pi / M) of M equal caps. Bounds a little beyond what was measured.
    EXPECT_LT(largest / smallest, 1.2) << count;
    EXPECT_GT(smallest, 0.8 * std::sqrt(4 * pi / count)) << count;
  }
}

TEST(FibonacciSphere, ClosedOutwardHullOf2MMinus4Triangles) {
  for (int count : {4, 5, 6, 200, 1001, 2000}) {
    const TriangleMesh sphere = kdem::fibonacci_sphere(count);
    EXPECT_EQ(sphere.points.size(), std::size_t(count));
    EXPECT_EQ(sphere.triangles.size(), std::size_t(2 * count - 4)) << count;
    EXPECT_TRUE(closed_and_consistently_wound(sphere)) << count;
    EXPECT_GT(kdem::enclosed_volume(sphere), 0) << count;
    // Each node stays where the lattice put it (the hull keeps the input order).
    EXPECT_EQ(sphere.points, kdem::fibonacci_directions(count)) << count;
  }
}

TEST(FibonacciLattice, RefusesFewerThanFourNodes) {
  EXPECT_THROW(kdem::fibonacci_directions(3), std::invalid_argument);
}

// ---- superquadric
// ---------------------------------------------------------------------------------

TEST(SuperquadricCore, SphereHasTheExactRadiusAtEveryNode) {
  const double radius = 0.003;
  const TriangleMesh sphere = kdem::superquadric_core(radius, radius, radius, 2, 2, 500);
  ASSERT_EQ(sphere.triangles.size(), 996u);
  for (const Point3& p : sphere.points)
    EXPECT_NEAR(norm(p), radius, 1e-15 * radius); // a square root and a power of rounding
}

TEST(SuperquadricCore, NodesLieOnTheFamilysSurface) {
  // The project's superquadric function (n2 in the xy section, n1 along z): F = 0 at every node.
  const double a = 1.0, b = 0.7, c = 0.5, n1 = 4, n2 = 3;
  const kdem::SuperquadricShape shape = kdem::make_superquadric(a, b, c, n1, n2);
  const TriangleMesh core = kdem::superquadric_core(a, b, c, n1, n2, 400);
  for (const Point3& p : core.points) {
    const double f = kdem::superquadric_local<false>(shape, kdem::Vec3{p[0], p[1], p[2]}).value;
    EXPECT_NEAR(f / shape.conditioning, 0, 1e-13); // F is of order one; pow rounding
  }
}

TEST(SuperquadricCore, VolumeConvergesToTheClosedForm) {
  const double a = 1.0, b = 0.7, c = 0.5, n1 = 4, n2 = 3;
  const double exact = kdem::superquadric_volume(kdem::make_superquadric(a, b, c, n1, n2));
  std::vector<double> errors;
  for (int nodes : {250, 500, 1000, 2000})
    errors.push_back(1 - kdem::enclosed_volume(kdem::superquadric_core(a, b, c, n1, n2, nodes)) /
                             exact);
  // Measured: 3.70e-2, 1.69e-2, 8.96e-3, 4.83e-3, orders 1.13, 0.92, 0.89 in M (an inscribed
  // polyhedron's volume error falls as the square of the node spacing, spacing^2 ~ 1 / M).
  for (std::size_t k = 1; k < errors.size(); ++k) {
    EXPECT_GT(errors[k], 0); // inscribed in a convex body: less volume
    const double order = std::log(errors[k - 1] / errors[k]) / std::log(2.0);
    EXPECT_GT(order, 0.8) << k;
    EXPECT_LT(order, 1.3) << k;
  }
  EXPECT_LT(errors.back(), 5e-3);
}

// ---- harmonics
// ------------------------------------------------------------------------------------

std::vector<kdem::HarmonicCoefficient> sphere_coefficients(double a00) {
  return {{0, 0, a00, 0}};
}

TEST(HarmonicCore, OnlyA00IsASphere) {
  const double a00 = 0.004;
  const TriangleMesh sphere = kdem::harmonic_core(sphere_coefficients(a00), 300);
  ASSERT_EQ(sphere.triangles.size(), 596u);
  for (const Point3& p : sphere.points)
    EXPECT_NEAR(norm(p), a00 / (2 * std::sqrt(pi)), 1e-15 * a00); // Y_0^0 = 1 / (2 sqrt(pi))
}

// r of A_00, A_10, A_11, A_22 from the closed forms of the harmonics (any table of them), with the
// negative orders written out: A_1,-1 Y_1^-1 + A_11 Y_11 = 2 Re(A_11 Y_11), likewise m = 2.
double closed_form_radius(double theta, double phi) {
  const std::complex<double> a11(0.2, 0.1), a22(-0.05, 0.08);
  const double a00 = 3, a10 = 0.3;
  const double y00 = 0.5 / std::sqrt(pi);
  const double y10 = std::sqrt(3 / (4 * pi)) * std::cos(theta);
  const std::complex<double> y11 = -std::sqrt(3 / (8 * pi)) * std::sin(theta) *
                                   std::complex<double>(std::cos(phi), std::sin(phi));
  const std::complex<double> y22 = 0.25 * std::sqrt(15 / (2 * pi)) * std::pow(std::sin(theta), 2) *
                                   std::complex<double>(std::cos(2 * phi), std::sin(2 * phi));
  return a00 * y00 + a10 * y10 + 2 * (a11 * y11).real() + 2 * (a22 * y22).real();
}

TEST(HarmonicCore, RealCombinationMatchesTheClosedForms) {
  const std::vector<kdem::HarmonicCoefficient> coefficients{
      {0, 0, 3, 0}, {1, 0, 0.3, 0}, {1, 1, 0.2, 0.1}, {2, 2, -0.05, 0.08}};
  const TriangleMesh core = kdem::harmonic_core(coefficients, 600);
  for (const Point3& p : core.points) {
    const double theta = std::acos(p[2] / norm(p)), phi = std::atan2(p[1], p[0]);
    EXPECT_NEAR(norm(p), closed_form_radius(theta, phi), 1e-14); // r about 0.85; rounding
  }
  EXPECT_TRUE(closed_and_consistently_wound(core));
}

// Gauss-Legendre nodes and weights on [-1, 1] by Newton on P_n (Golub-Welsch would do as well).
std::vector<std::pair<double, double>> gauss_legendre(int count) {
  std::vector<std::pair<double, double>> rule;
  for (int k = 1; k <= count; ++k) {
    double x = std::cos(pi * (k - 0.25) / (count + 0.5)), derivative = 0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1, p1 = x;
      for (int n = 2; n <= count; ++n) {
        const double p2 = ((2 * n - 1) * x * p1 - (n - 1) * p0) / n;
        p0 = p1;
        p1 = p2;
      }
      derivative = count * (x * p1 - p0) / (x * x - 1);
      const double step = p1 / derivative;
      x -= step;
      if (std::fabs(step) < 1e-16)
        break;
    }
    rule.push_back({x, 2 / ((1 - x * x) * derivative * derivative)});
  }
  return rule;
}

TEST(HarmonicCore, BasisIsOrthonormalUpToDegreeThree) {
  // Y_n^m conj(Y_n'^m') is a polynomial of degree <= 6 in cos(theta) times e^(i (m - m') phi):
  // 8 Gauss points in cos(theta) and 16 equal steps in phi integrate it exactly.
  const auto rule = gauss_legendre(8);
  const int azimuth_steps = 16;
  std::vector<std::pair<int, int>> degrees_orders;
  for (int n = 0; n <= 3; ++n)
    for (int m = 0; m <= n; ++m)
      degrees_orders.push_back({n, m});
  for (const auto& [n, m] : degrees_orders)
    for (const auto& [n2, m2] : degrees_orders) {
      std::complex<double> integral = 0;
      for (const auto& [x, weight] : rule)
        for (int step = 0; step < azimuth_steps; ++step) {
          const double theta = std::acos(x), phi = 2 * pi * step / azimuth_steps;
          integral += weight * (2 * pi / azimuth_steps) *
                      kdem::spherical_harmonic(n, m, theta, phi) *
                      std::conj(kdem::spherical_harmonic(n2, m2, theta, phi));
        }
      const double expected = (n == n2 && m == m2) ? 1 : 0;
      EXPECT_NEAR(integral.real(), expected, 1e-14) << n << m << " " << n2 << m2;
      EXPECT_NEAR(integral.imag(), 0, 1e-14) << n << m << " " << n2 << m2;
    }
}

TEST(HarmonicCore, RefusesARadiusThatIsNotPositive) {
  // r = 1 / (2 sqrt(pi)) + 5 sqrt(3 / (4 pi)) cos(theta) < 0 near the south pole.
  try {
    kdem::harmonic_core({{0, 0, 1, 0}, {1, 0, 5, 0}}, 200);
    ADD_FAILURE() << "a negative radius was accepted";
  } catch (const std::invalid_argument& refused) {
    EXPECT_NE(std::string(refused.what()).find("not positive"), std::string::npos)
        << refused.what();
  }
  EXPECT_THROW(kdem::harmonic_core({{1, 2, 1, 0}}, 200), std::invalid_argument); // m > n
  EXPECT_THROW(kdem::harmonic_core({{0, 0, 1, 0}, {0, 0, 2, 0}}, 200), std::invalid_argument);
}

// ---- convex hull
// ----------------------------------------------------------------------------------

std::vector<Point3> unit_cube_corners() {
  std::vector<Point3> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back({double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
  return corners;
}

TEST(ConvexHullCore, CubeCornersAmongInteriorPoints) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> inside(0.01, 0.99);
  std::vector<Point3> points;
  for (int k = 0; k < 300; ++k)
    points.push_back({inside(random), inside(random), inside(random)});
  const std::vector<Point3> corners = unit_cube_corners();
  for (std::size_t k = 0; k < corners.size(); ++k)
    points.insert(points.begin() + std::ptrdiff_t(40 * k), corners[k]);
  const TriangleMesh hull = kdem::convex_hull_core(points);
  EXPECT_EQ(hull.triangles.size(), 12u);
  ASSERT_EQ(hull.points.size(), 8u);
  for (const Point3& corner : corners)
    EXPECT_NE(std::find(hull.points.begin(), hull.points.end(), corner), hull.points.end());
  EXPECT_NEAR(kdem::enclosed_volume(hull), 1, 1e-15); // sums of products of 0 and 1
  EXPECT_TRUE(closed_and_consistently_wound(hull));
  EXPECT_NO_THROW(engine_core(hull));
}

TEST(ConvexHullCore, PointsOnFacesAndEdgesAreNotVertices) {
  std::vector<Point3> points = unit_cube_corners();
  for (double s : {0.25, 0.5, 0.75})
    for (double t : {0.25, 0.5, 0.75}) {
      points.push_back({s, t, 0});
      points.push_back({s, t, 1});
      points.push_back({0, s, t});
      points.push_back({s, 0, 0});
    }
  const TriangleMesh hull = kdem::convex_hull_core(points);
  EXPECT_EQ(hull.points.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);
  EXPECT_NEAR(kdem::enclosed_volume(hull), 1, 1e-15);
}

TEST(ConvexHullCore, RefusesPointsThatSpanNoVolume) {
  const auto refusal = [](const std::vector<Point3>& points) -> std::string {
    try {
      kdem::convex_hull_core(points);
    } catch (const std::invalid_argument& refused) {
      return refused.what();
    }
    return "accepted";
  };
  EXPECT_NE(refusal({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).find("at least 4 points"),
            std::string::npos);
  EXPECT_NE(refusal({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}).find("coincide"),
            std::string::npos);
  EXPECT_NE(
      refusal({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {-3, -3, -3}, {0.5, 0.5, 0.5}}).find("collinear"),
      std::string::npos);
  std::vector<Point3> flat;
  for (int k = 0; k < 20; ++k)
    flat.push_back({std::cos(k), std::sin(k), 0.5 * std::cos(k) + 0.25 * std::sin(k)});
  EXPECT_NE(refusal(flat).find("coplanar"), std::string::npos) << refusal(flat);
}

// ---- simplification
// -------------------------------------------------------------------------------

TEST(SimplifyCore, FineSuperquadricToAThousandFaces) {
  const TriangleMesh fine = kdem::superquadric_core(1.0, 0.8, 0.6, 4, 4, 2502);
  ASSERT_EQ(fine.triangles.size(), 5000u);
  const TriangleMesh coarse = kdem::simplify_core(fine, 1000);
  // Each collapse of an edge between two triangles removes both, and the decimation stops at the
  // first count at or below the target. Measured: 1000.
  EXPECT_LE(coarse.triangles.size(), 1000u);
  EXPECT_GE(coarse.triangles.size(), 999u);
  EXPECT_TRUE(closed_and_consistently_wound(coarse));
  EXPECT_NO_THROW(engine_core(coarse));
  // Measured: 2.3e-3 less than the fine mesh, 5.7e-3 less than the exact body; the lattice of
  // the same face count (502 nodes) holds 1.6e-2 less: the collapses go where it is flat.
  const double fine_volume = kdem::enclosed_volume(fine);
  EXPECT_NEAR(kdem::enclosed_volume(coarse) / fine_volume, 1, 3e-3);
  const double exact = kdem::superquadric_volume(kdem::make_superquadric(1.0, 0.8, 0.6, 4, 4));
  const double lattice_volume =
      kdem::enclosed_volume(kdem::superquadric_core(1.0, 0.8, 0.6, 4, 4, 502));
  EXPECT_LT(exact - kdem::enclosed_volume(coarse), 0.5 * (exact - lattice_volume));
}

// The box [0, a] x [0, b] x [0, c], each face a grid of `cells` x `cells` squares cut into two
// triangles, outward wound; points shared along the box's edges.
TriangleMesh fine_box(double a, double b, double c, int cells) {
  TriangleMesh box;
  std::map<std::array<long, 3>, int> index;
  const auto point = [&](int i, int j, int k) {
    const std::array<long, 3> key{i, j, k};
    const auto found = index.find(key);
    if (found != index.end())
      return found->second;
    box.points.push_back({a * i / cells, b * j / cells, c * k / cells});
    index.emplace(key, int(box.points.size()) - 1);
    return int(box.points.size()) - 1;
  };
  // Per face: the fixed axis, its value (0 or cells) and whether (u, v, normal) is right-handed.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int u = 0; u < cells; ++u)
        for (int v = 0; v < cells; ++v) {
          const auto corner = [&](int du, int dv) {
            std::array<int, 3> ijk{};
            ijk[std::size_t(axis)] = side * cells;
            ijk[std::size_t((axis + 1) % 3)] = u + du;
            ijk[std::size_t((axis + 2) % 3)] = v + dv;
            return point(ijk[0], ijk[1], ijk[2]);
          };
          const int p00 = corner(0, 0), p10 = corner(1, 0), p11 = corner(1, 1), p01 = corner(0, 1);
          if (side == 1) {
            box.triangles.push_back({p00, p10, p11});
            box.triangles.push_back({p00, p11, p01});
          } else {
            box.triangles.push_back({p00, p11, p10});
            box.triangles.push_back({p00, p01, p11});
          }
        }
  return box;
}

TEST(SimplifyCore, BoxKeepsItsCornersAndVolume) {
  const double a = 0.003, b = 0.002, c = 0.001;
  const TriangleMesh fine = fine_box(a, b, c, 16);
  ASSERT_TRUE(closed_and_consistently_wound(fine));
  ASSERT_NEAR(kdem::enclosed_volume(fine), a * b * c, 1e-12 * a * b * c); // 3072 rounded terms
  const TriangleMesh coarse = kdem::simplify_core(fine, 100);
  EXPECT_LE(coarse.triangles.size(), 100u);
  EXPECT_NO_THROW(engine_core(coarse, 1e-4));
  for (int k = 0; k < 8; ++k) {
    const Point3 corner{a * (k & 1), b * ((k >> 1) & 1), c * ((k >> 2) & 1)};
    double nearest = 1e300;
    for (const Point3& p : coarse.points)
      nearest = std::min(nearest, distance(p, corner));
    // A corner never moves: its coordinates are the input's.
    EXPECT_EQ(nearest, 0) << "corner " << k;
  }
  // Flat faces keep their volume up to the single precision of VTK's moved points (6e-8 of the
  // size; measured 2e-8 of the volume).
  EXPECT_NEAR(kdem::enclosed_volume(coarse), a * b * c, 2e-7 * a * b * c);
}

TEST(SimplifyCore, TheUnitOfLengthDoesNotMatter) {
  // The same superquadric in metres and in units of 0.1 mm: the same reduction, scaled. Measured
  // without the unit frame: 2.50e-3 and 2.26e-3 of the volume lost.
  std::vector<double> volume_ratios;
  for (double unit : {1e-4, 1.0}) {
    const TriangleMesh fine = kdem::superquadric_core(unit, 0.8 * unit, 0.6 * unit, 4, 4, 2502);
    const TriangleMesh coarse = kdem::simplify_core(fine, 1000);
    EXPECT_EQ(coarse.triangles.size(), 1000u);
    volume_ratios.push_back(kdem::enclosed_volume(coarse) / kdem::enclosed_volume(fine));
  }
  EXPECT_NEAR(volume_ratios[0], volume_ratios[1], 1e-7); // single-precision points
}

TEST(SimplifyCore, RefusesATargetNotBelowTheCountOrBelowFour) {
  const TriangleMesh sphere = kdem::fibonacci_sphere(100);
  EXPECT_THROW(kdem::simplify_core(sphere, 196), std::invalid_argument);
  EXPECT_THROW(kdem::simplify_core(sphere, 3), std::invalid_argument);
}

// ---- scene keys
// -----------------------------------------------------------------------------------

// A folder of its own for files a test writes; removed afterwards.
class ScratchFolder {
public:
  ScratchFolder() {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::path(testing::TempDir()) / (std::string("kdem_cores_") + test->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchFolder() { fs::remove_all(path_); }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  std::string path() const { return path_.string(); }
  void write(const std::string& name, const std::string& contents) const {
    std::ofstream(path_ / name) << contents;
  }

private:
  fs::path path_;
};

// A scene of one dilated-polyhedron shape whose entry's lines (from line 17) are `shape_lines`.
std::string scene_with_core(const std::string& shape_lines) {
  return "time_step: 1.0e-5\n"                                         // 1
         "duration: 0.5\n"                                             // 2
         "materials:\n"                                                // 3
         "  - {name: glass, density: 2500, youngs_modulus: 1.0e7, "    //
         "poisson_ratio: 0.25}\n"                                      // 4
         "particles:\n"                                                // 5
         "  - name: stones\n"                                          // 6
         "    material: glass\n"                                       // 7
         "    shape: stone\n"                                          // 8
         "    region: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}}\n" // 9
         "    count: 10\n"                                             // 10
         "shapes:\n"                                                   // 11
         "  - name: stone\n"                                           // 12
         "    dilated_polyhedron:\n"                                   // 13
         "      dilation_radius: 0.0002\n"                             // 14
         "      mass_precision: 1e-3\n"                                // 15
         "      scale: 0.001\n"                                        // 16
         + shape_lines;
}

// A copy: the scene holding the parameters is usually a temporary.
kdem::DilatedPolyhedronShapeParameters loaded_core(const kdem::SceneConfig& scene) {
  return kdem::dilated_polyhedron_parameters(scene.shapes.at(0));
}

kdem::SceneConfig load(const std::string& shape_lines, const std::string& base_dir = ".") {
  return kdem::load_scene_from_string(scene_with_core(shape_lines), "scene.yaml", base_dir);
}

// Succeeds when the scene is refused at `line` with a message naming `key_path` and holding
// `expectation`.
testing::AssertionResult refused(const std::string& shape_lines, int line,
                                 const std::string& key_path, const std::string& expectation,
                                 const std::string& base_dir = ".") {
  std::string message;
  try {
    load(shape_lines, base_dir);
    return testing::AssertionFailure() << "the scene was accepted";
  } catch (const kdem::SceneError& error) {
    message = error.what();
  }
  const std::string position = "scene.yaml:" + std::to_string(line) + ":";
  if (message.rfind(position, 0) != 0)
    return testing::AssertionFailure() << "no \"" << position << "\" at the start of: " << message;
  if (message.find(" " + key_path + ": ") == std::string::npos)
    return testing::AssertionFailure() << "no key path \"" << key_path << "\" in: " << message;
  if (message.find(expectation) == std::string::npos)
    return testing::AssertionFailure() << "no \"" << expectation << "\" in: " << message;
  return testing::AssertionSuccess();
}

const std::string core_path = "shapes[0].dilated_polyhedron";

TEST(CoreSceneKeys, SuperquadricCoreOfTheDefaultNodeCount) {
  const auto core = loaded_core(load("      superquadric: {a: 2, b: 1.5, c: 1, n1: 4, n2: 2}\n"));
  EXPECT_EQ(core.points.size(), 1000u); // the default, chosen from the speed-against-error study
  EXPECT_EQ(core.triangles.size(), 1996u);
  double largest_x = 0;
  for (const auto& p : core.points)
    largest_x = std::max(largest_x, p[0]);
  EXPECT_LE(largest_x, 0.002 * (1 + 1e-12)); // a = 2 times scale 0.001, reached only on the axis
  EXPECT_GT(largest_x, 0.0019);
  EXPECT_EQ(core.dilation_radius, 0.0002);
  EXPECT_EQ(core.mass_precision, 1e-3);
}

TEST(CoreSceneKeys, HarmonicCoreWithNodesHullAndSimplification) {
  const std::string harmonics =
      "      harmonics: {coefficients: [[0, 0, 3.5, 0], [2, 1, 0.3, -0.2], [3, 3, 0.1, 0.1]]}\n"
      "      nodes: 1002\n";
  const auto plain = loaded_core(load(harmonics));
  EXPECT_EQ(plain.triangles.size(), 2000u);
  const Point3 first_direction = kdem::fibonacci_directions(1002)[0];
  const double first_radius = kdem::harmonic_radius(
      {{0, 0, 3.5, 0}, {2, 1, 0.3, -0.2}, {3, 3, 0.1, 0.1}}, std::acos(first_direction[2]),
      std::atan2(first_direction[1], first_direction[0]));
  EXPECT_NEAR(norm(plain.points[0]), 0.001 * first_radius, 1e-18); // mm radii; rounding
  const auto hull = loaded_core(load(harmonics + "      convex_hull: true\n"));
  EXPECT_LT(hull.points.size(), plain.points.size()); // this surface has concave parts
  const auto simplified =
      loaded_core(load(harmonics + "      convex_hull: false\n      simplify_to: 500\n"));
  EXPECT_LE(simplified.triangles.size(), 500u);
  EXPECT_GE(simplified.triangles.size(), 499u);
}

TEST(CoreSceneKeys, MeshCoreHullAndSimplification) {
  ScratchFolder folder;
  std::string obj;
  const TriangleMesh box = fine_box(3, 2, 1, 4);
  for (const Point3& p : box.points)
    obj += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) +
           "\n";
  for (const auto& t : box.triangles)
    obj += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
           std::to_string(t[2] + 1) + "\n";
  folder.write("box.obj", obj);
  const auto plain = loaded_core(load("      mesh: box.obj\n", folder.path()));
  EXPECT_EQ(plain.triangles.size(), 192u);
  const auto hull =
      loaded_core(load("      mesh: box.obj\n      convex_hull: true\n", folder.path()));
  EXPECT_EQ(hull.triangles.size(), 12u);
  EXPECT_EQ(hull.points.size(), 8u);
  const auto simplified =
      loaded_core(load("      mesh: box.obj\n      simplify_to: 40\n", folder.path()));
  EXPECT_LE(simplified.triangles.size(), 40u);
  EXPECT_GE(simplified.triangles.size(), 39u);
}

TEST(CoreSceneKeys, ExactlyOneCoreSource) {
  EXPECT_TRUE(refused("      mesh: box.obj\n      superquadric: {a: 1, b: 1, c: 1, n1: 2, "
                      "n2: 2}\n",
                      18, core_path,
                      "expected exactly one of the keys mesh, superquadric, harmonics, got mesh "
                      "and superquadric"));
  EXPECT_TRUE(refused("", 14, core_path,
                      "expected exactly one of the keys mesh, superquadric, harmonics, got none"));
}

TEST(CoreSceneKeys, SuperquadricKeysAndRanges) {
  EXPECT_TRUE(refused("      superquadric: {a: 1, b: 1, c: 1, n1: 0.5, n2: 2}\n", 17,
                      core_path + ".superquadric.n1",
                      "expected an exponent in [1, 20], got \"0.5\""));
  EXPECT_TRUE(refused("      superquadric: {a: 1, b: 1, c: 1, n1: 2, n2: 25}\n", 17,
                      core_path + ".superquadric.n2",
                      "expected an exponent in [1, 20], got \"25\""));
  EXPECT_TRUE(refused("      superquadric: {a: 1, b: 0, c: 1, n1: 2, n2: 2}\n", 17,
                      core_path + ".superquadric.b", "expected a positive number in m, got \"0\""));
  EXPECT_TRUE(refused("      superquadric: {a: 1, b: 1, n1: 2, n2: 2}\n", 17,
                      core_path + ".superquadric.c", "required key is missing"));
}

TEST(CoreSceneKeys, NodeCount) {
  const std::string sphere = "      superquadric: {a: 1, b: 1, c: 1, n1: 2, n2: 2}\n";
  EXPECT_TRUE(refused(sphere + "      nodes: 3\n", 18, core_path + ".nodes",
                      "expected a whole number >= 4, got \"3\""));
  EXPECT_TRUE(refused(sphere + "      nodes: 20.5\n", 18, core_path + ".nodes",
                      "expected a whole number >= 4"));
  EXPECT_TRUE(refused("      mesh: box.obj\n      nodes: 300\n", 18, core_path + ".nodes",
                      "expected nodes only with a superquadric or harmonics core, not with mesh"));
}

TEST(CoreSceneKeys, HarmonicCoefficients) {
  const std::string path = core_path + ".harmonics.coefficients";
  EXPECT_TRUE(refused("      harmonics: {coefficients: [[0, 0, 1, 0], [1, 0, 5, 0]]}\n", 17, path,
                      "expected coefficients whose radius is positive at every node"));
  EXPECT_TRUE(refused("      harmonics: {coefficients: [[0, 0, 1, 0], [1, 2, 0.1, 0]]}\n", 17,
                      path + "[1][1]", "expected an order m in [0, n] (n = 1), got \"2\""));
  EXPECT_TRUE(refused("      harmonics: {coefficients: [[0, 0, 1, 0], [0, 0, 2, 0]]}\n", 17,
                      path + "[1]", "expected each (n, m) once"));
  EXPECT_TRUE(refused("      harmonics: {coefficients: [[0, 0, 1]]}\n", 17, path + "[0]",
                      "expected a coefficient [n, m, re, im]"));
  EXPECT_TRUE(refused("      harmonics: {coefficients: []}\n", 17, path,
                      "expected a list of coefficients [n, m, re, im]"));
}

TEST(CoreSceneKeys, HullOfPointsThatSpanNoVolume) {
  ScratchFolder folder;
  // A square as two triangles on each side: a closed surface of zero volume, in one plane.
  folder.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\nf 1 3 2\n"
                           "f 1 4 3\n");
  EXPECT_TRUE(
      refused("      mesh: flat.obj\n      convex_hull: true\n", 18, core_path + ".convex_hull",
              "(the points of the convex hull are coplanar: they span no volume)", folder.path()));
}

TEST(CoreSceneKeys, SimplificationTarget) {
  const std::string sphere = "      superquadric: {a: 1, b: 1, c: 1, n1: 2, n2: 2}\n";
  // The default 1000 nodes: 1996 triangles.
  EXPECT_TRUE(refused(sphere + "      simplify_to: 1996\n", 18, core_path + ".simplify_to",
                      "expected a whole number of faces >= 4 and below the core's 1996, got "
                      "\"1996\""));
  EXPECT_TRUE(refused(sphere + "      simplify_to: 3\n", 18, core_path + ".simplify_to",
                      "expected a whole number >= 4, got \"3\""));
}

} // namespace
