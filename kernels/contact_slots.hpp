#pragma once
// Contact slots of candidate lists, and the lookup by key in a CSR row that history transfer
// uses.
#include <cstdint>

#include "types.hpp"

namespace kdem {

// Where the contact points of each candidate (a particle pair, or a particle and a wall
// element) live: candidate k owns contact slots [first(k), end(k)). With `start` empty every
// candidate has one slot, slot k (scenes whose families all have one contact point); otherwise
// start has one entry per candidate and one more.
struct ContactSlots {
  IndexView start;

  KOKKOS_INLINE_FUNCTION bool single() const { return start.extent(0) == 0; }
  KOKKOS_INLINE_FUNCTION int first(int k) const { return single() ? k : start(k); }
  KOKKOS_INLINE_FUNCTION int end(int k) const { return single() ? k + 1 : start(k + 1); }
};

// Finds, in row `row` of a CSR list keyed by partner ids, the entry whose key is `key`; -1 if none.
KOKKOS_INLINE_FUNCTION int find_in_row(const IndexView& row_start, const IdView& keys, int row,
                                       std::int64_t key) {
  if (row < 0)
    return -1;
  for (int k = row_start(row); k < row_start(row + 1); ++k)
    if (keys(k) == key)
      return k;
  return -1;
}

} // namespace kdem
