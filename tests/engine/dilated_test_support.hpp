#pragma once
// Core meshes for the dilated-polyhedron tests: boxes, regular tetrahedra and octahedra, and a
// concave U-shaped prism, as point and triangle lists (outward, counter-clockwise).
#include <array>
#include <vector>

#include "shapes/dilated_polyhedron_build.hpp"

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

} // namespace kdem::test
