#pragma once
// Lanes: four doubles handled by one instruction (GCC and clang vector extensions; AVX2 holds
// them in one register), for the host narrow phase that solves four pairs in lock step
// (superquadric_lanes.hpp). Host code only: where the compiler is nvcc, KDEM_HOST_LANES is 0 and
// nothing here is defined, so a GPU build solves one pair per thread as before.
//
// Every operation is the IEEE operation of each lane, so a lane computes what the scalar code
// computes from the same formulas (up to the contraction of a * b + c into a fused multiply-add,
// which the compiler may decide differently for scalar and vector code). Conditions are masks
// (all bits set where true) and branches become selects; a lane whose case the lanes do not
// handle is handed to the scalar code.
#include <cmath>

#include "mat3.hpp"

#if !defined(__CUDACC__) && (defined(__GNUC__) || defined(__clang__))
#define KDEM_HOST_LANES 1
#else
#define KDEM_HOST_LANES 0
#endif

#if KDEM_HOST_LANES
namespace kdem::lanes {

// Four: eight (two AVX2 registers per value) ran at 0.63 of four, the values no longer fitting
// in the registers (docs/performance.md, section 22).
constexpr int width = 4;
typedef double Real __attribute__((vector_size(8 * width)));
using Mask = decltype(Real{} < Real{}); // what a comparison of lanes gives: 0 or -1 per lane

inline Real splat(double x) {
  return Real{} + x;
}
inline Mask no_lane() {
  return Mask{};
}
inline Real select(Mask m, Real a, Real b) { // a where m, else b
  return (Real)((m & (Mask)a) | (~m & (Mask)b));
}
inline Real abs(Real x) {
  constexpr long long magnitude_bits = 0x7fffffffffffffffLL;
  const Mask magnitude = Mask{} + magnitude_bits;
  return (Real)((Mask)x & magnitude);
}
inline Real sqrt(Real x) {
  Real r{};
  for (int l = 0; l < width; ++l)
    r[l] = std::sqrt(x[l]);
  return r;
}
// As math::min and math::max: a < b ? a : b and a > b ? a : b lane by lane.
inline Real min(Real a, Real b) {
  return select(a < b, a, b);
}
inline Real max(Real a, Real b) {
  return select(a > b, a, b);
}
inline Real clamp(Real v, Real lo, Real hi) {
  return select(v < lo, lo, select(v > hi, hi, v));
}
inline Mask is_finite(Real x) { // false for NaN and +-inf, as kdem::is_finite
  return (x - x) == splat(0.0);
}
inline bool any(Mask m) {
  long long bits = 0;
  for (int l = 0; l < width; ++l)
    bits |= m[l];
  return bits != 0;
}
inline bool lane(Mask m, int l) {
  return m[l] != 0;
}
inline int bits(Mask m) { // lane l true sets bit l
  int b = 0;
  for (int l = 0; l < width; ++l)
    b |= (m[l] != 0) << l;
  return b;
}

struct Vec {
  Real x, y, z;
};

inline Vec operator+(const Vec& a, const Vec& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec operator-(const Vec& a, const Vec& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec operator-(const Vec& a) {
  return {-a.x, -a.y, -a.z};
}
inline Vec operator*(Real s, const Vec& a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline Real dot(const Vec& a, const Vec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Real norm(const Vec& a) {
  return sqrt(dot(a, a));
}
inline Vec select(Mask m, const Vec& a, const Vec& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
inline Mask is_finite(const Vec& v) {
  return is_finite(v.x) & is_finite(v.y) & is_finite(v.z);
}
inline Vec unit_or_zero(const Vec& v) { // as narrow_phase::unit_or_zero
  const Real length = norm(v);
  return select(length > splat(0.0), (1.0 / length) * v, Vec{splat(0), splat(0), splat(0)});
}

// A rotation matrix per lane, row-major as Mat3.
struct Rotation {
  Real m[3][3];
};

inline Vec times(const Rotation& a, const Vec& v) { // as Mat3 * Vec3
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
inline Vec transpose_times(const Rotation& a, const Vec& v) { // as kdem::transpose_times
  return {a.m[0][0] * v.x + a.m[1][0] * v.y + a.m[2][0] * v.z,
          a.m[0][1] * v.x + a.m[1][1] * v.y + a.m[2][1] * v.z,
          a.m[0][2] * v.x + a.m[1][2] * v.y + a.m[2][2] * v.z};
}

// Body-to-world rotation matrices of unit quaternions (w, x, y, z) per lane, as
// kdem::rotation_matrix.
inline Rotation rotation_matrix(Real w, Real x, Real y, Real z) {
  Rotation r;
  rotation_entries(w, x, y, z, r.m);
  return r;
}

} // namespace kdem::lanes
#endif
