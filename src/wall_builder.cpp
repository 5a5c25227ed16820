#include "wall_builder.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "mesh.hpp"

namespace kdem {
namespace {

constexpr double two_pi = 6.283185307179586;

// Kinds as in kernels/walls.hpp (WallElementKind).
constexpr int plane_kind = 0, cylinder_kind = 1, triangle_kind = 2;

Vec3d sub(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3d add(const Vec3d& a, const Vec3d& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3d scaled(const Vec3d& a, double s) {
  return {s * a[0], s * a[1], s * a[2]};
}
double dot(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3d unit(const Vec3d& a) {
  return scaled(a, 1.0 / std::sqrt(dot(a, a)));
}

// Two unit vectors completing `n` to an orthonormal basis.
std::pair<Vec3d, Vec3d> tangent_basis(const Vec3d& n) {
  const Vec3d helper = std::abs(n[0]) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d u = unit(cross(n, helper));
  return {u, cross(n, u)};
}

struct SurfaceBuilder {
  std::vector<double> points;
  std::vector<int> triangles;
  int add_point(const Vec3d& p) {
    points.insert(points.end(), p.begin(), p.end());
    return int(points.size() / 3) - 1;
  }
  void add_quad(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d) {
    const int ia = add_point(a), ib = add_point(b), ic = add_point(c), id = add_point(d);
    triangles.insert(triangles.end(), {ia, ib, ic, ia, ic, id});
  }
};

void add_plane(WallElementTable& t, int wall, const Vec3d& origin, const Vec3d& normal) {
  t.triangle_normal.push_back({0, 0, 0});
  t.kind.push_back(plane_kind);
  t.wall.push_back(wall);
  t.geometry.push_back({origin[0], origin[1], origin[2], normal[0], normal[1], normal[2], 0, 0, 0});
  t.features.push_back({-1, -1, -1, -1, -1, -1});
}

void draw_plane_patch(SurfaceBuilder& s, const Vec3d& origin, const Vec3d& normal,
                      double half_size) {
  const auto basis = tangent_basis(normal);
  const Vec3d u = basis.first, v = basis.second;
  auto corner = [&](double a, double b) { return add(origin, add(scaled(u, a), scaled(v, b))); };
  s.add_quad(corner(-half_size, -half_size), corner(half_size, -half_size),
             corner(half_size, half_size), corner(-half_size, half_size));
}

void add_box(WallElementTable& t, SurfaceBuilder& s, int wall, const WallConfig& c) {
  static const char* names[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  for (int face = 0; face < 6; ++face) {
    if (std::find(c.open_faces.begin(), c.open_faces.end(), names[face]) != c.open_faces.end())
      continue;
    const int axis = face / 2;
    const bool upper = face % 2 == 1;
    Vec3d origin = upper ? c.max : c.min;
    Vec3d normal{0, 0, 0};
    normal[axis] = upper ? -1 : 1;
    add_plane(t, wall, origin, normal);
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    auto corner = [&](bool hi1, bool hi2) {
      Vec3d p = origin;
      p[a1] = hi1 ? c.max[a1] : c.min[a1];
      p[a2] = hi2 ? c.max[a2] : c.min[a2];
      return p;
    };
    s.add_quad(corner(false, false), corner(true, false), corner(true, true), corner(false, true));
  }
}

void add_cylinder(WallElementTable& t, SurfaceBuilder& s, int wall, const WallConfig& c) {
  t.kind.push_back(cylinder_kind);
  t.triangle_normal.push_back({0, 0, 0});
  t.wall.push_back(wall);
  const Vec3d& b = c.base_center;
  const Vec3d& a = c.axis_direction;
  t.geometry.push_back({b[0], b[1], b[2], a[0], a[1], a[2], c.radius, c.length, 0});
  t.features.push_back({-1, -1, -1, -1, -1, -1});
  const auto basis = tangent_basis(a);
  const Vec3d u = basis.first, v = basis.second;
  const int segments = 64;
  for (int k = 0; k < segments; ++k) {
    auto rim = [&](int m, double along) {
      const double phi = two_pi * m / segments;
      return add(add(b, scaled(a, along)),
                 add(scaled(u, c.radius * std::cos(phi)), scaled(v, c.radius * std::sin(phi))));
    };
    s.add_quad(rim(k, 0), rim(k + 1, 0), rim(k + 1, c.length), rim(k, c.length));
  }
}

int find_root(std::vector<int>& parent, int k) {
  while (parent[k] != k)
    k = parent[k] = parent[parent[k]];
  return k;
}

// A sphere's mesh contact decides between a face and its edges by each edge's in-plane
// directions on its two sides; an edge of three or more triangles has no such pair, and its
// contacts would be wrong, not merely approximate. Such meshes are refused with the edge named.
void refuse_non_manifold_edges(const TriangleMesh& mesh, const MeshTopology& topo,
                               const WallConfig& c) {
  for (std::size_t e = 0; e < topo.edge_triangles.size(); ++e) {
    if (topo.edge_triangles[e].size() <= 2)
      continue;
    const auto& a = mesh.points[topo.edge_vertices[e][0]];
    const auto& b = mesh.points[topo.edge_vertices[e][1]];
    std::ostringstream msg;
    msg.precision(6);
    msg << "mesh wall '" << c.name << "' (" << c.file << "): the edge from (" << a[0] << ", "
        << a[1] << ", " << a[2] << ") to (" << b[0] << ", " << b[1] << ", " << b[2]
        << ") is shared by " << topo.edge_triangles[e].size()
        << " triangles (after scaling); mesh contacts need every edge shared by one or two "
           "triangles: split the mesh into walls of their own where surfaces meet";
    throw std::runtime_error(msg.str());
  }
}

// The median length of the triangles' first edges.
double median_edge(const TriangleMesh& mesh) {
  std::vector<double> lengths;
  for (const auto& t : mesh.triangles) {
    const Vec3d d = sub(mesh.points[t[1]], mesh.points[t[0]]);
    lengths.push_back(std::sqrt(dot(d, d)));
  }
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  return lengths[lengths.size() / 2];
}

double mesh_extent(const TriangleMesh& mesh) {
  double extent = 0;
  for (const auto& p : mesh.points)
    extent = std::max(extent, std::sqrt(dot(sub(p, mesh.points[0]), sub(p, mesh.points[0]))));
  return extent;
}

// Planar patches: triangles joined across an edge whose normals agree to 1e-12 and whose
// vertices lie in each other's plane to 1e-9 of the mesh size. Each triangle stores its patch's
// normal (that of the patch's lowest triangle, negated where its own points the other way), so
// that coplanar triangles compare the same numbers.
std::vector<Vec3d> patch_normals(const TriangleMesh& mesh, const MeshTopology& topo,
                                 std::vector<int>& patch) {
  const std::size_t n = mesh.triangles.size();
  std::vector<Vec3d> own(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto& tri = mesh.triangles[k];
    own[k] = unit(cross(sub(mesh.points[tri[1]], mesh.points[tri[0]]),
                        sub(mesh.points[tri[2]], mesh.points[tri[0]])));
  }
  const double distance_tolerance = 1e-9 * mesh_extent(mesh);
  patch.resize(n);
  for (std::size_t k = 0; k < n; ++k)
    patch[k] = int(k);
  for (const auto& adjacent : topo.edge_triangles) {
    if (adjacent.size() != 2)
      continue;
    const int t0 = adjacent[0], t1 = adjacent[1];
    if (std::abs(dot(own[t0], own[t1])) < 1 - 1e-12)
      continue;
    bool coplanar = true;
    for (int v : mesh.triangles[t1])
      coplanar = coplanar && std::abs(dot(sub(mesh.points[v], mesh.points[mesh.triangles[t0][0]]),
                                          own[t0])) <= distance_tolerance;
    if (coplanar) {
      const int r0 = find_root(patch, t0), r1 = find_root(patch, t1);
      patch[std::max(r0, r1)] = std::min(r0, r1);
    }
  }
  std::vector<Vec3d> stored(n);
  for (std::size_t k = 0; k < n; ++k) {
    patch[k] = find_root(patch, int(k));
    const Vec3d& reference = own[patch[k]];
    stored[k] = dot(own[k], reference) >= 0 ? reference : scaled(reference, -1.0);
  }
  return stored;
}

// Mesh topology for bodies that are not spheres (their deepest-point contacts with faces, edges
// and vertices): stored normals, the triangles of each edge, corner vertices and the ring of
// neighbours of each vertex.
void add_body_contact_topology(WallElementTable& t, const TriangleMesh& mesh,
                               const MeshTopology& topo, int first_element) {
  std::vector<int> patch;
  for (const Vec3d& normal : patch_normals(mesh, topo, patch))
    t.triangle_normal.push_back(normal);
  std::vector<int> corner(mesh.points.size(), 0);
  std::vector<std::vector<int>> ring(mesh.points.size());
  for (std::size_t e = 0; e < topo.edge_vertices.size(); ++e) {
    const auto& adjacent = topo.edge_triangles[e];
    t.edge_triangles.push_back(
        {first_element + adjacent[0], adjacent.size() > 1 ? first_element + adjacent[1] : -1});
    const int v0 = topo.edge_vertices[e][0], v1 = topo.edge_vertices[e][1];
    ring[v0].push_back(v1);
    ring[v1].push_back(v0);
    if (adjacent.size() < 2)
      corner[v0] = corner[v1] = 1; // the mesh boundary
  }
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    for (int triangle : topo.vertex_triangles[v])
      if (patch[triangle] != patch[topo.vertex_triangles[v].front()])
        corner[v] = 1;
    t.vertex_corner.push_back(corner[v]);
    for (int neighbour : ring[v])
      t.vertex_ring.push_back(mesh.points[neighbour]);
    t.vertex_ring_start.push_back(int(t.vertex_ring.size()));
  }
}

void add_mesh(WallElementTable& t, SurfaceBuilder& s, int wall, const WallConfig& c,
              const Vec3d& grid_origin, double grid_cell) {
  TriangleMesh mesh = read_mesh(c.file);
  for (auto& p : mesh.points)
    for (int a = 0; a < 3; ++a)
      p[a] = p[a] * c.scale + c.translate[a];
  mesh = spatially_ordered(mesh, grid_origin, grid_cell > 0 ? grid_cell : 2 * median_edge(mesh));
  const MeshTopology topo = build_topology(mesh);
  refuse_non_manifold_edges(mesh, topo, c);
  const int first_element = int(t.kind.size());
  const int first_edge = int(t.edge_owner.size());
  const int first_vertex = int(t.vertex_owner.size());
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const auto& tri = mesh.triangles[k];
    std::array<double, 9> g{};
    for (int v = 0; v < 3; ++v)
      for (int a = 0; a < 3; ++a)
        g[3 * v + a] = mesh.points[tri[v]][a];
    t.kind.push_back(triangle_kind);
    t.wall.push_back(wall);
    t.geometry.push_back(g);
    const auto& e = topo.triangle_edges[k];
    t.features.push_back({first_edge + e[0], first_edge + e[1], first_edge + e[2],
                          first_vertex + tri[0], first_vertex + tri[1], first_vertex + tri[2]});
  }
  for (std::size_t e = 0; e < topo.edge_vertices.size(); ++e) {
    const auto& adjacent = topo.edge_triangles[e];
    t.edge_owner.push_back(first_element + *std::min_element(adjacent.begin(), adjacent.end()));
    t.edge_sides.push_back(int(std::min<std::size_t>(2, adjacent.size())));
    t.edge_outward.push_back(topo.edge_outward[e]);
    t.edge_vertices.push_back(
        {first_vertex + topo.edge_vertices[e][0], first_vertex + topo.edge_vertices[e][1]});
    t.edge_direction.push_back(topo.edge_direction[e]);
  }
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    const auto& incident = topo.vertex_triangles[v];
    t.vertex_owner.push_back(
        incident.empty() ? -1
                         : first_element + *std::min_element(incident.begin(), incident.end()));
    for (const auto& d : topo.vertex_edge_directions[v])
      t.vertex_edge_direction.push_back(d);
    t.vertex_edge_start.push_back(int(t.vertex_edge_direction.size()));
    for (int triangle : incident)
      t.vertex_triangle.push_back(first_element + triangle);
    t.vertex_triangle_start.push_back(int(t.vertex_triangle.size()));
    t.vertex_position.push_back(mesh.points[v]);
  }
  add_body_contact_topology(t, mesh, topo, first_element);
  // Features are told apart to 1e-9 of the mesh size: far below any overlap that matters, far
  // above the rounding of the tests that compare them.
  t.feature_tolerance = std::max(t.feature_tolerance, 1e-9 * mesh_extent(mesh));
  for (const auto& p : mesh.points)
    s.add_point(p);
  for (const auto& tri : mesh.triangles)
    s.triangles.insert(s.triangles.end(), tri.begin(), tri.end());
}

} // namespace

WallElementTable build_wall_elements(const std::vector<WallConfig>& walls, const Vec3d& domain_min,
                                     const Vec3d& domain_max, double particle_cell) {
  WallElementTable table;
  const double half_patch =
      0.5 * std::sqrt(dot(sub(domain_max, domain_min), sub(domain_max, domain_min)));
  for (int w = 0; w < int(walls.size()); ++w) {
    const WallConfig& c = walls[w];
    SurfaceBuilder surface;
    switch (c.kind) {
    case WallConfig::Kind::Plane:
      add_plane(table, w, c.point, unit(c.normal));
      draw_plane_patch(surface, c.point, unit(c.normal), half_patch);
      break;
    case WallConfig::Kind::Box:
      add_box(table, surface, w, c);
      break;
    case WallConfig::Kind::Cylinder:
      add_cylinder(table, surface, w, c);
      break;
    case WallConfig::Kind::Mesh:
      add_mesh(table, surface, w, c, domain_min, particle_cell);
      break;
    }
    table.surface_points.push_back(std::move(surface.points));
    table.surface_triangles.push_back(std::move(surface.triangles));
  }
  return table;
}

std::vector<WallMotionData> wall_motions(const std::vector<WallConfig>& walls) {
  std::vector<WallMotionData> motions;
  for (const WallConfig& c : walls) {
    WallMotionData m;
    m.pivot = c.motion.axis_point;
    m.velocity = c.motion.velocity;
    m.omega = scaled(unit(c.motion.axis_direction), c.motion.rpm * two_pi / 60.0);
    m.start = c.motion.start;
    m.active_from = c.active_from;
    m.active_until = c.active_until;
    m.material = c.material;
    motions.push_back(m);
  }
  return motions;
}

bool walls_bounding_box(const std::vector<WallConfig>& walls, Vec3d& lo, Vec3d& hi) {
  bool any = false;
  lo = {1e300, 1e300, 1e300};
  hi = {-1e300, -1e300, -1e300};
  auto include = [&](const Vec3d& p) {
    any = true;
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  };
  for (const WallConfig& c : walls) {
    if (c.kind == WallConfig::Kind::Box) {
      include(c.min);
      include(c.max);
    } else if (c.kind == WallConfig::Kind::Cylinder) {
      for (double along : {0.0, c.length}) {
        const Vec3d centre = add(c.base_center, scaled(c.axis_direction, along));
        include(sub(centre, {c.radius, c.radius, c.radius}));
        include(add(centre, {c.radius, c.radius, c.radius}));
      }
    } else if (c.kind == WallConfig::Kind::Mesh) {
      for (const auto& p : read_mesh(c.file).points) {
        Vec3d q;
        for (int a = 0; a < 3; ++a)
          q[a] = p[a] * c.scale + c.translate[a];
        include(q);
      }
    }
  }
  return any;
}

} // namespace kdem
