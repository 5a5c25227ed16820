#include "mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace kdem {
namespace {

using Point = std::array<double, 3>;

Point minus(const Point& a, const Point& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Point cross3(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot3(const Point& a, const Point& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Point unit(const Point& a) {
  const double n = std::sqrt(dot3(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

double bounding_diagonal(const TriangleMesh& mesh) {
  Point lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const Point& p : mesh.points)
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  const Point d = minus(hi, lo);
  return std::sqrt(dot3(d, d));
}

// Unit direction in the plane of triangle t, perpendicular to its edge (a, b), pointing away
// from the triangle's third vertex.
Point outward_in_plane(const TriangleMesh& mesh, int t, int a, int b) {
  const auto& tri = mesh.triangles[t];
  int third = tri[0];
  for (int v : tri)
    if (v != a && v != b)
      third = v;
  const Point edge = minus(mesh.points[b], mesh.points[a]);
  const Point normal = cross3(minus(mesh.points[tri[1]], mesh.points[tri[0]]),
                              minus(mesh.points[tri[2]], mesh.points[tri[0]]));
  Point out = unit(cross3(edge, normal));
  if (dot3(out, minus(mesh.points[third], mesh.points[a])) > 0)
    out = {-out[0], -out[1], -out[2]};
  return out;
}

} // namespace

namespace {

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension)
    c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

} // namespace

TriangleMesh read_stl(const std::string& path) {
  const TriangleMesh mesh = read_stl_unwelded(path);
  return weld(mesh, 1e-9 * bounding_diagonal(mesh));
}

TriangleMesh read_obj(const std::string& path) {
  const TriangleMesh mesh = read_obj_unwelded(path);
  return weld(mesh, 1e-9 * bounding_diagonal(mesh));
}

TriangleMesh read_mesh(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension == ".stl")
    return read_stl(path);
  if (extension == ".obj")
    return read_obj(path);
  throw std::runtime_error(path + ": expected a mesh file ending in .stl or .obj");
}

bool is_mesh_file_name(const std::string& path) {
  const std::string extension = lower_extension(path);
  return extension == ".stl" || extension == ".obj";
}

TriangleMesh weld(const TriangleMesh& mesh, double tolerance) {
  TriangleMesh result;
  std::map<std::array<long long, 3>, int> index_of_key;
  std::vector<int> new_index(mesh.points.size());
  const double cell = tolerance > 0 ? tolerance : 1e-300;
  for (std::size_t p = 0; p < mesh.points.size(); ++p) {
    std::array<long long, 3> key;
    for (int a = 0; a < 3; ++a)
      key[a] = std::llround(mesh.points[p][a] / cell);
    auto [it, inserted] = index_of_key.emplace(key, int(result.points.size()));
    if (inserted)
      result.points.push_back(mesh.points[p]);
    new_index[p] = it->second;
  }
  for (const auto& t : mesh.triangles) {
    const std::array<int, 3> mapped{new_index[t[0]], new_index[t[1]], new_index[t[2]]};
    if (mapped[0] == mapped[1] || mapped[1] == mapped[2] || mapped[0] == mapped[2])
      continue;
    const Point n = cross3(minus(result.points[mapped[1]], result.points[mapped[0]]),
                           minus(result.points[mapped[2]], result.points[mapped[0]]));
    if (dot3(n, n) == 0)
      continue;
    result.triangles.push_back(mapped);
  }
  return result;
}

TriangleMesh spatially_ordered(const TriangleMesh& mesh, const std::array<double, 3>& origin,
                               double cell) {
  std::vector<std::pair<std::array<long long, 3>, int>> order;
  for (int t = 0; t < int(mesh.triangles.size()); ++t) {
    std::array<double, 3> centroid{0, 0, 0};
    for (int v : mesh.triangles[t])
      for (int a = 0; a < 3; ++a)
        centroid[a] += mesh.points[v][a] / 3;
    // z, y, x: the order of the particles' cells. Triangles more than 2^40 cells away (or
    // with a cell that is not a number) sort at the ends: the order is only for locality.
    std::array<long long, 3> key{};
    constexpr double farthest_cell = 1099511627776.0;
    for (int a = 0; a < 3; ++a) {
      const double cell_index = std::floor((centroid[a] - origin[a]) / cell);
      key[2 - a] = (long long)(cell_index < farthest_cell
                                   ? (cell_index > -farthest_cell ? cell_index : -farthest_cell)
                                   : farthest_cell);
    }
    order.emplace_back(key, t);
  }
  std::sort(order.begin(), order.end());
  TriangleMesh result;
  std::vector<int> new_index(mesh.points.size(), -1);
  for (const auto& entry : order) {
    std::array<int, 3> mapped{};
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[entry.second][k];
      if (new_index[v] < 0) {
        new_index[v] = int(result.points.size());
        result.points.push_back(mesh.points[v]);
      }
      mapped[k] = new_index[v];
    }
    result.triangles.push_back(mapped);
  }
  return result;
}

MeshTopology build_topology(const TriangleMesh& mesh) {
  MeshTopology topo;
  std::map<std::pair<int, int>, int> edge_of_vertices;
  topo.vertex_triangles.resize(mesh.points.size());
  topo.vertex_edge_directions.resize(mesh.points.size());
  for (int t = 0; t < int(mesh.triangles.size()); ++t) {
    const auto& tri = mesh.triangles[t];
    std::array<int, 3> edges{};
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      const auto key = std::minmax(a, b);
      auto [it, inserted] = edge_of_vertices.emplace(key, int(topo.edge_vertices.size()));
      if (inserted) {
        topo.edge_vertices.push_back({key.first, key.second});
        topo.edge_triangles.emplace_back();
      }
      edges[k] = it->second;
      topo.edge_triangles[it->second].push_back(t);
      topo.vertex_triangles[tri[k]].push_back(t);
    }
    topo.triangle_edges.push_back(edges);
  }
  for (std::size_t e = 0; e < topo.edge_vertices.size(); ++e) {
    const auto [a, b] = topo.edge_vertices[e];
    std::array<double, 6> outward{};
    for (std::size_t side = 0; side < std::min<std::size_t>(2, topo.edge_triangles[e].size());
         ++side) {
      const Point out = outward_in_plane(mesh, topo.edge_triangles[e][side], a, b);
      std::copy(out.begin(), out.end(), outward.begin() + 3 * side);
    }
    topo.edge_outward.push_back(outward);
    const Point direction = unit(minus(mesh.points[b], mesh.points[a]));
    topo.edge_direction.push_back(direction);
    // Bit for bit the negation of `direction`: edge and vertex tests must read the same numbers.
    topo.vertex_edge_directions[a].push_back(direction);
    topo.vertex_edge_directions[b].push_back({-direction[0], -direction[1], -direction[2]});
  }
  return topo;
}

} // namespace kdem
