#pragma once
// Host construction of a dilated polyhedron's core (shapes/dilated_polyhedron.hpp) from a
// triangle mesh: checks that it is a closed, consistently oriented 2-manifold, turns it outward,
// numbers its edges, gives each vertex and edge its owner face, normal cone and convexity, and
// builds the bounding-sphere tree over its faces. Plain inline C++, run once per template.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dilated_polyhedron.hpp"

namespace kdem {

// A core and its dilation radius in one frame, with the accessors the device geometry reads
// (the same as the engine's device table gives for one template).
struct DilatedCore {
  double radius = 0; // m, dilation
  std::vector<CoreVertex> vertices;
  std::vector<CoreEdge> edges;
  std::vector<CoreFace> faces;
  std::vector<Vec3> cones; // edge directions at the vertices (CoreVertex::cone_first)
  std::vector<SphereNode> nodes;
  // Host only: the angle-weighted pseudonormals that sign the distance to the core (Baerentzen
  // and Aanaes, IEEE TVCG 11 (2005) 243): per vertex, and per edge the sum of its faces' normals.
  std::vector<Vec3> vertex_pseudonormals, edge_pseudonormals;
  // The cone reach (cone_reach) the node caps were bound for; the walks use the caps for a
  // slack of no greater reach. Negative: no caps.
  double caps_reach = -1;

  double dilation() const { return radius; }
  double cap_reach() const { return caps_reach; }
  FeatureNumbering numbering() const { return {int(vertices.size()), int(edges.size())}; }
  const CoreVertex& vertex(int k) const { return vertices[std::size_t(k)]; }
  const CoreEdge& edge(int k) const { return edges[std::size_t(k)]; }
  const CoreFace& face(int k) const { return faces[std::size_t(k)]; }
  Vec3 cone(int k) const { return cones[std::size_t(k)]; }
  const SphereNode& node(int k) const { return nodes[std::size_t(k)]; }
};

namespace dilated_build {

inline Vec3 unit(Vec3 v) {
  return (1.0 / norm(v)) * v;
}

inline double signed_volume(const std::vector<Vec3>& points,
                            const std::vector<std::array<int, 3>>& triangles) {
  double six_volume = 0;
  for (const auto& t : triangles)
    six_volume += dot(points[t[0]], cross(points[t[1]], points[t[2]]));
  return six_volume / 6.0;
}

// The points the triangles use, renumbered in order of first use.
inline void drop_unused_points(std::vector<Vec3>& points,
                               std::vector<std::array<int, 3>>& triangles) {
  std::vector<int> renumbered(points.size(), -1);
  std::vector<Vec3> used;
  for (auto& t : triangles)
    for (int& v : t) {
      if (renumbered[std::size_t(v)] < 0) {
        renumbered[std::size_t(v)] = int(used.size());
        used.push_back(points[std::size_t(v)]);
      }
      v = renumbered[std::size_t(v)];
    }
  points = std::move(used);
}

struct EdgeUse {
  int face = 0, corner = 0; // the face and the corner the directed edge starts at
  bool forward = true;      // traversed from the lower to the higher vertex number
};

// Numbers the undirected edges and checks that each is used by exactly two faces in opposite
// directions (a closed, consistently oriented 2-manifold).
inline std::vector<std::array<EdgeUse, 2>>
number_edges(const std::vector<std::array<int, 3>>& triangles, std::vector<CoreFace>& faces,
             std::vector<std::array<int, 2>>& edge_vertices) {
  std::map<std::pair<int, int>, int> index;
  std::vector<std::vector<EdgeUse>> uses;
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[f][k], b = triangles[f][(k + 1) % 3];
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      auto found = index.find(key);
      if (found == index.end()) {
        found = index.emplace(key, int(uses.size())).first;
        uses.emplace_back();
        edge_vertices.push_back({key.first, key.second});
      }
      uses[std::size_t(found->second)].push_back(EdgeUse{int(f), k, a < b});
      faces[f].edge[k] = found->second;
    }
  std::vector<std::array<EdgeUse, 2>> pairs;
  for (std::size_t e = 0; e < uses.size(); ++e) {
    const auto& u = uses[e];
    const std::string where = "the edge between vertices " + std::to_string(edge_vertices[e][0]) +
                              " and " + std::to_string(edge_vertices[e][1]);
    if (u.size() == 1)
      throw std::invalid_argument("the mesh is open: " + where +
                                  " belongs to one triangle (a closed surface is needed)");
    if (u.size() > 2)
      throw std::invalid_argument("the mesh is not a manifold: " + where + " belongs to " +
                                  std::to_string(u.size()) + " triangles");
    if (u[0].forward == u[1].forward)
      throw std::invalid_argument("the mesh is not consistently oriented: the two triangles of " +
                                  where + " run along it in the same direction");
    pairs.push_back({u[0], u[1]});
  }
  return pairs;
}

// Checks that the faces at each vertex form one fan (else two sheets meet at a point).
inline void check_vertex_fans(int vertex_count, const std::vector<CoreFace>& faces,
                              const std::vector<std::array<int, 2>>& edge_vertices,
                              const std::vector<std::array<EdgeUse, 2>>& edge_uses) {
  std::vector<std::vector<int>> vertex_faces(static_cast<std::size_t>(vertex_count));
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int v : faces[f].vertex)
      vertex_faces[std::size_t(v)].push_back(int(f));
  for (int v = 0; v < vertex_count; ++v) {
    const auto& around = vertex_faces[std::size_t(v)];
    // Walk from the first face across its edges at v; a fan returns after visiting them all.
    int face = around[0], steps = 0, entered = -1;
    do {
      int next_edge = -1;
      for (int e : faces[std::size_t(face)].edge)
        if ((edge_vertices[std::size_t(e)][0] == v || edge_vertices[std::size_t(e)][1] == v) &&
            e != entered) {
          next_edge = e;
          break;
        }
      const auto& uses = edge_uses[std::size_t(next_edge)];
      face = uses[0].face == face ? uses[1].face : uses[0].face;
      entered = next_edge;
      ++steps;
    } while (face != around[0] && steps <= int(around.size()));
    if (steps != int(around.size()))
      throw std::invalid_argument("the mesh is not a manifold at vertex " + std::to_string(v) +
                                  ": its triangles form more than one fan");
  }
}

inline double vertex_angle(Vec3 at, Vec3 p, Vec3 q) {
  const Vec3 u = unit(p - at), w = unit(q - at);
  return std::atan2(norm(cross(u, w)), dot(u, w));
}

// Top-down median split of the faces on the longest axis of their centroids' box; nodes in
// depth-first order, each sphere centred on its faces' box and reaching their farthest corner.
struct TreeBuilder {
  const std::vector<CoreVertex>& vertices;
  const std::vector<CoreFace>& faces;
  std::vector<Vec3> centroids;
  std::vector<SphereNode> nodes;

  int build(std::vector<int>::iterator first, std::vector<int>::iterator last) {
    const int index = int(nodes.size());
    nodes.emplace_back();
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    Vec3 clo = lo, chi = hi;
    for (auto f = first; f != last; ++f) {
      for (int v : faces[std::size_t(*f)].vertex) {
        const Vec3 x = vertices[std::size_t(v)].position;
        lo = Vec3{std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
        hi = Vec3{std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
      }
      const Vec3 c = centroids[std::size_t(*f)];
      clo = Vec3{std::min(clo.x, c.x), std::min(clo.y, c.y), std::min(clo.z, c.z)};
      chi = Vec3{std::max(chi.x, c.x), std::max(chi.y, c.y), std::max(chi.z, c.z)};
    }
    SphereNode node;
    node.centre = 0.5 * (lo + hi);
    for (auto f = first; f != last; ++f)
      for (int v : faces[std::size_t(*f)].vertex)
        node.radius = std::max(node.radius, norm(vertices[std::size_t(v)].position - node.centre));
    if (last - first == 1) {
      node.left = -1;
      node.right = *first;
    } else {
      const Vec3 extent = chi - clo;
      const int axis =
          extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
      const auto middle = first + (last - first) / 2;
      std::nth_element(first, middle, last, [&](int a, int b) {
        const double ca = centroids[std::size_t(a)][axis], cb = centroids[std::size_t(b)][axis];
        return ca < cb || (ca == cb && a < b);
      });
      node.left = build(first, middle);
      node.right = build(middle, last);
    }
    nodes[std::size_t(index)] = node;
    return index;
  }
};

// A half-space of directions: d . normal <= limit.
struct DirectionBound {
  Vec3 normal;
  double limit = 0;
};
using DirectionRegion = std::vector<DirectionBound>;

// Feasibility is tested with this slack, so that rounding errs towards a wider region.
constexpr double region_tolerance = 1e-9;

inline bool in_region(Vec3 d, const DirectionRegion& region) {
  for (const DirectionBound& b : region)
    if (dot(d, b.normal) > b.limit + region_tolerance)
      return false;
  return true;
}

// The cosine of the largest angle from `axis` (unit) of the unit directions in the region: -1
// where it holds -axis, above 1 (2) where it is empty. The largest angle over a closed region of
// the sphere not holding -axis lies on its boundary: at the point of one bounding circle
// (d . normal = limit) farthest from the axis, or where two such circles cross.
inline double least_cosine_from(Vec3 axis, const DirectionRegion& region) {
  if (in_region(-1.0 * axis, region))
    return -1.0;
  double least = 2.0;
  const auto consider = [&](Vec3 d) {
    if (in_region(d, region))
      least = std::min(least, dot(d, axis));
  };
  for (const DirectionBound& b : region) {
    if (!(std::fabs(b.limit) < 1))
      continue; // the whole sphere or nothing: no circle
    const double across = std::sqrt(1 - b.limit * b.limit);
    Vec3 away = axis - dot(axis, b.normal) * b.normal;
    if (!(norm(away) > 1e-12)) // axis along the normal: every point of the circle alike
      away = std::fabs(b.normal.x) < 0.9 ? cross(b.normal, Vec3{1, 0, 0})
                                         : cross(b.normal, Vec3{0, 1, 0});
    consider(b.limit * b.normal - (across / norm(away)) * away);
  }
  for (std::size_t i = 0; i < region.size(); ++i)
    for (std::size_t j = i + 1; j < region.size(); ++j) {
      const DirectionBound &p = region[i], &q = region[j];
      const double c = dot(p.normal, q.normal), sine2 = 1 - c * c;
      if (!(sine2 > 1e-15))
        continue; // parallel circles do not cross
      const double x = (p.limit - c * q.limit) / sine2, y = (q.limit - c * p.limit) / sine2;
      const Vec3 in_plane = x * p.normal + y * q.normal;
      const double height2 = 1 - norm2(in_plane);
      if (!(height2 >= 0))
        continue;
      const Vec3 up = (std::sqrt(height2) / std::sqrt(sine2)) * cross(p.normal, q.normal);
      consider(in_plane + up);
      consider(in_plane - up);
    }
  return least;
}

// The outward directions (at the feature, towards the other body) in which the features face f
// tests (the face, and the edges and vertices it owns) can meet another body: where their
// ConeSlack weights are not 0 for a slack of cone reach `reach` (ConeSlack::weight: 0 where
// the excursion out of the cone, a sine, reaches it). A reflex edge meets nothing. The closest
// points of an edge's interior are joined at right angles to it, to within `across_edge`.
inline std::vector<DirectionRegion> face_feature_regions(const DilatedCore& core, int f,
                                                         double reach) {
  constexpr double across_edge = 1e-6;
  std::vector<DirectionRegion> regions;
  const CoreFace& face = core.face(f);
  const double face_cosine = reach < 1 ? std::sqrt(1 - reach * reach) : 0.0;
  regions.push_back({{-1.0 * face.normal, -face_cosine}});
  for (int k = 0; k < 3; ++k) {
    const CoreEdge& edge = core.edge(face.edge[k]);
    if (edge.owner == f && edge.convex) {
      const Vec3 along =
          unit(core.vertex(edge.vertex[1]).position - core.vertex(edge.vertex[0]).position);
      regions.push_back({{edge.inward[0], reach},
                         {edge.inward[1], reach},
                         {along, across_edge},
                         {-1.0 * along, across_edge}});
    }
    const CoreVertex& vertex = core.vertex(face.vertex[k]);
    if (vertex.owner == f) {
      DirectionRegion region;
      for (int m = 0; m < vertex.cone_count; ++m)
        region.push_back({core.cone(vertex.cone_first + m), reach});
      if (!vertex.convex)
        region.push_back({-1.0 * vertex.outward, 0.0});
      regions.push_back(region);
    }
  }
  return regions;
}

// Sets the cap of node `index` and those below it from the regions of each face; returns the
// node's faces.
struct CapBuilder {
  DilatedCore& core;
  std::vector<std::vector<DirectionRegion>> regions; // per face

  std::vector<int> bound(int index) {
    SphereNode& node = core.nodes[std::size_t(index)];
    std::vector<int> faces;
    if (node.left < 0) {
      faces.push_back(node.right);
    } else {
      faces = bound(node.left);
      const std::vector<int> right = bound(node.right);
      faces.insert(faces.end(), right.begin(), right.end());
    }
    Vec3 sum{};
    for (int f : faces) {
      const CoreFace& face = core.face(f);
      const Vec3 a = core.vertex(face.vertex[0]).position;
      sum += norm(cross(core.vertex(face.vertex[1]).position - a,
                        core.vertex(face.vertex[2]).position - a)) *
             face.normal;
    }
    node.cap_axis = norm(sum) > 0 ? unit(sum) : core.face(faces.front()).normal;
    double least = 1.0;
    for (int f : faces)
      for (const DirectionRegion& region : regions[std::size_t(f)])
        least = std::min(least, least_cosine_from(node.cap_axis, region));
    const double angle = std::acos(std::max(-1.0, least)) + region_tolerance;
    node.cap_cos = angle < pi_value ? std::cos(angle) : -1.0;
    node.cap_sin = angle < pi_value ? std::sin(angle) : 0.0;
    return faces;
  }
  static constexpr double pi_value = 3.14159265358979323846;
};

} // namespace dilated_build

// Bounds every node's cap (SphereNode) for contacts weighed with `slack` or any slack of no
// greater cone reach.
inline void bound_normal_cones(DilatedCore& core, const ConeSlack& slack) {
  using namespace dilated_build;
  const double reach = cone_reach(slack);
  CapBuilder caps{core, {}};
  for (int f = 0; f < int(core.faces.size()); ++f)
    caps.regions.push_back(face_feature_regions(core, f, reach));
  caps.bound(0);
  core.caps_reach = reach;
}

// Edges meeting at an angle this close to flat (cosine of the dihedral deviation) count as flat,
// hence convex: the two triangles of a flat quad, or nearly flat parts of a fine mesh.
constexpr double flat_edge_tolerance = 1e-9;

// The core of a dilated polyhedron from a triangle mesh (points in the body frame). Throws
// std::invalid_argument naming what is wrong: a radius not positive, an index out of range, a
// triangle of zero area, an open or non-manifold or inconsistently oriented surface, zero volume.
// An inward-oriented mesh is turned outward.
inline DilatedCore build_dilated_core(std::vector<Vec3> points,
                                      std::vector<std::array<int, 3>> triangles, double radius) {
  using namespace dilated_build;
  if (!(radius > 0) || !std::isfinite(radius))
    throw std::invalid_argument("the dilation radius must be positive, not " +
                                std::to_string(radius));
  if (triangles.size() < 4)
    throw std::invalid_argument("a closed surface needs at least 4 triangles, the mesh has " +
                                std::to_string(triangles.size()));
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int v : triangles[f])
      if (v < 0 || v >= int(points.size()))
        throw std::invalid_argument("triangle " + std::to_string(f) + " names vertex " +
                                    std::to_string(v) + ", the mesh has " +
                                    std::to_string(points.size()));
  drop_unused_points(points, triangles);
  double size = 0;
  for (const Vec3& p : points)
    size = std::max(size, norm(p - points[0]));
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    const double area2 = norm(cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]));
    if (!(area2 > 1e-24 * size * size))
      throw std::invalid_argument("triangle " + std::to_string(f) + " has zero area");
  }
  const double volume = signed_volume(points, triangles);
  if (!(std::fabs(volume) > 1e-18 * size * size * size))
    throw std::invalid_argument("the mesh encloses zero volume");
  if (volume < 0)
    for (auto& t : triangles)
      std::swap(t[1], t[2]);

  DilatedCore core;
  core.radius = radius;
  core.faces.resize(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    CoreFace& face = core.faces[f];
    for (int k = 0; k < 3; ++k)
      face.vertex[k] = triangles[f][k];
    face.normal = unit(cross(points[triangles[f][1]] - points[triangles[f][0]],
                             points[triangles[f][2]] - points[triangles[f][0]]));
  }
  std::vector<std::array<int, 2>> edge_vertices;
  const auto edge_uses = number_edges(triangles, core.faces, edge_vertices);
  check_vertex_fans(int(points.size()), core.faces, edge_vertices, edge_uses);

  core.edges.resize(edge_uses.size());
  core.edge_pseudonormals.resize(edge_uses.size());
  for (std::size_t e = 0; e < edge_uses.size(); ++e) {
    CoreEdge& edge = core.edges[e];
    edge.vertex[0] = edge_vertices[e][0], edge.vertex[1] = edge_vertices[e][1];
    auto uses = edge_uses[e];
    if (uses[1].face < uses[0].face)
      std::swap(uses[0], uses[1]);
    edge.owner = uses[0].face;
    for (int k = 0; k < 2; ++k) {
      const CoreFace& face = core.faces[std::size_t(uses[k].face)];
      const Vec3 a = points[std::size_t(face.vertex[uses[k].corner])];
      const Vec3 b = points[std::size_t(face.vertex[(uses[k].corner + 1) % 3])];
      edge.inward[k] = unit(cross(face.normal, b - a));
    }
    const Vec3 n1 = core.faces[std::size_t(uses[1].face)].normal;
    edge.convex = dot(n1, edge.inward[0]) <= flat_edge_tolerance ? 1 : 0;
    core.edge_pseudonormals[e] = core.faces[std::size_t(uses[0].face)].normal + n1;
  }

  const std::size_t vertex_count = points.size();
  core.vertices.resize(vertex_count);
  core.vertex_pseudonormals.assign(vertex_count, Vec3{});
  std::vector<std::vector<int>> vertex_edges(vertex_count);
  for (std::size_t e = 0; e < core.edges.size(); ++e)
    for (int v : core.edges[e].vertex)
      vertex_edges[std::size_t(v)].push_back(int(e));
  for (std::size_t v = 0; v < vertex_count; ++v) {
    CoreVertex& vertex = core.vertices[v];
    vertex.position = points[v];
    vertex.owner = int(core.faces.size());
    vertex.cone_first = int(core.cones.size());
    vertex.convex = 1;
    for (int e : vertex_edges[v]) {
      const CoreEdge& edge = core.edges[std::size_t(e)];
      const int other = edge.vertex[0] == int(v) ? edge.vertex[1] : edge.vertex[0];
      core.cones.push_back(unit(points[std::size_t(other)] - points[v]));
      vertex.convex = vertex.convex && edge.convex;
    }
    vertex.cone_count = int(core.cones.size()) - vertex.cone_first;
  }
  for (std::size_t f = 0; f < core.faces.size(); ++f) {
    const CoreFace& face = core.faces[f];
    for (int k = 0; k < 3; ++k) {
      const int v = face.vertex[k];
      CoreVertex& vertex = core.vertices[std::size_t(v)];
      vertex.owner = std::min(vertex.owner, int(f));
      core.vertex_pseudonormals[std::size_t(v)] +=
          vertex_angle(points[std::size_t(v)], points[std::size_t(face.vertex[(k + 1) % 3])],
                       points[std::size_t(face.vertex[(k + 2) % 3])]) *
          face.normal;
    }
  }

  for (std::size_t v = 0; v < vertex_count; ++v)
    core.vertices[v].outward = unit(core.vertex_pseudonormals[v]);
  TreeBuilder tree{core.vertices, core.faces, {}, {}};
  for (const CoreFace& face : core.faces)
    tree.centroids.push_back((1.0 / 3.0) * (points[std::size_t(face.vertex[0])] +
                                            points[std::size_t(face.vertex[1])] +
                                            points[std::size_t(face.vertex[2])]));
  std::vector<int> order(core.faces.size());
  std::iota(order.begin(), order.end(), 0);
  tree.build(order.begin(), order.end());
  core.nodes = std::move(tree.nodes);
  bound_normal_cones(core, ConeSlack{});
  return core;
}

// The depth of a core's sphere tree (a leaf alone: 1).
inline int sphere_tree_depth(const DilatedCore& core, int node = 0) {
  const SphereNode& n = core.node(node);
  if (n.left < 0)
    return 1;
  return 1 + std::max(sphere_tree_depth(core, n.left), sphere_tree_depth(core, n.right));
}

} // namespace kdem
