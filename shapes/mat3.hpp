#pragma once
// 3 x 3 matrices (row-major), callable on host and device: Hessians of shape functions and
// rotation matrices of orientations.
#include "vec3.hpp"

namespace kdem {

struct Mat3 {
  double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
};

KOKKOS_INLINE_FUNCTION Vec3 operator*(const Mat3& a, Vec3 v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}

KOKKOS_INLINE_FUNCTION Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      c.m[r][k] = a.m[r][0] * b.m[0][k] + a.m[r][1] * b.m[1][k] + a.m[r][2] * b.m[2][k];
  return c;
}

KOKKOS_INLINE_FUNCTION Mat3 operator+(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      c.m[r][k] = a.m[r][k] + b.m[r][k];
  return c;
}

KOKKOS_INLINE_FUNCTION Mat3 operator*(double s, const Mat3& a) {
  Mat3 c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      c.m[r][k] = s * a.m[r][k];
  return c;
}

KOKKOS_INLINE_FUNCTION Mat3 identity3() {
  Mat3 a;
  a.m[0][0] = a.m[1][1] = a.m[2][2] = 1;
  return a;
}

KOKKOS_INLINE_FUNCTION Mat3 transpose(const Mat3& a) {
  Mat3 t;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      t.m[r][k] = a.m[k][r];
  return t;
}

// transpose(a) * v without forming the transpose (the same operations in the same order).
KOKKOS_INLINE_FUNCTION Vec3 transpose_times(const Mat3& a, Vec3 v) {
  return {a.m[0][0] * v.x + a.m[1][0] * v.y + a.m[2][0] * v.z,
          a.m[0][1] * v.x + a.m[1][1] * v.y + a.m[2][1] * v.z,
          a.m[0][2] * v.x + a.m[1][2] * v.y + a.m[2][2] * v.z};
}

KOKKOS_INLINE_FUNCTION double trace(const Mat3& a) {
  return a.m[0][0] + a.m[1][1] + a.m[2][2];
}

KOKKOS_INLINE_FUNCTION Vec3 column(const Mat3& a, int k) {
  return {a.m[0][k], a.m[1][k], a.m[2][k]};
}

// The entries of the body-to-world rotation matrix of a unit quaternion (w, x, y, z), row-major.
// T: double, or the lanes of shapes/lanes.hpp.
template <class T> KOKKOS_INLINE_FUNCTION void rotation_entries(T w, T x, T y, T z, T (&m)[3][3]) {
  m[0][0] = 1 - 2 * (y * y + z * z);
  m[0][1] = 2 * (x * y - w * z);
  m[0][2] = 2 * (x * z + w * y);
  m[1][0] = 2 * (x * y + w * z);
  m[1][1] = 1 - 2 * (x * x + z * z);
  m[1][2] = 2 * (y * z - w * x);
  m[2][0] = 2 * (x * z - w * y);
  m[2][1] = 2 * (y * z + w * x);
  m[2][2] = 1 - 2 * (x * x + y * y);
}

// Body-to-world rotation matrix of a unit quaternion: rotation_matrix(q) * v == rotate(q, v).
KOKKOS_INLINE_FUNCTION Mat3 rotation_matrix(Quat q) {
  Mat3 r;
  rotation_entries(q.w, q.x, q.y, q.z, r.m);
  return r;
}

// R A R^T: a body-frame tensor seen in the world frame.
KOKKOS_INLINE_FUNCTION Mat3 rotate_tensor(const Mat3& rotation, const Mat3& body) {
  return rotation * body * transpose(rotation);
}

} // namespace kdem
