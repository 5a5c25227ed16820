#pragma once
// Mass properties of a rigid body from its volume moments: volume, centroid, full inertia tensor
// per unit density and its principal frame, and the change between two estimates (for the
// numerically integrated bodies: clumps, dilated polyhedra). Host code.
#include <algorithm>
#include <cmath>

#include "mat3.hpp"
#include "symmetric_eigen.hpp"
#include "vec3.hpp"

namespace kdem {

struct BodyMassProperties {
  double volume = 0;                  // m^3
  Vec3 centroid;                      // m, body frame
  Mat3 inertia_per_density;           // m^5, about the centroid, body frame, full tensor
  Vec3 principal_inertia_per_density; // m^5, ascending
  Mat3 principal_axes;                // columns: principal axes in the body frame, det +1
  // Estimated relative error of the volume, the centroid (in units of the radius of gyration)
  // and the inertia (in units of its trace): the change of the last grid refinement; 0 where the
  // result is exact.
  double relative_precision = 0;
  int grid_levels = 0; // grid levels evaluated (0: exact, no grid)
};

// Volume moments about a reference point: integral of 1, x and x x^T (m^3, m^4, m^5).
struct VolumeMoments {
  double volume = 0;
  Vec3 first;
  Mat3 second;
};

inline VolumeMoments operator-(const VolumeMoments& a, const VolumeMoments& b) {
  return VolumeMoments{a.volume - b.volume, a.first - b.first, a.second + (-1.0) * b.second};
}

inline Mat3 outer(Vec3 u, Vec3 v) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m.m[i][j] = u[i] * v[j];
  return m;
}

// The moments of the axis-aligned cube of edge h centred at c, about the reference point.
inline void add_cube_moments(VolumeMoments& m, Vec3 c, double h) {
  const double v = h * h * h;
  m.volume += v;
  m.first += v * c;
  const double self = v * h * h / 12.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      m.second.m[a][b] += v * c[a] * c[b] + (a == b ? self : 0.0);
}

inline BodyMassProperties properties_of(const VolumeMoments& m, Vec3 reference) {
  BodyMassProperties props;
  props.volume = m.volume;
  const Vec3 c = (1.0 / m.volume) * m.first; // from the reference
  props.centroid = reference + c;
  Mat3 second; // about the centroid: M = S - V c c^T
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j)
      second.m[i][j] = second.m[j][i] =
          0.5 * (m.second.m[i][j] + m.second.m[j][i]) - m.volume * c[i] * c[j];
  // I = tr(M) 1 - M (I_xx = integral of y^2 + z^2, I_xy = -integral of x y).
  props.inertia_per_density = trace(second) * identity3() + (-1.0) * second;
  const SymmetricEigen principal = symmetric_eigen(props.inertia_per_density);
  props.principal_inertia_per_density = principal.values;
  props.principal_axes = principal.vectors;
  return props;
}

// The change between two estimates, relative to the later one's volume, radius of gyration
// r_g = sqrt(tr I / (2 V)) (the centroid) and tr I (every entry of the tensor).
inline double relative_change(const BodyMassProperties& now, const BodyMassProperties& before) {
  const double inertia_scale = trace(now.inertia_per_density);
  const double gyration = std::sqrt(inertia_scale / (2.0 * now.volume));
  double change = std::max(std::fabs(now.volume - before.volume) / now.volume,
                           norm(now.centroid - before.centroid) / gyration);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      change = std::max(
          change, std::fabs(now.inertia_per_density.m[i][j] - before.inertia_per_density.m[i][j]) /
                      inertia_scale);
  return change;
}

} // namespace kdem
