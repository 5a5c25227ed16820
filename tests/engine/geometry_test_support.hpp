#pragma once
// Helpers shared by the superquadric geometry tests: host-side random inputs (mt19937_64 streams,
// so that a seed gives the same cases on every backend) and a runner that evaluates a device
// functor over a std::vector of cases in a parallel_for on the engine's execution space.
#include <Kokkos_Core.hpp>

#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "kernels/types.hpp"
#include "shapes/superquadric.hpp"

namespace kdem {

// ------------------------------------------------------------------ random inputs

// Uniform in [lo, hi) from the top 53 bits of one draw.
inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * ((rng() >> 11) * 0x1.0p-53);
}

// Log-uniform in [lo, hi): one uniform draw in log space.
inline double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(uniform(rng, std::log(lo), std::log(hi)));
}

// Uniform on the unit sphere: a normalised Gaussian vector.
inline Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  const Vec3 v{gauss(rng), gauss(rng), gauss(rng)};
  return (1.0 / norm(v)) * v;
}

// A random unit vector perpendicular to the unit vector `direction`: a random_unit draw with its
// component along `direction` removed, normalised.
inline Vec3 random_unit_perpendicular(std::mt19937_64& rng, Vec3 direction) {
  Vec3 v = random_unit(rng);
  v = v - dot(v, direction) * direction;
  return (1.0 / norm(v)) * v;
}

// Uniform over rotations: a normalised Gaussian quaternion.
inline Quat random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  return normalized(Quat{gauss(rng), gauss(rng), gauss(rng), gauss(rng)});
}

// Rotation by `angle` about `axis` (any length), from the half-angle sine and cosine.
inline Quat axis_angle(Vec3 axis, double angle) {
  const Vec3 u = (1.0 / norm(axis)) * axis;
  const double s = std::sin(0.5 * angle);
  return {std::cos(0.5 * angle), s * u.x, s * u.y, s * u.z};
}

// The same rotation through quat_from_rotation_vector (rounds differently from axis_angle).
inline Quat axis_angle_by_rotation_vector(Vec3 axis, double angle) {
  return quat_from_rotation_vector((angle / norm(axis)) * axis);
}

// Semi-axes a log-uniform in [0.5, 2], b / a and c / a log-uniform in [0.2, 5]; exponents
// uniform in [2, n_max].
inline SuperquadricShape random_shape(std::mt19937_64& rng, double n_max) {
  const double a = log_uniform(rng, 0.5, 2.0);
  return make_superquadric(a, a * log_uniform(rng, 0.2, 5.0), a * log_uniform(rng, 0.2, 5.0),
                           uniform(rng, 2.0, n_max), uniform(rng, 2.0, n_max));
}

// Semi-axes each log-uniform in [0.2, 2] independently; exponents uniform in [2, 10].
inline SuperquadricShape random_shape_independent_axes(std::mt19937_64& rng) {
  const auto length = [&] { return log_uniform(rng, 0.2, 2.0); };
  return make_superquadric(length(), length(), length(), uniform(rng, 2, 10), uniform(rng, 2, 10));
}

// ------------------------------------------------------------------ device runs

template <class T> using Cases = DeviceView<T*>;

template <class T> Cases<T> to_device(const std::vector<T>& host, const char* label) {
  Cases<T> device(std::string(label), host.size());
  auto mirror = Kokkos::create_mirror_view(device);
  for (std::size_t i = 0; i < host.size(); ++i)
    mirror(i) = host[i];
  Kokkos::deep_copy(device, mirror);
  return device;
}

template <class T> std::vector<T> to_host(const Cases<T>& device) {
  auto mirror = Kokkos::create_mirror_view(device);
  Kokkos::deep_copy(mirror, device);
  return std::vector<T>(mirror.data(), mirror.data() + mirror.extent(0));
}

// Applies `Compute` to every case on the device. A functor rather than an extended lambda, so
// that nvcc accepts it wherever it is launched from.
template <class Case, class Result, class Compute> struct CaseKernel {
  Cases<Case> in;
  Cases<Result> out;
  Compute compute;
  KOKKOS_INLINE_FUNCTION void operator()(int i) const { out(i) = compute(in(i)); }
};

// compute(case) for every case in a parallel_for on KDEM_EXEC_SPACE, results copied to the host.
template <class Result, class Case, class Compute>
std::vector<Result> run_on_device(const std::vector<Case>& cases, Compute compute) {
  const Cases<Case> in = to_device(cases, "cases");
  const Cases<Result> out("results", cases.size());
  Kokkos::parallel_for("kdem::geometry_test_cases", RangePolicy(0, int(cases.size())),
                       CaseKernel<Case, Result, Compute>{in, out, compute});
  Kokkos::fence();
  return to_host(out);
}

} // namespace kdem
