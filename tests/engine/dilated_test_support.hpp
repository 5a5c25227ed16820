#pragma once
// Core meshes for the dilated-polyhedron tests: boxes, regular tetrahedra and octahedra, and a
// concave U-shaped prism, as point and triangle lists (outward, counter-clockwise).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "shapes/dilated_polyhedron_build.hpp"
#include "shapes/wall_geometry.hpp"

namespace kdem::test {

struct CoreMesh {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
};

// The box [-a, a] x [-b, b] x [-c, c], two triangles per face.
inline CoreMesh box_mesh(double a, double b, double c) {
  CoreMesh m;
  for (int k = 0; k < 8; ++k)
    m.points.push_back(Vec3{(k & 1) ? a : -a, (k & 2) ? b : -b, (k & 4) ? c : -c});
  // Faces as quads (counter-clockwise seen from outside), split on their first diagonal.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

// The regular tetrahedron with vertices at distance `circumradius` from the origin.
inline CoreMesh tetrahedron_mesh(double circumradius) {
  const double s = circumradius / std::sqrt(3.0);
  CoreMesh m;
  m.points = {Vec3{s, s, s}, Vec3{s, -s, -s}, Vec3{-s, s, -s}, Vec3{-s, -s, s}};
  m.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  return m;
}

inline CoreMesh octahedron_mesh(double circumradius) {
  const double r = circumradius;
  CoreMesh m;
  m.points = {Vec3{r, 0, 0},  Vec3{-r, 0, 0}, Vec3{0, r, 0},
              Vec3{0, -r, 0}, Vec3{0, 0, r},  Vec3{0, 0, -r}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

// A U-shaped prism: the outline (0,0) (3,0) (3,2) (2,2) (2,1) (1,1) (1,2) (0,2) times `unit`,
// extruded over z in [0, depth]; the notch between x = unit and x = 2 unit above y = unit.
inline CoreMesh u_prism_mesh(double unit, double depth) {
  const double outline[8][2] = {{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const int cap[6][3] = {{0, 1, 4}, {1, 2, 3}, {1, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 6, 7}};
  CoreMesh m;
  for (int level = 0; level < 2; ++level)
    for (const auto& p : outline)
      m.points.push_back(Vec3{unit * p[0], unit * p[1], level * depth});
  for (const auto& t : cap) {
    m.triangles.push_back({t[0], t[2], t[1]});             // bottom, facing -z
    m.triangles.push_back({8 + t[0], 8 + t[1], 8 + t[2]}); // top, facing +z
  }
  for (int k = 0; k < 8; ++k) {
    const int next = (k + 1) % 8;
    m.triangles.push_back({k, next, 8 + next});
    m.triangles.push_back({k, 8 + next, 8 + k});
  }
  return m;
}

inline DilatedCore core_of(const CoreMesh& m, double radius) {
  return build_dilated_core(m.points, m.triangles, radius);
}

// Collects every contact (a sink of the contact walks).
struct ContactList {
  std::vector<FeatureContact> contacts;
  void add(const FeatureContact& c) { contacts.push_back(c); }
  double deepest() const {
    double d = -1e300;
    for (const auto& c : contacts)
      d = std::max(d, c.overlap);
    return d;
  }
};

// --- Brute-force distances between cores ---------------------------------------------------

// The distance between two segments, by a ternary search along the first (the distance of its
// points to the second segment is convex along it).
inline double segment_distance(Vec3 p1, Vec3 q1, Vec3 p2, Vec3 q2) {
  const auto to_segment = [&](Vec3 x) {
    const Vec3 d = q2 - p2;
    const double t = std::clamp(dot(x - p2, d) / norm2(d), 0.0, 1.0);
    return norm(x - (p2 + t * d));
  };
  double lo = 0, hi = 1;
  for (int it = 0; it < 200; ++it) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (to_segment(p1 + m1 * (q1 - p1)) < to_segment(p1 + m2 * (q1 - p1)))
      hi = m2;
    else
      lo = m1;
  }
  return to_segment(p1 + 0.5 * (lo + hi) * (q1 - p1));
}

// Whether segment [p, q] passes through triangle t.
inline bool segment_pierces(Vec3 p, Vec3 q, const Vec3 (&t)[3]) {
  const Vec3 n = cross(t[1] - t[0], t[2] - t[0]);
  const double sp = dot(p - t[0], n), sq = dot(q - t[0], n);
  if (sp * sq > 0 || sp == sq)
    return false;
  const Vec3 x = p + (sp / (sp - sq)) * (q - p);
  for (int k = 0; k < 3; ++k)
    if (dot(cross(t[(k + 1) % 3] - t[k], x - t[k]), n) < 0)
      return false;
  return true;
}

// The distance between two triangles: 0 where they intersect (an edge of one pierces the
// other), else the smallest of the six point-triangle and nine segment-segment distances.
inline double triangle_distance(const Vec3 (&a)[3], const Vec3 (&b)[3]) {
  for (int k = 0; k < 3; ++k)
    if (segment_pierces(a[k], a[(k + 1) % 3], b) || segment_pierces(b[k], b[(k + 1) % 3], a))
      return 0;
  double d = 1e300;
  for (int k = 0; k < 3; ++k) {
    d = std::min(d, norm(a[k] - triangle_query(b[0], b[1], b[2], a[k]).point));
    d = std::min(d, norm(b[k] - triangle_query(a[0], a[1], a[2], b[k]).point));
    for (int m = 0; m < 3; ++m)
      d = std::min(d, segment_distance(a[k], a[(k + 1) % 3], b[m], b[(m + 1) % 3]));
  }
  return d;
}

inline double core_core_distance(const DilatedCore& a, const DilatedCore& b,
                                 const RelativePose& pose) {
  double d = 1e300;
  for (const CoreFace& fa : a.faces)
    for (const CoreFace& fb : b.faces) {
      Vec3 ta[3], tb[3];
      for (int k = 0; k < 3; ++k) {
        ta[k] = a.vertex(fa.vertex[k]).position;
        tb[k] = pose.point(b.vertex(fb.vertex[k]).position);
      }
      d = std::min(d, triangle_distance(ta, tb));
    }
  return d;
}

// The same, over the face pairs whose tree nodes come within `reach` (the distance where it is
// below reach, else at least reach): brute force on the pairs the sphere trees cannot rule out.
inline double near_core_distance(const DilatedCore& a, const DilatedCore& b,
                                 const RelativePose& pose, double reach) {
  double d = 1e300;
  for_each_face_pair_near(a, b, pose, reach, [&](int fa, int fb) {
    Vec3 ta[3], tb[3];
    for (int k = 0; k < 3; ++k) {
      ta[k] = a.vertex(a.face(fa).vertex[k]).position;
      tb[k] = pose.point(b.vertex(b.face(fb).vertex[k]).position);
    }
    d = std::min(d, triangle_distance(ta, tb));
  });
  return d;
}

} // namespace kdem::test
