#pragma once
// Small numeric helpers shared by the shape tests: matrix norms and comparisons, formatting of
// measured values, and tanh-sinh quadrature nodes.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "shapes/mat3.hpp"
#include "shapes/sphere.hpp"

namespace kdem::testing {

inline std::string scientific(double v) {
  std::ostringstream out;
  out << std::scientific << v;
  return out.str();
}

inline Mat3 diagonal(Vec3 d) {
  Mat3 a;
  a.m[0][0] = d.x, a.m[1][1] = d.y, a.m[2][2] = d.z;
  return a;
}

inline double frobenius(const Mat3& a) {
  double sum = 0;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      sum += a.m[r][k] * a.m[r][k];
  return std::sqrt(sum);
}

inline double max_abs_difference(const Mat3& a, const Mat3& b) {
  double largest = 0;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      largest = std::max(largest, std::fabs(a.m[r][k] - b.m[r][k]));
  return largest;
}

inline double determinant(const Mat3& a) {
  return dot(cross(column(a, 0), column(a, 1)), column(a, 2));
}

// Tanh-sinh nodes on [0, 1] (exponentially convergent even with the (1 - x)^(1/n) endpoint
// behaviour of superquadric limits of integration), with each node's distance to 1 kept
// separately: 1 - x would cancel near 1.
struct QuadratureNode {
  double x, complement, weight;
};

inline std::vector<QuadratureNode> tanh_sinh_nodes(int per_unit, double reach) {
  std::vector<QuadratureNode> nodes;
  const double h = 1.0 / per_unit;
  const int count = int(reach * per_unit);
  for (int i = -count; i <= count; ++i) {
    const double t = i * h;
    const double s = 0.5 * pi * std::sinh(t);
    const double cosh_s = std::cosh(s);
    nodes.push_back({1.0 / (1.0 + std::exp(-2.0 * s)), 1.0 / (1.0 + std::exp(2.0 * s)),
                     h * 0.25 * pi * std::cosh(t) / (cosh_s * cosh_s)});
  }
  return nodes;
}

} // namespace kdem::testing
