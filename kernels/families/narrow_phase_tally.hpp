#pragma once
// Counters of the iterative narrow phases (evaluations, iterations, fallbacks, failures) that
// reach the run summary, shared by every pair type that has such a narrow phase.
#include <cstdint>

#include "../types.hpp"

namespace kdem {

// Sums over narrow-phase evaluations, reduced over a kernel's pairs rather than counted with
// atomics: on a GPU thousands of lanes adding to one address would serialise. Integers, so the
// sums do not depend on the order of the reduction.
struct NarrowPhaseTally {
  std::int64_t evaluations = 0, iterations = 0, fallbacks = 0, failures = 0;

  // r: any result with `iterations` and `status` (0 converged, 1 through a fallback, 2 failed).
  template <class Result> KOKKOS_INLINE_FUNCTION void add(const Result& r) {
    ++evaluations;
    iterations += r.iterations;
    fallbacks += r.status == 1 ? 1 : 0;
    failures += r.status == 2 ? 1 : 0;
  }
  KOKKOS_INLINE_FUNCTION NarrowPhaseTally& operator+=(const NarrowPhaseTally& o) {
    evaluations += o.evaluations;
    iterations += o.iterations;
    fallbacks += o.fallbacks;
    failures += o.failures;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile NarrowPhaseTally& o) volatile {
    evaluations += o.evaluations;
    iterations += o.iterations;
    fallbacks += o.fallbacks;
    failures += o.failures;
  }
};

} // namespace kdem

namespace Kokkos {
template <> struct reduction_identity<kdem::NarrowPhaseTally> {
  KOKKOS_FORCEINLINE_FUNCTION static kdem::NarrowPhaseTally sum() { return {}; }
};
} // namespace Kokkos

namespace kdem {

// Running totals of the iterative narrow phases' evaluations, kept in the engine's memory: each
// kernel reduces its own tally into `kernel_tally` (no host wait) and a one-lane kernel adds it.
struct NarrowPhaseCounters {
  DeviceView<NarrowPhaseTally> totals;
  DeviceView<NarrowPhaseTally> kernel_tally;
  // Empty handles (a context that is assigned its counters later allocates nothing).
  NarrowPhaseCounters() = default;
  static NarrowPhaseCounters allocate() {
    NarrowPhaseCounters c;
    c.totals = DeviceView<NarrowPhaseTally>("narrow_phase_totals");
    c.kernel_tally = DeviceView<NarrowPhaseTally>("narrow_phase_tally");
    return c;
  }

  Kokkos::Sum<NarrowPhaseTally, MemSpace> reducer() const {
    return Kokkos::Sum<NarrowPhaseTally, MemSpace>(kernel_tally);
  }
  // Defined in narrow_phase_tally.cpp: a lambda-holding function compiled in one unit only
  // (kernels/integrate.hpp says why).
  void add_kernel_tally() const;
};

} // namespace kdem
