#pragma once
// Device-callable math functions under one name, for Kokkos 3.4 (Kokkos::Experimental) and 4.x
// (Kokkos).
#include <Kokkos_Core.hpp>

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
} // namespace kdem::math
