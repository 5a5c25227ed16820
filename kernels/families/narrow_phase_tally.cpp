#include "narrow_phase_tally.hpp"

namespace kdem {

void NarrowPhaseCounters::add_kernel_tally() const {
  auto sum = totals;
  auto part = kernel_tally;
  Kokkos::parallel_for(
      "kdem::narrow_phase_tally", RangePolicy(0, 1), KOKKOS_LAMBDA(int) { sum() += part(); });
}

} // namespace kdem
