#pragma once
// Host-side construction of a level-set body (book chapter 5; digest ch4_5 B3, B4) from a closed
// triangle mesh: every source (a mesh file, a superquadric, spherical harmonics) goes through a
// mesh, as the book's unified construction does. Run once per shape template.
//
// - Grid (B4): the signed distance to the mesh at every node of a uniform grid over the mesh's
//   box widened by `padding` cells, exact for the mesh: the closest point by a branch-and-bound
//   walk of the core's sphere tree, the sign from the angle-weighted pseudonormal of the closest
//   feature (core_distance; Baerentzen and Aanaes 2005), which is robust where the book's
//   ray-parity rule has to guard against rays through edges and vertices.
// - Surface points (B3(b), applied to every source): candidates in the order vertices, points
//   along the edges, random points on the faces (area-weighted), each kept only when no kept
//   point lies within `point_spacing` (Poisson-disk rejection), so the points are near-uniform
//   and no two are closer than the spacing. Vertices come sharpest first (largest angle defect)
//   and edges sharpest first (largest dihedral turn), so that corners and ridges, where a flat
//   face meets a body first, keep their points.
// - Mass properties: of the mesh's interior, exact (signed tetrahedra from the origin).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "dilated_polyhedron_properties.hpp"
#include "level_set.hpp"
#include "sphere.hpp"
#include "volume_moments.hpp"

namespace kdem {

struct LevelSetOptions {
  double spacing = 0;       // m, the grid spacing (> 0)
  int padding = 2;          // cells of grid beyond the mesh's box on every side (>= 1)
  double point_spacing = 0; // m, the least distance between surface points (> 0)
  // When positive, the points are about this many instead (point_spacing is then chosen, see
  // spacing_for_count) and point_spacing is ignored.
  int point_count = 0;
  std::uint32_t seed = 1; // of the face candidates
  // Candidates drawn per point_spacing^2 of face area: enough that the rejection leaves no gap
  // wider than about twice the spacing.
  double candidates_per_area = 40;
  // Edge of the cells the points are sorted into, in point spacings (see point_cells_over).
  // Four (about 16 points to a cell of surface): as fast as two and faster than one in two
  // level-set bodies' pairs (docs/performance.md, section 28), with fewer cells.
  double cell_size_in_point_spacings = 4;
  long long max_nodes = 64ll << 20; // a larger grid is refused (8 bytes per node)
};

struct LevelSetBody {
  LevelSetGrid grid;
  std::vector<double> values;       // m, per node, negative inside
  std::vector<Vec3> surface_points; // sorted by cell
  double point_spacing = 0;         // m, the least distance between them
  LevelSetPointCells cells;         // the mesh's box and the cells over it
  std::vector<int> cell_first;      // per cell, its first point; then the point count
  BodyMassProperties mass;          // of the mesh's interior, in the mesh's frame
  double bounding_radius = 0;       // m, of the mesh about the frame's origin

  std::size_t grid_bytes() const { return values.size() * sizeof(double); }
  std::size_t point_bytes() const {
    return surface_points.size() * sizeof(Vec3) + cell_first.size() * sizeof(int);
  }
};

// The body as the contact code reads it, over the body's own storage (host).
inline LevelSetBodyView view_of(const LevelSetBody& body) {
  LevelSetBodyView v;
  v.grid = body.grid;
  v.values = body.values.data();
  v.points = body.surface_points.data();
  v.point_count = int(body.surface_points.size());
  v.reach = body.bounding_radius;
  v.cells = body.cells;
  v.cell_first = body.cell_first.data();
  return v;
}

namespace level_set_build {

// Exact volume moments of a closed, outward-wound mesh: the sum over its triangles of the signed
// tetrahedra (origin, a, b, c): volume det / 6, first moment V (a + b + c) / 4, second moment
// V / 20 (sum_k p_k p_k^T + S S^T) with S = a + b + c (the origin contributes nothing).
inline VolumeMoments mesh_moments(const DilatedCore& core) {
  VolumeMoments m;
  for (const CoreFace& f : core.faces) {
    const Vec3 a = core.vertex(f.vertex[0]).position, b = core.vertex(f.vertex[1]).position,
               c = core.vertex(f.vertex[2]).position;
    const double v = dot(a, cross(b, c)) / 6.0;
    const Vec3 s = a + b + c;
    m.volume += v;
    m.first += (v / 4.0) * s;
    const Mat3 second = outer(a, a) + outer(b, b) + outer(c, c) + outer(s, s);
    m.second = m.second + (v / 20.0) * second;
  }
  return m;
}

inline void check_options(const LevelSetOptions& o) {
  if (!(o.spacing > 0) || !std::isfinite(o.spacing))
    throw std::invalid_argument("the grid spacing must be positive, not " +
                                std::to_string(o.spacing));
  if (o.padding < 1)
    throw std::invalid_argument("the grid padding must be at least 1 cell, not " +
                                std::to_string(o.padding));
  if (o.point_count < 0 || o.point_count > 10000000)
    throw std::invalid_argument("the surface point count must be in [1, 1e7], not " +
                                std::to_string(o.point_count));
  if (o.point_count == 0 && (!(o.point_spacing > 0) || !std::isfinite(o.point_spacing)))
    throw std::invalid_argument("the surface-point spacing must be positive, not " +
                                std::to_string(o.point_spacing));
}

inline LevelSetGrid grid_over(const DilatedCore& core, const LevelSetOptions& o) {
  double lo[3], hi[3], origin[3];
  for (int a = 0; a < 3; ++a)
    lo[a] = hi[a] = core.vertex(0).position[a];
  for (const CoreVertex& v : core.vertices)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], v.position[a]);
      hi[a] = std::max(hi[a], v.position[a]);
    }
  LevelSetGrid grid;
  grid.spacing = o.spacing;
  int n[3];
  for (int a = 0; a < 3; ++a) {
    const double cells = std::ceil((hi[a] - lo[a]) / o.spacing);
    if (!(cells + 2.0 * o.padding + 1 < 1e6))
      throw std::invalid_argument("a grid spacing of " + std::to_string(o.spacing) +
                                  " m gives over a million nodes along an axis");
    n[a] = int(cells) + 2 * o.padding + 1;
    // The box is centred on the mesh's: the padding is the same on both sides.
    origin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * (n[a] - 1) * o.spacing;
  }
  grid.origin = Vec3{origin[0], origin[1], origin[2]};
  grid.nx = n[0], grid.ny = n[1], grid.nz = n[2];
  const long long nodes = (long long)n[0] * n[1] * n[2];
  if (nodes > o.max_nodes)
    throw std::invalid_argument("a grid spacing of " + std::to_string(o.spacing) + " m gives " +
                                std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " +
                                std::to_string(n[2]) + " nodes, more than the " +
                                std::to_string(o.max_nodes) + " allowed");
  return grid;
}

inline std::vector<double> signed_distances(const DilatedCore& core, const LevelSetGrid& grid) {
  std::vector<double> values(std::size_t(grid.nodes()));
  for (int k = 0; k < grid.nz; ++k)
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i)
        values[std::size_t(grid.index(i, j, k))] =
            core_distance(core, grid.node(i, j, k)).signed_distance;
  return values;
}

// Points kept at least `spacing` apart, found through a hash of cells of that size.
class PoissonPoints {
public:
  explicit PoissonPoints(double spacing) : spacing_(spacing) {}

  bool offer(Vec3 p) {
    const std::array<long long, 3> c = cell_of(p);
    for (long long dz = -1; dz <= 1; ++dz)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dx = -1; dx <= 1; ++dx) {
          const auto found = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (found == cells_.end())
            continue;
          for (int index : found->second)
            if (norm2(points_[std::size_t(index)] - p) < spacing_ * spacing_)
              return false;
        }
    cells_[key(c)].push_back(int(points_.size()));
    points_.push_back(p);
    return true;
  }
  const std::vector<Vec3>& points() const { return points_; }

private:
  std::array<long long, 3> cell_of(Vec3 p) const {
    return {(long long)std::floor(p.x / spacing_), (long long)std::floor(p.y / spacing_),
            (long long)std::floor(p.z / spacing_)};
  }
  static std::uint64_t key(const std::array<long long, 3>& c) {
    const std::uint64_t mask = (1ull << 21) - 1;
    return (std::uint64_t(c[0]) & mask) | ((std::uint64_t(c[1]) & mask) << 21) |
           ((std::uint64_t(c[2]) & mask) << 42);
  }
  double spacing_;
  std::vector<Vec3> points_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// Angle defect of each vertex (2 pi minus the angles of its triangles there): 0 on a flat or
// developable part, large at a corner.
inline std::vector<double> angle_defects(const DilatedCore& core) {
  std::vector<double> defect(core.vertices.size(), 2.0 * pi);
  for (const CoreFace& f : core.faces)
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = core.vertex(f.vertex[k]).position;
      const Vec3 u = core.vertex(f.vertex[(k + 1) % 3]).position - p;
      const Vec3 w = core.vertex(f.vertex[(k + 2) % 3]).position - p;
      defect[std::size_t(f.vertex[k])] -= std::atan2(norm(cross(u, w)), dot(u, w));
    }
  return defect;
}

// Indices 0 .. n - 1 by decreasing key, ties in index order.
inline std::vector<int> by_decreasing(const std::vector<double>& key) {
  std::vector<int> order(key.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = int(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return key[std::size_t(a)] > key[std::size_t(b)]; });
  return order;
}

// A uniform draw in [0, 1) from the generator's 32 bits (the same on every platform, unlike
// std::uniform_real_distribution).
inline double unit_draw(std::mt19937& random) {
  return double(random()) * (1.0 / 4294967296.0);
}

inline std::vector<Vec3> surface_points(const DilatedCore& core, const LevelSetOptions& o) {
  PoissonPoints kept(o.point_spacing);
  std::vector<double> defect = angle_defects(core);
  for (double& d : defect)
    d = std::fabs(d); // a saddle's defect is negative
  for (int v : by_decreasing(defect))
    kept.offer(core.vertex(v).position);
  std::vector<double> turn(core.edges.size());
  for (std::size_t e = 0; e < core.edges.size(); ++e) {
    // 0 where the faces are flat, 1 at a right angle, towards 2 at a knife edge (convex or
    // reflex alike).
    const CoreEdge& edge = core.edges[e];
    turn[e] = std::fabs(norm(cross(edge.inward[0], edge.inward[1])));
    if (dot(edge.inward[0], edge.inward[1]) > 0)
      turn[e] = 2.0 - turn[e];
  }
  for (int e : by_decreasing(turn)) {
    const Vec3 a = core.vertex(core.edges[std::size_t(e)].vertex[0]).position;
    const Vec3 b = core.vertex(core.edges[std::size_t(e)].vertex[1]).position;
    const int pieces = int(std::ceil(norm(b - a) / o.point_spacing));
    for (int s = 1; s < pieces; ++s)
      kept.offer(a + (double(s) / pieces) * (b - a));
  }
  std::mt19937 random(o.seed);
  for (const CoreFace& f : core.faces) {
    const Vec3 a = core.vertex(f.vertex[0]).position, b = core.vertex(f.vertex[1]).position,
               c = core.vertex(f.vertex[2]).position;
    const double area = 0.5 * norm(cross(b - a, c - a));
    const double expected = o.candidates_per_area * area / (o.point_spacing * o.point_spacing);
    // The whole part of the expected count, and one more with the probability of the rest.
    int count = int(expected);
    if (unit_draw(random) < expected - count)
      ++count;
    for (int s = 0; s < count; ++s) {
      double u = unit_draw(random), w = unit_draw(random);
      if (u + w > 1)
        u = 1 - u, w = 1 - w;
      kept.offer(a + u * (b - a) + w * (c - a));
    }
  }
  return kept.points();
}

// The spacing whose surface points number `count` within 1 % (or the closest found): the count
// falls as the spacing grows, so bisection on the spacing's logarithm, from a bracket of 8 times
// either way about sqrt(area / count), 40 halvings at most.
inline double spacing_for_count(const DilatedCore& core, LevelSetOptions o, int count) {
  double area = 0;
  for (const CoreFace& f : core.faces)
    area +=
        0.5 * norm(cross(core.vertex(f.vertex[1]).position - core.vertex(f.vertex[0]).position,
                         core.vertex(f.vertex[2]).position - core.vertex(f.vertex[0]).position));
  const double guess = std::sqrt(area / count);
  double lo = std::log(guess / 8), hi = std::log(guess * 8);
  double best = guess;
  long long best_miss = -1;
  for (int halving = 0; halving < 40; ++halving) {
    const double middle = 0.5 * (lo + hi);
    o.point_spacing = std::exp(middle);
    const long long found = static_cast<long long>(surface_points(core, o).size());
    const long long miss = std::llabs(found - count);
    if (best_miss < 0 || miss < best_miss)
      best = o.point_spacing, best_miss = miss;
    if (100 * miss <= count)
      break;
    (found > count ? lo : hi) = middle;
  }
  return best;
}

// Cells over the core's box: edges of `cell_size` (a few point spacings), at most 32 cells along
// the longest axis.
inline LevelSetPointCells point_cells_over(const DilatedCore& core, double cell_size) {
  LevelSetPointCells c;
  c.lo = c.hi = core.vertex(0).position;
  for (const CoreVertex& v : core.vertices) {
    const Vec3 x = v.position;
    c.lo = Vec3{std::min(c.lo.x, x.x), std::min(c.lo.y, x.y), std::min(c.lo.z, x.z)};
    c.hi = Vec3{std::max(c.hi.x, x.x), std::max(c.hi.y, x.y), std::max(c.hi.z, x.z)};
  }
  const Vec3 extent = c.hi - c.lo;
  const double longest = std::max({extent.x, extent.y, extent.z});
  c.size = std::max(cell_size, longest / 32);
  const auto cells_along = [&](double e) { return std::max(1, int(std::ceil(e / c.size))); };
  c.nx = cells_along(extent.x);
  c.ny = cells_along(extent.y);
  c.nz = cells_along(extent.z);
  return c;
}

// The body's points sorted by cell (in their kept order within a cell), and each cell's first.
inline void sort_into_cells(LevelSetBody& body) {
  const LevelSetPointCells& c = body.cells;
  std::vector<int> cell(body.surface_points.size());
  body.cell_first.assign(std::size_t(c.count()) + 1, 0);
  for (std::size_t q = 0; q < cell.size(); ++q) {
    cell[q] = c.cell_of(body.surface_points[q]);
    ++body.cell_first[std::size_t(cell[q]) + 1];
  }
  for (std::size_t k = 1; k < body.cell_first.size(); ++k)
    body.cell_first[k] += body.cell_first[k - 1];
  std::vector<int> next(body.cell_first.begin(), body.cell_first.end() - 1);
  std::vector<Vec3> sorted(body.surface_points.size());
  for (std::size_t q = 0; q < cell.size(); ++q)
    sorted[std::size_t(next[std::size_t(cell[q])]++)] = body.surface_points[q];
  body.surface_points = std::move(sorted);
}

} // namespace level_set_build

// The mass properties of a closed mesh's interior (points in its frame), with the checks of
// build_level_set.
inline BodyMassProperties mesh_mass_properties(const std::vector<Vec3>& points,
                                               const std::vector<std::array<int, 3>>& triangles) {
  // The core's dilation radius plays no part in its volume.
  return properties_of(level_set_build::mesh_moments(build_dilated_core(points, triangles, 1.0)),
                       Vec3{});
}

// The level-set body of a closed mesh (points in the body frame). Throws std::invalid_argument
// naming what is wrong: options out of range, a grid too large, or a mesh that is not a closed,
// consistently oriented 2-manifold enclosing a volume (build_dilated_core's checks).
inline LevelSetBody build_level_set(const std::vector<Vec3>& points,
                                    const std::vector<std::array<int, 3>>& triangles,
                                    const LevelSetOptions& options) {
  using namespace level_set_build;
  check_options(options);
  // The core's dilation radius plays no part in its distances.
  const DilatedCore core = build_dilated_core(points, triangles, options.spacing);
  LevelSetOptions chosen = options;
  if (options.point_count > 0)
    chosen.point_spacing = spacing_for_count(core, options, options.point_count);
  LevelSetBody body;
  body.grid = grid_over(core, chosen);
  body.values = signed_distances(core, body.grid);
  body.surface_points = surface_points(core, chosen);
  body.point_spacing = chosen.point_spacing;
  body.cells = point_cells_over(core, chosen.cell_size_in_point_spacings * chosen.point_spacing);
  sort_into_cells(body);
  body.mass = properties_of(mesh_moments(core), Vec3{});
  for (const CoreVertex& v : core.vertices)
    body.bounding_radius = std::max(body.bounding_radius, norm(v.position));
  body.bounding_radius += std::sqrt(3.0) * options.spacing;
  return body;
}

} // namespace kdem
