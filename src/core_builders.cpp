// Builders of dilated-polyhedron cores: Fibonacci directions, their hull, the superquadric and
// spherical-harmonic radial maps, convex hulls (qhull, reentrant C API) and simplification
// (VTK's quadric decimation).
#include "core_builders.hpp"

#include <libqhull_r/qhull_ra.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricDecimation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace kdem {
namespace {

constexpr double pi = 3.14159265358979323846;

Point3 difference(const Point3& p, const Point3& q) {
  return {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
}

Point3 cross(const Point3& p, const Point3& q) {
  return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}

double dot(const Point3& p, const Point3& q) {
  return p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
}

double length(const Point3& p) {
  return std::sqrt(dot(p, p));
}

// ---- degenerate point sets ----------------------------------------------------------------------

// Relative to the points' extent: spans below this are rounding, not volume.
constexpr double flatness_tolerance = 1e-10;

template <class Distance>
const Point3& farthest(const std::vector<Point3>& points, Distance distance) {
  return *std::max_element(points.begin(), points.end(), [&](const Point3& p, const Point3& q) {
    return distance(p) < distance(q);
  });
}

Point3 unit(const Point3& p) {
  const double l = length(p);
  return {p[0] / l, p[1] / l, p[2] / l};
}

// Refuses points that span no volume, saying how they lie; qhull would stop on them with a
// message about its initial simplex.
void require_volume(const std::vector<Point3>& points) {
  if (points.size() < 4)
    throw std::invalid_argument("a convex hull needs at least 4 points that span a volume, got " +
                                std::to_string(points.size()));
  for (const Point3& p : points)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw std::invalid_argument("a convex hull needs finite coordinates");
  const Point3& first = points[0];
  const auto from_first = [&](const Point3& p) { return length(difference(p, first)); };
  const Point3& far = farthest(points, from_first);
  const double extent = from_first(far);
  if (!(extent > 0))
    throw std::invalid_argument("the points of the convex hull all coincide");
  const Point3 line = unit(difference(far, first));
  const auto from_line = [&](const Point3& p) { return length(cross(difference(p, first), line)); };
  const Point3& off_line = farthest(points, from_line);
  if (!(from_line(off_line) > flatness_tolerance * extent))
    throw std::invalid_argument("the points of the convex hull are collinear: they span no volume");
  const Point3 normal = unit(cross(line, difference(off_line, first)));
  const auto from_plane = [&](const Point3& p) {
    return std::fabs(dot(difference(p, first), normal));
  };
  if (!(from_plane(farthest(points, from_plane)) > flatness_tolerance * extent))
    throw std::invalid_argument("the points of the convex hull are coplanar: they span no volume");
}

// ---- qhull
// ----------------------------------------------------------------------------------------

// Qhull's messages, gathered in memory instead of printed.
class MessageBuffer {
public:
  MessageBuffer() : file_(open_memstream(&text_, &size_)) {}
  ~MessageBuffer() {
    if (file_)
      std::fclose(file_);
    std::free(text_);
  }
  MessageBuffer(const MessageBuffer&) = delete;
  MessageBuffer& operator=(const MessageBuffer&) = delete;

  FILE* file() const { return file_ ? file_ : stderr; }
  std::string first_line() {
    if (!file_)
      return "";
    std::fflush(file_);
    const std::string all(text_ ? text_ : "", size_);
    const auto start = all.find_first_not_of(" \n");
    if (start == std::string::npos)
      return "";
    return all.substr(start, all.find('\n', start) - start);
  }

private:
  char* text_ = nullptr;
  std::size_t size_ = 0;
  FILE* file_;
};

// One run of qhull with its memory released on every way out.
class Qhull {
public:
  explicit Qhull(FILE* messages) { qh_zero(&qh_, messages); }
  ~Qhull() {
    qh_freeqhull(&qh_, !qh_ALL);
    int unfreed_long = 0, unfreed_total = 0;
    qh_memfreeshort(&qh_, &unfreed_long, &unfreed_total);
  }
  Qhull(const Qhull&) = delete;
  Qhull& operator=(const Qhull&) = delete;

  qhT* get() { return &qh_; }

private:
  qhT qh_;
};

// The hull's triangles as input point numbers, wound along each facet's outward normal.
// "Qt": merged (coplanar) facets come out triangulated.
std::vector<std::array<int, 3>> qhull_triangles(const std::vector<Point3>& points) {
  std::vector<coordT> coordinates;
  for (const Point3& p : points)
    coordinates.insert(coordinates.end(), p.begin(), p.end());
  MessageBuffer messages;
  Qhull hull(messages.file());
  qhT* qh = hull.get();
  char command[] = "qhull Qt";
  const int status = qh_new_qhull(qh, 3, int(points.size()), coordinates.data(), False, command,
                                  nullptr, messages.file());
  if (status != 0)
    throw std::invalid_argument("qhull could not build the convex hull: " + messages.first_line());
  std::vector<std::array<int, 3>> triangles;
  facetT* facet = nullptr;
  vertexT *vertex = nullptr, **vertexp = nullptr;
  FORALLfacets {
    std::array<int, 3> corners{};
    int corner = 0;
    FOREACHvertex_(facet->vertices) {
      if (corner < 3)
        corners[std::size_t(corner)] = qh_pointid(qh, vertex->point);
      ++corner;
    }
    if (corner != 3)
      throw std::logic_error("qhull gave a hull facet of " + std::to_string(corner) +
                             " vertices despite option Qt");
    const Point3 normal{facet->normal[0], facet->normal[1], facet->normal[2]};
    const Point3& a = points[std::size_t(corners[0])];
    const Point3 wound = cross(difference(points[std::size_t(corners[1])], a),
                               difference(points[std::size_t(corners[2])], a));
    if (dot(wound, normal) < 0)
      std::swap(corners[1], corners[2]);
    triangles.push_back(corners);
  }
  return triangles;
}

// The points the triangles use, renumbered in input order.
TriangleMesh used_points_only(const std::vector<Point3>& points,
                              std::vector<std::array<int, 3>> triangles) {
  std::vector<int> renumbered(points.size(), -1);
  for (const auto& t : triangles)
    for (int v : t)
      renumbered[std::size_t(v)] = 0;
  TriangleMesh mesh;
  for (std::size_t k = 0; k < points.size(); ++k)
    if (renumbered[k] == 0) {
      renumbered[k] = int(mesh.points.size());
      mesh.points.push_back(points[k]);
    }
  for (auto& t : triangles)
    for (int& v : t)
      v = renumbered[std::size_t(v)];
  mesh.triangles = std::move(triangles);
  return mesh;
}

// Each directed edge once and its reverse once: the mesh is closed, every edge in two triangles,
// consistently wound.
void require_closed_and_wound(const TriangleMesh& mesh, const std::string& made_by) {
  std::vector<std::pair<int, int>> edges;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      edges.emplace_back(t[std::size_t(k)], t[std::size_t((k + 1) % 3)]);
  std::sort(edges.begin(), edges.end());
  const bool repeated = std::adjacent_find(edges.begin(), edges.end()) != edges.end();
  const bool unpaired = std::any_of(edges.begin(), edges.end(), [&](const auto& e) {
    return !std::binary_search(edges.begin(), edges.end(), std::make_pair(e.second, e.first));
  });
  if (repeated || unpaired)
    throw std::invalid_argument(made_by + " gave a mesh that is not closed and consistently "
                                          "wound");
}

// ---- radial maps --------------------------------------------------------------------------------

// The Fibonacci sphere with node k moved to radius(direction k) along its direction.
template <class Radius> TriangleMesh radial_core(int nodes, Radius radius) {
  TriangleMesh mesh = fibonacci_sphere(nodes);
  for (Point3& p : mesh.points) {
    const double r = radius(p);
    p = {r * p[0], r * p[1], r * p[2]};
  }
  return mesh;
}

double polar_angle(const Point3& direction) {
  return std::acos(std::clamp(direction[2], -1.0, 1.0));
}

double azimuth(const Point3& direction) {
  return std::atan2(direction[1], direction[0]);
}

// sqrt((2n+1)(n-m)! / (4 pi (n+m)!)) P_n^m(x), P_n^m with the Condon-Shortley phase, by the
// stable recurrences in m and then n of the normalised functions (Press et al., Numerical Recipes,
// 3rd ed., Sect. 6.7), which no factorial overflows.
double normalised_legendre(int n, int m, double x) {
  const double sine = std::sqrt(std::max(0.0, (1 - x) * (1 + x)));
  double diagonal = 1 / std::sqrt(4 * pi);
  for (int k = 1; k <= m; ++k)
    diagonal *= -std::sqrt((2.0 * k + 1) / (2.0 * k)) * sine;
  if (n == m)
    return diagonal;
  double below = diagonal, current = x * std::sqrt(2.0 * m + 3) * diagonal;
  for (int l = m + 2; l <= n; ++l) {
    const double l2 = double(l) * l, k2 = double(l - 1) * (l - 1), m2 = double(m) * m;
    const double next = std::sqrt((4 * l2 - 1) / (l2 - m2)) *
                        (x * current - std::sqrt((k2 - m2) / (4 * k2 - 1)) * below);
    below = current;
    current = next;
  }
  return current;
}

// Digest A1.3: A_{n,-m} = (-1)^m conj(A_nm) keeps r real, and P_n^{-m} = (-1)^m (n-m)!/(n+m)!
// P_n^m gives Y_n^{-m} = (-1)^m conj(Y_n^m): the same map serves both.
std::complex<double> negative_order(std::complex<double> z, int m) {
  return (m % 2 == 0 ? 1.0 : -1.0) * std::conj(z);
}

void require_valid_coefficients(const std::vector<HarmonicCoefficient>& coefficients) {
  if (coefficients.empty())
    throw std::invalid_argument("a harmonic surface needs at least one coefficient");
  std::set<std::pair<int, int>> seen;
  for (const HarmonicCoefficient& c : coefficients) {
    const std::string name = "A_" + std::to_string(c.n) + "," + std::to_string(c.m);
    if (c.n < 0 || c.m < 0 || c.m > c.n)
      throw std::invalid_argument("coefficient " + name + ": needs 0 <= m <= n");
    if (!std::isfinite(c.real) || !std::isfinite(c.imag))
      throw std::invalid_argument("coefficient " + name + " is not finite");
    if (!seen.insert({c.n, c.m}).second)
      throw std::invalid_argument("coefficient " + name + " is given twice");
  }
}

std::string angle_text(double radians) {
  std::ostringstream text;
  text.precision(4);
  text << radians * 180 / pi << " degrees";
  return text.str();
}

// ---- VTK
// ------------------------------------------------------------------------------------------

// The mesh's box centred at the origin and scaled to a largest side of 1. VTK's quadric decimation
// tests its placement matrices against fixed thresholds, so in the scene's units it decides
// differently for a body of millimetres and one of metres (measured: the same superquadric lost
// 2.50e-3 of its volume at 0.1 mm, 2.26e-3 at 1 mm); in the unit frame the result is the same.
struct UnitFrame {
  Point3 centre{};
  double size = 1;

  explicit UnitFrame(const std::vector<Point3>& points) {
    Point3 lowest{1e300, 1e300, 1e300}, highest{-1e300, -1e300, -1e300};
    for (const Point3& p : points)
      for (std::size_t k = 0; k < 3; ++k) {
        lowest[k] = std::min(lowest[k], p[k]);
        highest[k] = std::max(highest[k], p[k]);
      }
    size = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      centre[k] = 0.5 * (lowest[k] + highest[k]);
      size = std::max(size, highest[k] - lowest[k]);
    }
  }
  Point3 to_unit(const Point3& p) const {
    return {(p[0] - centre[0]) / size, (p[1] - centre[1]) / size, (p[2] - centre[2]) / size};
  }
  Point3 from_unit(const Point3& p) const {
    return {centre[0] + size * p[0], centre[1] + size * p[1], centre[2] + size * p[2]};
  }
};

vtkNew<vtkPolyData> to_poly_data(const TriangleMesh& mesh, const UnitFrame& frame) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const Point3& p : mesh.points)
    points->InsertNextPoint(frame.to_unit(p).data());
  vtkNew<vtkCellArray> triangles;
  for (const auto& t : mesh.triangles) {
    const vtkIdType corners[3] = {t[0], t[1], t[2]};
    triangles->InsertNextCell(3, corners);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(triangles);
  return poly;
}

TriangleMesh from_poly_data(vtkPolyData* poly, const UnitFrame& frame) {
  std::vector<Point3> points(std::size_t(poly->GetNumberOfPoints()));
  for (vtkIdType k = 0; k < poly->GetNumberOfPoints(); ++k) {
    Point3& p = points[std::size_t(k)];
    poly->GetPoint(k, p.data());
    p = frame.from_unit(p);
  }
  std::vector<std::array<int, 3>> triangles;
  vtkCellArray* cells = poly->GetPolys();
  vtkIdType corner_count = 0;
  const vtkIdType* corners = nullptr;
  for (cells->InitTraversal(); cells->GetNextCell(corner_count, corners);) {
    if (corner_count != 3)
      throw std::logic_error("the decimation gave a polygon of " + std::to_string(corner_count) +
                             " corners");
    triangles.push_back({int(corners[0]), int(corners[1]), int(corners[2])});
  }
  return used_points_only(points, std::move(triangles));
}

// VTK 9.1's quadric decimation returns its points in single precision (measured: a kept box
// corner 1e-8 of the box's size off). A point within `reach` of an input point is that input point,
// not moved by the decimation: it gets the input's coordinates back.
void restore_kept_points(TriangleMesh& simplified, const std::vector<Point3>& original,
                         double reach) {
  std::vector<std::size_t> by_x(original.size());
  for (std::size_t k = 0; k < by_x.size(); ++k)
    by_x[k] = k;
  std::sort(by_x.begin(), by_x.end(),
            [&](std::size_t i, std::size_t j) { return original[i][0] < original[j][0]; });
  for (Point3& p : simplified.points) {
    auto first = std::lower_bound(by_x.begin(), by_x.end(), p[0] - reach,
                                  [&](std::size_t k, double x) { return original[k][0] < x; });
    double nearest = reach;
    const Point3* kept = nullptr;
    for (; first != by_x.end() && original[*first][0] <= p[0] + reach; ++first) {
      const double d = length(difference(original[*first], p));
      if (d <= nearest) {
        nearest = d;
        kept = &original[*first];
      }
    }
    if (kept)
      p = *kept;
  }
}

} // namespace

std::vector<Point3> fibonacci_directions(int count) {
  if (count < 4)
    throw std::invalid_argument("a lattice of directions needs at least 4 nodes, got " +
                                std::to_string(count));
  // Book Eq. 4.3: lambda the golden ratio, eps = 0.36 (the book's, found empirically).
  const double golden_ratio = 0.5 * (1 + std::sqrt(5.0));
  const double offset = 0.36;
  std::vector<Point3> directions;
  for (int i = 0; i < count; ++i) {
    const double azimuth_of_node = 2 * pi * i / golden_ratio;
    const double cos_polar = 1 - 2 * (i + offset) / (count - 1 + 2 * offset);
    const double sin_polar = std::sqrt(std::max(0.0, 1 - cos_polar * cos_polar));
    directions.push_back(
        {sin_polar * std::cos(azimuth_of_node), sin_polar * std::sin(azimuth_of_node), cos_polar});
  }
  return directions;
}

TriangleMesh convex_hull_core(const std::vector<Point3>& points) {
  require_volume(points);
  TriangleMesh hull = used_points_only(points, qhull_triangles(points));
  require_closed_and_wound(hull, "qhull");
  return hull;
}

TriangleMesh fibonacci_sphere(int count) {
  TriangleMesh sphere = convex_hull_core(fibonacci_directions(count));
  if (sphere.points.size() != std::size_t(count))
    throw std::logic_error("only " + std::to_string(sphere.points.size()) + " of " +
                           std::to_string(count) + " unit directions are hull vertices");
  return sphere;
}

TriangleMesh superquadric_core(double a, double b, double c, double n1, double n2, int nodes) {
  for (double size : {a, b, c})
    if (!(size > 0) || !std::isfinite(size))
      throw std::invalid_argument("a superquadric needs positive semi-axes a, b, c");
  for (double exponent : {n1, n2})
    if (!(exponent > 0) || !std::isfinite(exponent))
      throw std::invalid_argument("a superquadric needs positive exponents n1, n2");
  return radial_core(nodes, [&](const Point3& u) {
    const double section =
        std::pow(std::pow(std::fabs(u[0] / a), n2) + std::pow(std::fabs(u[1] / b), n2), n1 / n2);
    const double radius = std::pow(section + std::pow(std::fabs(u[2] / c), n1), -1 / n1);
    if (!(radius > 0) || !std::isfinite(radius))
      throw std::invalid_argument("the superquadric's radius overflows; give its semi-axes in "
                                  "units nearer 1 and use scale");
    return radius;
  });
}

std::complex<double> spherical_harmonic(int n, int m, double theta, double phi) {
  return normalised_legendre(n, m, std::cos(theta)) * std::polar(1.0, m * phi);
}

double harmonic_radius(const std::vector<HarmonicCoefficient>& coefficients, double theta,
                       double phi) {
  std::complex<double> sum = 0;
  for (const HarmonicCoefficient& c : coefficients) {
    const std::complex<double> coefficient(c.real, c.imag);
    const std::complex<double> harmonic = spherical_harmonic(c.n, c.m, theta, phi);
    sum += coefficient * harmonic;
    if (c.m > 0)
      sum += negative_order(coefficient, c.m) * negative_order(harmonic, c.m);
  }
  return sum.real();
}

TriangleMesh harmonic_core(const std::vector<HarmonicCoefficient>& coefficients, int nodes) {
  require_valid_coefficients(coefficients);
  return radial_core(nodes, [&](const Point3& u) {
    const double theta = polar_angle(u), phi = azimuth(u);
    const double radius = harmonic_radius(coefficients, theta, phi);
    if (!(radius > 0))
      throw std::invalid_argument(
          "the radius is not positive in every direction: r = " + std::to_string(radius) +
          " at polar angle " + angle_text(theta) + ", azimuth " + angle_text(phi));
    return radius;
  });
}

TriangleMesh simplify_core(const TriangleMesh& mesh, int target_faces) {
  const std::size_t faces = mesh.triangles.size();
  if (target_faces < 4 || std::size_t(target_faces) >= faces)
    throw std::invalid_argument("the target face count must be at least 4 and below the mesh's " +
                                std::to_string(faces) + ", got " + std::to_string(target_faces));
  const UnitFrame frame(mesh.points);
  vtkNew<vtkQuadricDecimation> decimation;
  decimation->SetInputData(to_poly_data(mesh, frame));
  decimation->SetTargetReduction(1 - double(target_faces) / double(faces));
  decimation->Update();
  TriangleMesh simplified = from_poly_data(decimation->GetOutput(), frame);
  // Far above single-precision rounding in the unit frame (6e-8), far below any mesh spacing.
  restore_kept_points(simplified, mesh.points, 1e-6 * frame.size);
  require_closed_and_wound(simplified, "the decimation");
  return simplified;
}

TriangleMesh zero_level_surface(const Point3& origin, double spacing,
                                const std::array<int, 3>& nodes,
                                const std::vector<double>& values) {
  const std::size_t count = std::size_t(nodes[0]) * std::size_t(nodes[1]) * std::size_t(nodes[2]);
  if (!(spacing > 0) || nodes[0] < 2 || nodes[1] < 2 || nodes[2] < 2 || values.size() != count)
    throw std::invalid_argument("a grid needs a positive spacing, 2 nodes or more per axis and a "
                                "value per node");
  vtkNew<vtkImageData> image;
  image->SetDimensions(nodes[0], nodes[1], nodes[2]);
  image->SetOrigin(origin[0], origin[1], origin[2]);
  image->SetSpacing(spacing, spacing, spacing);
  vtkNew<vtkDoubleArray> scalars;
  scalars->SetNumberOfTuples(vtkIdType(count));
  for (std::size_t k = 0; k < count; ++k)
    scalars->SetValue(vtkIdType(k), values[k]);
  image->GetPointData()->SetScalars(scalars);
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, 0.0);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  vtkPolyData* poly = contour->GetOutput();
  TriangleMesh surface;
  for (vtkIdType k = 0; k < poly->GetNumberOfPoints(); ++k) {
    Point3 p;
    poly->GetPoint(k, p.data());
    surface.points.push_back(p);
  }
  vtkCellArray* cells = poly->GetPolys();
  vtkIdType corner_count = 0;
  const vtkIdType* corners = nullptr;
  for (cells->InitTraversal(); cells->GetNextCell(corner_count, corners);)
    if (corner_count == 3)
      surface.triangles.push_back({int(corners[0]), int(corners[1]), int(corners[2])});
  if (surface.triangles.empty())
    throw std::invalid_argument("the grid holds no zero level set (no value changes sign)");
  return surface;
}

double enclosed_volume(const TriangleMesh& mesh) {
  double six_volume = 0;
  for (const auto& t : mesh.triangles)
    six_volume += dot(mesh.points[std::size_t(t[0])],
                      cross(mesh.points[std::size_t(t[1])], mesh.points[std::size_t(t[2])]));
  return six_volume / 6;
}

} // namespace kdem
