#pragma once
// Mass properties of a dilated polyhedron (core plus dilation, book chapter 4; the book gives
// none, digest A1.7), by integrating the body {x : s(x) <= r} over an octree, s the signed
// distance to the core (negative inside). Host code, run once per template.
//
// s is 1-Lipschitz, so a cube of half-diagonal rho about c lies wholly inside the body when
// s(c) - r <= -rho and wholly outside when s(c) - r >= rho: such cubes are added whole or
// dropped, and only cubes the dilated surface may cross are split, down to the finest cells,
// whose part inside is that of the surface's tangent plane there (the level set of s through
// the cell's centre has the gradient of s as its normal), in closed form. The surface of
// the dilated body is smooth (curvature radius at least r where the core is convex), so the
// plane is within h^2 / (2 r) of it over a cell of edge h. The grid is refined until the
// estimate changes by less than the requested precision between two levels.
#include <algorithm>
#include <cmath>
#include <vector>

#include "dilated_polyhedron_build.hpp"
#include "volume_moments.hpp"
#include "wall_geometry.hpp"

namespace kdem {

// The signed distance from x to the core surface (negative inside) and the closest point on it,
// by a branch-and-bound walk of the sphere tree; signed by the pseudonormal of the closest
// feature.
struct CoreDistance {
  double signed_distance = 0;
  Vec3 closest;
  Vec3 outward; // unit gradient of the signed distance at x (away from the core outside)
};

inline CoreDistance core_distance(const DilatedCore& core, Vec3 x) {
  double best2 = 1e300;
  int best_face = -1, best_feature = 0;
  Vec3 best_point;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const SphereNode& node = core.node(stack.back());
    stack.pop_back();
    const double lower = norm(x - node.centre) - node.radius;
    if (lower > 0 && lower * lower >= best2)
      continue;
    if (node.left >= 0) {
      stack.push_back(node.right);
      stack.push_back(node.left);
      continue;
    }
    const CoreFace& face = core.face(node.right);
    const SurfaceQuery q =
        triangle_query(core.vertex(face.vertex[0]).position, core.vertex(face.vertex[1]).position,
                       core.vertex(face.vertex[2]).position, x);
    const double d2 = norm2(x - q.point);
    if (d2 < best2) {
      best2 = d2, best_face = node.right, best_feature = q.feature, best_point = q.point;
    }
  }
  const CoreFace& face = core.face(best_face);
  Vec3 pseudonormal = face.normal;
  if (best_feature >= 4)
    pseudonormal = core.vertex_pseudonormals[std::size_t(face.vertex[best_feature - 4])];
  else if (best_feature >= 1)
    pseudonormal = core.edge_pseudonormals[std::size_t(face.edge[best_feature - 1])];
  CoreDistance d;
  d.closest = best_point;
  const double distance = std::sqrt(best2);
  const bool inside = dot(x - best_point, pseudonormal) < 0;
  d.signed_distance = inside ? -distance : distance;
  d.outward = distance > 0 ? (inside ? -1.0 : 1.0) / distance * (x - best_point)
                           : dilated_build::unit(pseudonormal);
  return d;
}

namespace dilated_mass {

// Moments about the cube's corner of {y in [0, h]^3 : n . y <= t}, n > 0 componentwise: by
// inclusion-exclusion over the corners v of the cube, sum_v (-1)^(ones of v) of the simplex
// {y >= v, n . y <= t} (apex v, legs (t - n . v) / n_i along the axes), whose moments are
// exact: volume L1 L2 L3 / 6, first moment V (sum of vertices) / 4, second moment
// V / 20 (sum_k p_k p_k^T + S S^T) with S the sum of the vertices.
inline VolumeMoments cut_cube_corner_moments(double h, Vec3 n, double t) {
  VolumeMoments m;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 v{(corner & 1) ? h : 0.0, (corner & 2) ? h : 0.0, (corner & 4) ? h : 0.0};
    const double reach = t - dot(n, v);
    if (!(reach > 0))
      continue;
    const double sign = ((corner & 1) + ((corner >> 1) & 1) + ((corner >> 2) & 1)) % 2 ? -1.0 : 1.0;
    const Vec3 legs{reach / n.x, reach / n.y, reach / n.z};
    const double volume = sign * legs.x * legs.y * legs.z / 6.0;
    const Vec3 p[4] = {v, v + Vec3{legs.x, 0, 0}, v + Vec3{0, legs.y, 0}, v + Vec3{0, 0, legs.z}};
    const Vec3 sum = p[0] + p[1] + p[2] + p[3];
    m.volume += volume;
    m.first += (volume / 4.0) * sum;
    Mat3 second = outer(sum, sum);
    for (const Vec3& q : p)
      second = second + outer(q, q);
    m.second = m.second + (volume / 20.0) * second;
  }
  return m;
}

// Normal components below this are raised to it (and the normal renormalised): the
// inclusion-exclusion sums terms of size 1/n_i that cancel, and tilting the plane by up to this
// angle about its point on the cube's centre line changes the cut's volume only to second order.
constexpr double cut_normal_floor = 1e-2;

// Adds the moments of the part of the cube (centre c, edge h, about the integral's reference)
// where the tangent-plane model level_value + n . (y - c) <= 0 holds.
inline void add_cut_cube(VolumeMoments& m, Vec3 c, double h, double level_value, Vec3 n) {
  // Reflect the axes where n is negative so that it is positive, and floor its components.
  const double sign[3] = {n.x < 0 ? -1.0 : 1.0, n.y < 0 ? -1.0 : 1.0, n.z < 0 ? -1.0 : 1.0};
  const auto floored = [](double component) {
    return std::max(std::fabs(component), cut_normal_floor);
  };
  Vec3 positive{floored(n.x), floored(n.y), floored(n.z)};
  positive = (1.0 / norm(positive)) * positive;
  // In corner coordinates y = u + h/2 (u the reflected offset from the centre): n . u <= -level.
  const double t = -level_value + 0.5 * h * (positive.x + positive.y + positive.z);
  const VolumeMoments corner = cut_cube_corner_moments(h, positive, t);
  // Back to offsets u from the centre, then unreflected, then about the reference.
  const Vec3 half{0.5 * h, 0.5 * h, 0.5 * h};
  const double v = corner.volume;
  const Vec3 shifted = corner.first - v * half;
  const Vec3 first{sign[0] * shifted.x, sign[1] * shifted.y, sign[2] * shifted.z};
  Mat3 second = corner.second + (-1.0) * (outer(corner.first, half) + outer(half, corner.first)) +
                v * outer(half, half);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      second.m[a][b] *= sign[a] * sign[b];
  m.volume += v;
  m.first += v * c + first;
  m.second = m.second + v * outer(c, c) + outer(c, first) + outer(first, c) + second;
}

struct OctreeIntegral {
  const DilatedCore& core;
  Vec3 reference; // moments are taken about it (the root cube's centre)
  int finest = 0; // depth of the finest cells
  VolumeMoments moments;
  long long distance_queries = 0;

  void visit(Vec3 c, double h, int depth) {
    const CoreDistance d = core_distance(core, reference + c);
    ++distance_queries;
    const double level_value = d.signed_distance - core.radius;
    const double rho = 0.5 * std::sqrt(3.0) * h;
    if (level_value <= -rho) {
      add_cube_moments(moments, c, h);
      return;
    }
    if (level_value >= rho)
      return;
    if (depth == finest) {
      add_cut_cube(moments, c, h, level_value, d.outward);
      return;
    }
    const double q = 0.25 * h;
    for (int child = 0; child < 8; ++child)
      visit(Vec3{c.x + ((child & 1) ? q : -q), c.y + ((child & 2) ? q : -q),
                 c.z + ((child & 4) ? q : -q)},
            0.5 * h, depth + 1);
  }
};

} // namespace dilated_mass

struct DilatedMassOptions {
  double precision = 1e-4; // relative, see BodyMassProperties::relative_precision
  int coarsest_level = 5;  // finest cells of 2^-level of the bounding cube's edge, first estimate
  int finest_level = 10;   // the last level tried
};

// Volume, centroid and inertia of the dilated body in the core's frame; relative_precision is the
// change of the last refinement (the test suite checks that it bounds the error against closed
// forms: dilated boxes, tetrahedra, the sphere limit).
inline BodyMassProperties dilated_mass_properties(const DilatedCore& core,
                                                  const DilatedMassOptions& options = {}) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const CoreVertex& v : core.vertices) {
    const Vec3 x = v.position;
    lo = Vec3{std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
    hi = Vec3{std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
  }
  const Vec3 reference = 0.5 * (lo + hi);
  const Vec3 extent = hi - lo;
  const double edge = std::max({extent.x, extent.y, extent.z}) + 2.0 * core.radius;
  // The root cube is split into 2^root cubes per axis before the tree decides.
  const int root = 2;
  BodyMassProperties before, now;
  for (int level = options.coarsest_level; level <= options.finest_level; ++level) {
    dilated_mass::OctreeIntegral integral{core, reference, level - root, {}, 0};
    const double h = edge / (1 << root);
    const int n = 1 << root;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          integral.visit(Vec3{(i + 0.5) * h - 0.5 * edge, (j + 0.5) * h - 0.5 * edge,
                              (k + 0.5) * h - 0.5 * edge},
                         h, 0);
    now = properties_of(integral.moments, reference);
    now.grid_levels = level - options.coarsest_level + 1;
    if (level > options.coarsest_level) {
      now.relative_precision = relative_change(now, before);
      if (now.relative_precision < options.precision)
        break;
    } else {
      now.relative_precision = 1;
    }
    before = now;
  }
  return now;
}

} // namespace kdem
