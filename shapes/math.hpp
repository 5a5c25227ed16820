#pragma once
// Device-callable math functions under one name, for Kokkos 3.4 (Kokkos::Experimental) and 4.x
// (Kokkos).
#include <Kokkos_Core.hpp>

// KDEM_ONE_COPY_FUNCTION: a device-callable function compiled once and called, never inlined or
// cloned. For tests that must give the same bits wherever they are made (two triangles deciding
// which of them claims a point): a compiler may contract a * b + c into a fused multiply-add
// differently in each inlined copy of one expression (GCC where the target has FMA, nvcc always),
// so only a single compiled copy is sure to round alike for every caller.
#if defined(__CUDACC__)
#define KDEM_ONE_COPY_FUNCTION __noinline__ KOKKOS_INLINE_FUNCTION
#elif defined(__clang__)
#define KDEM_ONE_COPY_FUNCTION __attribute__((noinline)) KOKKOS_INLINE_FUNCTION
#else
#define KDEM_ONE_COPY_FUNCTION __attribute__((noipa)) KOKKOS_INLINE_FUNCTION
#endif

// KDEM_WHOLE_FUNCTION: KDEM_ONE_COPY_FUNCTION with everything it calls inlined into it (GCC and
// clang: flatten), so that its code does not depend on the translation unit it is compiled in.
// The Serial and OpenMP engines compile the same kernels in translation units of their own, and
// where a callee is inlined depends on what else the unit holds; with fused multiply-adds that
// decides the last bits. For the narrow phases, so that both engines run the same instructions.
#if defined(__CUDACC__)
#define KDEM_WHOLE_FUNCTION KDEM_ONE_COPY_FUNCTION
#else
#define KDEM_WHOLE_FUNCTION __attribute__((flatten)) KDEM_ONE_COPY_FUNCTION
#endif

namespace kdem::math {
#if KOKKOS_VERSION >= 40000
using Kokkos::cbrt;
using Kokkos::cos;
using Kokkos::exp;
using Kokkos::fabs;
using Kokkos::floor;
using Kokkos::isfinite;
using Kokkos::log;
using Kokkos::pow;
using Kokkos::sin;
using Kokkos::sqrt;
#else
using Kokkos::Experimental::cbrt;
using Kokkos::Experimental::cos;
using Kokkos::Experimental::exp;
using Kokkos::Experimental::fabs;
using Kokkos::Experimental::floor;
using Kokkos::Experimental::isfinite;
using Kokkos::Experimental::log;
using Kokkos::Experimental::pow;
using Kokkos::Experimental::sin;
using Kokkos::Experimental::sqrt;
#endif
KOKKOS_INLINE_FUNCTION double min(double a, double b) {
  return a < b ? a : b;
}
KOKKOS_INLINE_FUNCTION double max(double a, double b) {
  return a > b ? a : b;
}
KOKKOS_INLINE_FUNCTION double clamp(double v, double lo, double hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}
// 1 - 3 t^2 + 2 t^3 on [0, 1], 1 before and 0 after (and for NaN): a smooth step from 1 at 0 to
// 0 at 1 with zero slope at both ends.
KOKKOS_INLINE_FUNCTION double falloff(double t) {
  if (!(t < 1))
    return 0;
  return t <= 0 ? 1.0 : 1.0 - t * t * (3.0 - 2.0 * t);
}
} // namespace kdem::math
