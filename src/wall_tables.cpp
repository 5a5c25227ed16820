#include "wall_tables.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "../kernels/walls.hpp"
#include "../shapes/wall_geometry.hpp"
#include "host_copy.hpp"

namespace kdem {

namespace {

Vec3 vertex_of(const std::array<double, 9>& g, int v) {
  return {g[3 * v], g[3 * v + 1], g[3 * v + 2]};
}

// Box of the triangles of elements [first, end) grown by `reach`.
void grown_box(const WallElementTable& table, int first, int end, double reach, double lo[3],
               double hi[3]) {
  for (int a = 0; a < 3; ++a)
    lo[a] = 1e300, hi[a] = -1e300;
  for (int e = first; e < end; ++e)
    for (int v = 0; v < 3; ++v)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], table.geometry[e][3 * v + a] - reach);
        hi[a] = std::max(hi[a], table.geometry[e][3 * v + a] + reach);
      }
}

// Sizes the grid of `wall` over [lo, hi]: cells of the reach, grown by a quarter until the grid has
// at most max_cells cells.
void size_grid(WallLookup& wall, const double lo[3], const double hi[3], double reach,
               long max_cells) {
  wall.cell_size = reach;
  for (;;) {
    double total = 1; // counted in doubles: a tiny cell must not overflow the integers
    for (int a = 0; a < 3; ++a) {
      wall.origin[a] = lo[a];
      total *= 1 + std::floor((hi[a] - lo[a]) / wall.cell_size);
    }
    if (total <= double(max_cells))
      break;
    wall.cell_size *= 1.25;
  }
  for (int a = 0; a < 3; ++a)
    wall.dims[a] = 1 + int(std::floor((hi[a] - lo[a]) / wall.cell_size));
}

// A box beyond the doubles (a particle reach of 1e300 m, say) cannot hold a grid.
bool finite_box(const double lo[3], const double hi[3]) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(hi[a] - lo[a]))
      return false;
  return true;
}

// Index range along axis a of the cells whose centres may lie within `distance` of [lo, hi].
void cell_range(const WallLookup& wall, int a, double lo, double hi, double distance, int& first,
                int& last) {
  const double h = wall.cell_size;
  first = std::max(0, int(std::floor((lo - distance - wall.origin[a]) / h)));
  last = std::min(wall.dims[a] - 1, int(std::floor((hi + distance - wall.origin[a]) / h)));
}

// Appends (cell, element) for every cell of `wall` whose centre lies within `distance` of
// triangle e.
void bin_triangle(const WallElementTable& table, const WallLookup& wall, int e, double distance,
                  std::vector<std::pair<int, int>>& cell_element) {
  const std::array<double, 9>& g = table.geometry[e];
  const Vec3 a = vertex_of(g, 0), b = vertex_of(g, 1), c = vertex_of(g, 2);
  int first[3], last[3];
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = std::min({g[axis], g[3 + axis], g[6 + axis]});
    const double hi = std::max({g[axis], g[3 + axis], g[6 + axis]});
    cell_range(wall, axis, lo, hi, distance, first[axis], last[axis]);
  }
  const double h = wall.cell_size;
  for (int z = first[2]; z <= last[2]; ++z)
    for (int y = first[1]; y <= last[1]; ++y)
      for (int x = first[0]; x <= last[0]; ++x) {
        const Vec3 centre{wall.origin[0] + (x + 0.5) * h, wall.origin[1] + (y + 0.5) * h,
                          wall.origin[2] + (z + 0.5) * h};
        if (triangle_query(a, b, c, centre).signed_distance <= distance)
          cell_element.emplace_back(x + wall.dims[0] * (y + wall.dims[1] * z), e);
      }
}

// Appends the cell lists of a mesh wall's grid to `cells`, ascending by element within a cell.
void bin_mesh_wall(const WallElementTable& table, WallLookup& wall, double reach,
                   HostRaggedTable& cells) {
  const int triangles = wall.end_element - wall.first_element;
  double lo[3], hi[3];
  grown_box(table, wall.first_element, wall.end_element, reach, lo, hi);
  wall.reach = reach;
  wall.first_cell = cells.rows();
  if (!finite_box(lo, hi)) {
    wall.cell_size = 0; // no grid: every element is a candidate of every particle
    return;
  }
  size_grid(wall, lo, hi, reach, std::max(4096L, 16L * triangles));
  // Relative margin: the distance test must not drop a triangle at rounding level.
  const double distance = (reach + 0.5 * std::sqrt(3.0) * wall.cell_size) * (1 + 1e-9);
  std::vector<std::pair<int, int>> cell_element;
  for (int e = wall.first_element; e < wall.end_element; ++e)
    bin_triangle(table, wall, e, distance, cell_element);
  const int cell_count = wall.dims[0] * wall.dims[1] * wall.dims[2];
  std::vector<int> count(cell_count + 1, 0);
  for (const auto& ce : cell_element)
    ++count[ce.first + 1];
  for (int c = 0; c < cell_count; ++c)
    count[c + 1] += count[c];
  const std::size_t base = cells.values.size();
  cells.values.resize(base + cell_element.size());
  std::vector<int> next(count.begin(), count.end() - 1);
  for (const auto& ce : cell_element) // elements ascending, so each cell's list is ascending
    cells.values[base + next[ce.first]++] = ce.second;
  for (int c = 0; c < cell_count; ++c)
    cells.offsets.push_back(int(base) + count[c + 1]);
}

// The device rows of the elements' geometry: the table's nine numbers, then for a triangle what
// face_claims tests: for each of its edges the position of the edge's first vertex and the
// edge's outward direction from the triangle's side (side 0 for the edge's owner, 1 otherwise),
// copied from the edge tables.
std::vector<std::array<double, 27>> geometry_rows(const WallElementTable& table) {
  std::vector<std::array<double, 27>> rows(table.kind.size());
  for (std::size_t e = 0; e < table.kind.size(); ++e) {
    rows[e].fill(0);
    std::copy(table.geometry[e].begin(), table.geometry[e].end(), rows[e].begin());
    if (table.kind[e] != triangle_element)
      continue;
    for (int k = 0; k < 3; ++k) {
      const int edge = table.features[e][k];
      const int side = table.edge_owner[edge] == int(e) ? 0 : 1;
      const auto& start = table.vertex_position[table.edge_vertices[edge][0]];
      for (int a = 0; a < 3; ++a) {
        rows[e][9 + 6 * k + a] = start[a];
        rows[e][12 + 6 * k + a] = table.edge_outward[edge][3 * side + a];
      }
    }
  }
  return rows;
}

} // namespace

WallBinTable bin_wall_elements(const WallElementTable& table, int wall_count, double reach) {
  if (!(reach > 0) || !std::isfinite(reach))
    throw std::invalid_argument("wall bins need a positive, finite reach");
  WallBinTable bins;
  bins.reach = reach;
  bins.walls.resize(wall_count);
  const int elements = int(table.wall.size());
  for (int e = 0; e < elements;) {
    const int w = table.wall[e];
    WallLookup& wall = bins.walls[w];
    wall.first_element = e;
    while (e < elements && table.wall[e] == w)
      ++e;
    wall.end_element = e;
    const bool mesh = std::all_of(table.kind.begin() + wall.first_element, table.kind.begin() + e,
                                  [](int kind) { return kind == triangle_element; });
    if (mesh)
      bin_mesh_wall(table, wall, reach, bins.cells);
  }
  return bins;
}

WallElements upload_wall_elements(const WallElementTable& table) {
  WallElements el;
  el.count = int(table.kind.size());
  el.kind = upload<int>("wall_element_kind", table.kind);
  el.wall = upload<int>("wall_element_wall", table.wall);
  el.geometry =
      upload_rows<DeviceView<double* [27]>>("wall_element_geometry", geometry_rows(table));
  el.features = upload_rows<DeviceView<int* [6]>>("wall_element_features", table.features);
  el.edge_owner = upload<int>("wall_edge_owner", table.edge_owner);
  el.edge_sides = upload<int>("wall_edge_sides", table.edge_sides);
  el.edge_outward = upload_rows<DeviceView<double* [6]>>("wall_edge_outward", table.edge_outward);
  el.feature_tolerance = table.feature_tolerance;
  el.edge_vertices = upload_rows<DeviceView<int* [2]>>("wall_edge_vertices", table.edge_vertices);
  el.edge_direction = upload_rows<Vec3View>("wall_edge_direction", table.edge_direction);
  el.vertex_position = upload_rows<Vec3View>("wall_vertex_position", table.vertex_position);
  el.vertex_triangle_start = upload<int>("wall_vertex_triangle_start", table.vertex_triangle_start);
  el.vertex_triangle = upload<int>("wall_vertex_triangle", table.vertex_triangle);
  el.vertex_owner = upload<int>("wall_vertex_owner", table.vertex_owner);
  el.vertex_edge_start = upload<int>("wall_vertex_edge_start", table.vertex_edge_start);
  el.vertex_edge_direction =
      upload_rows<Vec3View>("wall_vertex_edge_direction", table.vertex_edge_direction);
  el.triangle_normal = upload_rows<Vec3View>("wall_triangle_normal", table.triangle_normal);
  el.edge_triangles =
      upload_rows<DeviceView<int* [2]>>("wall_edge_triangles", table.edge_triangles);
  el.vertex_corner = upload<int>("wall_vertex_corner", table.vertex_corner);
  el.vertex_ring_start = upload<int>("wall_vertex_ring_start", table.vertex_ring_start);
  std::vector<Vec3> ring;
  for (const auto& p : table.vertex_ring)
    ring.push_back(Vec3{p[0], p[1], p[2]});
  el.vertex_ring = upload<Vec3>("wall_vertex_ring", ring);
  return el;
}

void upload_wall_lookup(WallSet& walls, const WallBinTable& bins) {
  walls.lookup = upload<WallLookup>("wall_lookup", bins.walls);
  walls.cells = RaggedTable<int>{upload<int>("wall_cell_elements", bins.cells.values),
                                 upload<int>("wall_cell_offsets", bins.cells.offsets)};
}

} // namespace kdem
