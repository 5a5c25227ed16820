#pragma once
// Dense 4 x 4 linear solve by LU factorisation with partial (row) pivoting, callable on host and
// device: the Newton systems of the superquadric narrow phase.
#include "math.hpp"

namespace kdem {

struct Matrix4 {
  double m[4][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
};

struct Vector4 {
  double v[4] = {0, 0, 0, 0};
};

constexpr double double_epsilon = 2.220446049250313e-16;

// A pivot below this multiple of machine epsilon times the largest entry of the matrix makes the
// matrix singular to working precision (Golub & Van Loan, Sect. 3.4: the backward error of
// pivoted LU is a small multiple of n eps |A|, so smaller pivots are indistinguishable from 0).
constexpr double singular_pivot_factor = 16.0 * double_epsilon;

KOKKOS_INLINE_FUNCTION bool is_finite(double x) {
  return x - x == 0.0; // false for NaN and +-inf
}

KOKKOS_INLINE_FUNCTION double largest_magnitude(const Matrix4& a) {
  double largest = 0;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      largest = math::max(largest, math::fabs(a.m[r][c]));
  return largest;
}

// Solves a x = b. Returns false, leaving x at zero, when a is singular to working precision or
// holds a non-finite entry; then no NaN escapes.
KOKKOS_INLINE_FUNCTION bool solve_4x4(Matrix4 a, Vector4 b, Vector4& x) {
  x = Vector4{};
  const double largest = largest_magnitude(a);
  if (!is_finite(largest) || !(largest > 0))
    return false;
  const double smallest_pivot = singular_pivot_factor * largest;
  for (int k = 0; k < 4; ++k) {
    int pivot_row = k;
    for (int r = k + 1; r < 4; ++r)
      if (math::fabs(a.m[r][k]) > math::fabs(a.m[pivot_row][k]))
        pivot_row = r;
    if (!(math::fabs(a.m[pivot_row][k]) > smallest_pivot))
      return false;
    if (pivot_row != k) {
      for (int c = 0; c < 4; ++c) {
        const double t = a.m[k][c];
        a.m[k][c] = a.m[pivot_row][c];
        a.m[pivot_row][c] = t;
      }
      const double t = b.v[k];
      b.v[k] = b.v[pivot_row];
      b.v[pivot_row] = t;
    }
    for (int r = k + 1; r < 4; ++r) {
      const double factor = a.m[r][k] / a.m[k][k];
      for (int c = k + 1; c < 4; ++c)
        a.m[r][c] -= factor * a.m[k][c];
      b.v[r] -= factor * b.v[k];
    }
  }
  Vector4 solution;
  for (int r = 3; r >= 0; --r) {
    double sum = b.v[r];
    for (int c = r + 1; c < 4; ++c)
      sum -= a.m[r][c] * solution.v[c];
    solution.v[r] = sum / a.m[r][r];
    if (!is_finite(solution.v[r]))
      return false;
  }
  x = solution;
  return true;
}

} // namespace kdem
