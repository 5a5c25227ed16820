#pragma once
// Small fixed-size vector and quaternion algebra, callable on host and device.
#include "math.hpp"

namespace kdem {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  Vec3() = default;
  KOKKOS_INLINE_FUNCTION Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  KOKKOS_INLINE_FUNCTION double operator[](int k) const { return k == 0 ? x : (k == 1 ? y : z); }
};

KOKKOS_INLINE_FUNCTION Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
KOKKOS_INLINE_FUNCTION Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
KOKKOS_INLINE_FUNCTION Vec3 operator-(Vec3 a) {
  return {-a.x, -a.y, -a.z};
}
KOKKOS_INLINE_FUNCTION Vec3 operator*(double s, Vec3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
KOKKOS_INLINE_FUNCTION Vec3 operator*(Vec3 a, double s) {
  return {s * a.x, s * a.y, s * a.z};
}
KOKKOS_INLINE_FUNCTION Vec3& operator+=(Vec3& a, Vec3 b) {
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
KOKKOS_INLINE_FUNCTION Vec3& operator-=(Vec3& a, Vec3 b) {
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
  return a;
}
KOKKOS_INLINE_FUNCTION double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
KOKKOS_INLINE_FUNCTION Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
KOKKOS_INLINE_FUNCTION double norm2(Vec3 a) {
  return dot(a, a);
}
KOKKOS_INLINE_FUNCTION double norm(Vec3 a) {
  return math::sqrt(dot(a, a));
}

// Unit quaternion (w, x, y, z), Hamilton convention, rotating body frame to world frame.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
  Quat() = default;
  KOKKOS_INLINE_FUNCTION Quat(double w_, double x_, double y_, double z_)
      : w(w_), x(x_), y(y_), z(z_) {}
};

KOKKOS_INLINE_FUNCTION Quat operator*(Quat a, Quat b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

KOKKOS_INLINE_FUNCTION Quat normalized(Quat q) {
  const double inv = 1.0 / math::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w * inv, q.x * inv, q.y * inv, q.z * inv};
}

KOKKOS_INLINE_FUNCTION Vec3 rotate(Quat q, Vec3 v) {
  // v' = v + 2 w (u x v) + 2 u x (u x v), u = vector part
  const Vec3 u{q.x, q.y, q.z};
  const Vec3 t = 2.0 * cross(u, v);
  return v + q.w * t + cross(u, t);
}

KOKKOS_INLINE_FUNCTION Vec3 rotate_inverse(Quat q, Vec3 v) {
  return rotate(Quat{q.w, -q.x, -q.y, -q.z}, v);
}

// sin(a/2) / a and cos(a/2) of a rotation angle a. Below 1e-3 rad the series
// cos(a/2) = 1 - a^2/8 + a^4/384, sin(a/2) / a = 1/2 - a^2/48 + a^4/3840 are exact to double
// precision (next terms below 1e-19 relative) and avoid the transcendental calls of every time
// step.
struct HalfAngle {
  double sine_over_angle = 0.5, cosine = 1;
};

constexpr double half_angle_series_limit2 = 1e-6; // a^2 below which the series are used

KOKKOS_INLINE_FUNCTION HalfAngle half_angle_series(double angle2) {
  const double a4 = angle2 * angle2;
  return {0.5 - angle2 / 48.0 + a4 / 3840.0, 1.0 - angle2 / 8.0 + a4 / 384.0};
}

// sin(a/2) and cos(a/2).
KOKKOS_INLINE_FUNCTION void half_angle_sine_cosine(double angle, double& sine, double& cosine) {
  const double angle2 = angle * angle;
  if (angle2 < half_angle_series_limit2) {
    const HalfAngle h = half_angle_series(angle2);
    sine = angle * h.sine_over_angle;
    cosine = h.cosine;
  } else {
    sine = math::sin(0.5 * angle);
    cosine = math::cos(0.5 * angle);
  }
}

// Rotation by angle |phi| about phi/|phi|, exact for any angle.
KOKKOS_INLINE_FUNCTION Quat quat_from_rotation_vector(Vec3 phi) {
  const double angle2 = norm2(phi);
  HalfAngle h;
  if (angle2 < half_angle_series_limit2) {
    h = half_angle_series(angle2);
  } else {
    const double angle = math::sqrt(angle2);
    h = {math::sin(0.5 * angle) / angle, math::cos(0.5 * angle)};
  }
  const double s = h.sine_over_angle;
  return {h.cosine, s * phi.x, s * phi.y, s * phi.z};
}

} // namespace kdem
