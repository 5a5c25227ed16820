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

// What the first `kept` slots of a candidate held at the last step: the feature key and the
// history of each. A contact found now takes the history of the slot that held its key (the
// last such slot), or a fresh one.
// Only the first `kept` entries are set (see PairContacts: setting all K for every pair and
// every step cost more than the contacts did).
template <int K, class Key, class History> struct PreviousSlots {
  int kept = 0;
  union {
    Key key[K];
  };
  union {
    History history[K];
  };

  KOKKOS_INLINE_FUNCTION PreviousSlots() {}

  KOKKOS_INLINE_FUNCTION History matching(const Key& wanted) const {
    History found{};
    for (int m = 0; m < kept; ++m)
      if (key[m] == wanted)
        found = history[m];
    return found;
  }
};

// Reads slots [first, first + kept); `read(slot, key, history)` fills one.
template <int K, class Key, class History, class Read>
KOKKOS_INLINE_FUNCTION PreviousSlots<K, Key, History> read_previous_slots(int first, int kept,
                                                                          const Read& read) {
  PreviousSlots<K, Key, History> previous;
  previous.kept = kept;
  for (int m = 0; m < kept; ++m)
    read(first + m, previous.key[m], previous.history[m]);
  return previous;
}

// The features of a particle pair's contact point: of i, of j.
struct FeaturePair {
  int on_i = -1, on_j = -1;
  KOKKOS_INLINE_FUNCTION bool operator==(const FeaturePair& other) const {
    return on_i == other.on_i && on_j == other.on_j;
  }
};

} // namespace kdem
