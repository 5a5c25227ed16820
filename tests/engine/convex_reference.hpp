#pragma once
// Brute-force references for convex contacts, independent of the code under test: support
// functions h(d) = max x.d over the surface, from 6 x 16 x 16 radially projected samples refined
// by compass search, and the penetration depth min_n [h_j(n) + h_i(-n)] (n from j towards i) by a
// direction grid refined by compass search, whose minimiser is the reference normal. For any unit
// n, the chord of the intersection along n is at most h_j(n) + h_i(-n): a rigorous bound on the
// midway overlap.
#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "shapes/superquadric_contact.hpp"

namespace kdem::testing {

// Surface point on the ray from the centre along u (body frame): F + 1 = G is homogeneous of
// degree n1 (unconditioned), so the point is G(u)^(-1/n1) u.
inline Vec3 radial_surface_point(const SuperquadricShape& s, Vec3 u) {
  const double section = std::pow(
      std::pow(std::fabs(u.x / s.a), s.n2) + std::pow(std::fabs(u.y / s.b), s.n2), s.n1 / s.n2);
  const double g = section + std::pow(std::fabs(u.z / s.c), s.n1);
  return std::pow(g, -1.0 / s.n1) * u;
}

inline std::vector<Vec3> cube_directions(int per_edge) {
  std::vector<Vec3> out;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0})
      for (int p = 0; p < per_edge; ++p)
        for (int q = 0; q < per_edge; ++q) {
          const double s = -1 + 2 * (p + 0.5) / per_edge, t = -1 + 2 * (q + 0.5) / per_edge;
          double v[3];
          v[axis] = sign, v[(axis + 1) % 3] = s, v[(axis + 2) % 3] = t;
          const Vec3 d{v[0], v[1], v[2]};
          out.push_back((1.0 / norm(d)) * d);
        }
  return out;
}

// Maximises f over unit vectors by compass search (Kolda, Lewis & Torczon, SIAM Rev. 45 (2003)
// 385): axis moves of length `step`, doubled after a success, halved after a failure.
template <class Objective>
inline Vec3 compass_maximize(Objective f, Vec3 u, double step, double min_step, double& best) {
  best = f(u);
  for (int evaluations = 0; step > min_step && evaluations < 100000;) {
    bool improved = false;
    for (int k = 0; k < 6 && !improved; ++k) {
      double e[3] = {0, 0, 0};
      e[k / 2] = k % 2 ? -step : step;
      Vec3 trial = u + Vec3{e[0], e[1], e[2]};
      trial = (1.0 / norm(trial)) * trial;
      const double value = f(trial);
      ++evaluations;
      if (value > best) {
        best = value, u = trial, improved = true;
      }
    }
    step = improved ? std::min(2 * step, 0.25) : 0.5 * step;
  }
  return u;
}

struct Support {
  double value; // max x.d over the body, world frame
  Vec3 point;   // a surface point where it is attained
};

// A convex body known by its radial surface point along a body-frame direction (from its
// centre): support function by radial samples refined by compass search.
class BruteForceBody {
public:
  using Radial = std::function<Vec3(Vec3)>;
  BruteForceBody(Vec3 centre, const Mat3& rotation, Radial radial)
      : centre_(centre), rotation_(rotation), radial_(std::move(radial)) {
    for (const Vec3& u : cube_directions(16)) {
      directions_.push_back(u);
      points_.push_back(radial_(u));
    }
  }
  explicit BruteForceBody(const PosedSuperquadric& body)
      : BruteForceBody(body.centre, body.rotation,
                       [shape = body.shape](Vec3 u) { return radial_surface_point(shape, u); }) {}
  double coarse_support(Vec3 d) const {
    const Vec3 local = transpose(rotation_) * d;
    double best = -1e300;
    for (const Vec3& p : points_)
      best = std::max(best, dot(p, local));
    return best + dot(centre_, d);
  }
  Support support(Vec3 d) const {
    const Vec3 local = transpose(rotation_) * d;
    int best_k = 0;
    for (int k = 0; k < int(points_.size()); ++k)
      if (dot(points_[k], local) > dot(points_[best_k], local))
        best_k = k;
    double best = 0;
    const auto along = [&](Vec3 u) { return dot(radial_(u), local); };
    const Vec3 u = compass_maximize(along, directions_[best_k], 1.0 / 16, 1e-11, best);
    return {best + dot(centre_, d), centre_ + rotation_ * radial_(u)};
  }

private:
  Vec3 centre_;
  Mat3 rotation_;
  Radial radial_;
  std::vector<Vec3> directions_, points_;
};

// Extent of the overlap of the projections of i and j on the axis n (n from j towards i).
inline double projected_overlap(const BruteForceBody& i, const BruteForceBody& j, Vec3 n) {
  return j.support(n).value + i.support(-n).value;
}

struct Penetration {
  double depth;
  Vec3 normal; // from j towards i
};

// direction_resolution: the compass search's last step on the normal, rad.
inline Penetration penetration_depth(const BruteForceBody& i, const BruteForceBody& j,
                                     double direction_resolution = 1e-9) {
  std::vector<std::pair<double, Vec3>> coarse;
  for (const Vec3& n : cube_directions(10))
    coarse.push_back({j.coarse_support(n) + i.coarse_support(-n), n});
  std::sort(coarse.begin(), coarse.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  Penetration best{1e300, {0, 0, 1}};
  for (int k = 0; k < 3; ++k) {
    double value = 0;
    const auto negative = [&](Vec3 n) { return -projected_overlap(i, j, n); };
    const Vec3 n = compass_maximize(negative, coarse[k].second, 0.1, direction_resolution, value);
    if (-value < best.depth)
      best = {-value, n};
  }
  return best;
}

inline double angle_between(Vec3 a, Vec3 b) {
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

// Every number of a narrow-phase result is finite (no NaN ever leaves a narrow phase).
inline bool finite_result(const NarrowPhaseResult& r) {
  const ContactGeometry& g = r.geometry;
  return std::isfinite(g.overlap) && std::isfinite(g.normal.x + g.normal.y + g.normal.z) &&
         std::isfinite(g.point.x + g.point.y + g.point.z) &&
         std::isfinite(r.curvature_i + r.curvature_j) &&
         std::isfinite(r.state.point.x + r.state.point.y + r.state.point.z + r.state.multiplier);
}

} // namespace kdem::testing
