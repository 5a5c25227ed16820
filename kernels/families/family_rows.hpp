#pragma once
// Which family each particle belongs to, and the rows of each particle family and of each pair
// type, rebuilt with the candidate lists: the typed kernels of a family or pair type run over
// its rows only, and a pair type with no rows launches nothing.
#include <string>

#include "../pair_list.hpp"
#include "../walls.hpp"
#include "family_list.hpp"

namespace kdem {

// Device map from a particle's shape id to its family (index in the family list) and to its
// template within that family.
struct ShapeFamilies {
  IndexView family_of_shape;
  IndexView template_of_shape;
  IndexView features_of_shape; // contact features (a clump's elements); empty: 1 for every shape

  KOKKOS_INLINE_FUNCTION int family(int shape) const { return family_of_shape(shape); }
  KOKKOS_INLINE_FUNCTION int template_index(int shape) const { return template_of_shape(shape); }
  KOKKOS_INLINE_FUNCTION int features(int shape) const {
    return features_of_shape.extent(0) == 0 ? 1 : features_of_shape(shape);
  }
};

// Rows of one particle family or one pair type: every row of the store in order (a scene of
// one family), or the listed rows, ascending.
struct RowSet {
  int count = 0;
  bool all = false;
  IndexView listed;

  KOKKOS_INLINE_FUNCTION int operator()(int m) const { return all ? m : listed(m); }
};

// The rows of one pair type, and work space that its kernels may size once per list build (a
// prefilter's pass flags and survivors), so that a step allocates nothing.
struct PairTypeRows {
  RowSet rows;
  IndexView passes, survivors;
};

// Per-key counts of a scan: the running count of rows of each key.
template <int Keys> struct KeyCounts {
  int n[Keys] = {};

  KOKKOS_INLINE_FUNCTION KeyCounts& operator+=(const KeyCounts& o) {
    for (int k = 0; k < Keys; ++k)
      n[k] += o.n[k];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile KeyCounts& o) volatile {
    for (int k = 0; k < Keys; ++k)
      n[k] += o.n[k];
  }
};

template <int Keys> struct KeyedViews { IndexView rows[Keys]; };

// Sorts rows [0, count) by key_of(row) in [0, Keys), keeping the row order within a key (a
// stable counting sort): one scan, one host wait for the totals and one fill, for any number
// of keys.
template <int Keys, class KeyOf>
void rows_by_key(const std::string& label, int count, KeyOf key_of, RowSet (&sets)[Keys]) {
  auto position = uninitialized<IndexView>(label + "_position", count);
  KeyCounts<Keys> totals;
  Kokkos::parallel_scan(
      "kdem::rows_by_key", RangePolicy(0, count),
      KOKKOS_LAMBDA(int row, KeyCounts<Keys>& running, bool final) {
        const int key = key_of(row);
        if (final)
          position(row) = running.n[key];
        running.n[key] += 1;
      },
      totals);
  KeyedViews<Keys> keyed;
  for (int k = 0; k < Keys; ++k) {
    keyed.rows[k] = uninitialized<IndexView>(label + "_" + std::to_string(k), totals.n[k]);
    sets[k] = RowSet{totals.n[k], false, keyed.rows[k]};
  }
  Kokkos::parallel_for(
      "kdem::rows_by_key_fill", RangePolicy(0, count),
      KOKKOS_LAMBDA(int row) { keyed.rows[key_of(row)](position(row)) = row; });
}

// The most contact points a pair of bodies of families A and B keeps: one per pair of the
// features each may touch with (a sphere: 1; a clump of n elements: n), at most
// max_pair_contact_points (a narrow phase that finds more counts the rest as missed).
constexpr int max_pair_contact_points = 16;
constexpr int capped_contact_points(int points) {
  return points < max_pair_contact_points ? points : max_pair_contact_points;
}
template <class A, class B>
constexpr int pair_contact_points = capped_contact_points(A::contact_points* B::contact_points);

template <int Count> struct PerPairType {
  int value[Count] = {};
};

template <class List> struct FamilyRows {
  static constexpr int families = List::size;
  static constexpr int pair_types = pair_type_count(List::size);
  RowSet particles[families];
  PairTypeRows pairs[pair_types];

  template <class F> const RowSet& of() const { return particles[family_index_v<F, List>]; }
  template <class A, class B> PairTypeRows& of_pair() {
    return pairs[pair_type_index_v<A, B, List>];
  }
};

// The rows of each family and pair type. With one family present every particle and pair is
// of it, and no sort runs; otherwise two key sorts (particles, pairs).
template <class List>
FamilyRows<List> sort_into_families(const ParticleViews& p, const PairList& list,
                                    const ShapeFamilies& shapes, int single_family) {
  FamilyRows<List> f;
  if (single_family >= 0) {
    f.particles[single_family] = RowSet{p.count, true, {}};
    f.pairs[pair_type_index(single_family, single_family, List::size)].rows =
        RowSet{list.pair_count, true, {}};
    return f;
  }
  auto shape = p.shape;
  rows_by_key<List::size>(
      "family_rows", p.count, KOKKOS_LAMBDA(int i) { return shapes.family(shape(i)); },
      f.particles);
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  RowSet pair_sets[FamilyRows<List>::pair_types];
  rows_by_key<FamilyRows<List>::pair_types>(
      "pair_type_rows", list.pair_count,
      KOKKOS_LAMBDA(int k) {
        return pair_type_index(shapes.family(shape(pair_i(k))), shapes.family(shape(pair_j(k))),
                               List::size);
      },
      pair_sets);
  for (int t = 0; t < FamilyRows<List>::pair_types; ++t)
    f.pairs[t].rows = pair_sets[t];
  return f;
}

// Gives each pair as many contact slots as its bodies have pairs of features, within its pair
// type's contact points, when some pair type of the families in `present` has more than one;
// otherwise every pair keeps one slot.
template <class List>
void assign_slots_by_pair_type(PairList& list, const ParticleViews& p, const ShapeFamilies& shapes,
                               int present) {
  constexpr int types = pair_type_count(List::size);
  PerPairType<types> points;
  bool several = false;
  for_each_pair_type<List>([&](auto tag_a, auto tag_b) {
    using A = typename decltype(tag_a)::type;
    using B = typename decltype(tag_b)::type;
    constexpr int t = pair_type_index_v<A, B, List>;
    points.value[t] = pair_contact_points<A, B>;
    const int both = (1 << family_index_v<A, List>) | (1 << family_index_v<B, List>);
    several = several || ((present & both) == both && points.value[t] > 1);
  });
  if (!several)
    return;
  auto shape = p.shape;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  assign_contact_slots(
      list, KOKKOS_LAMBDA(int k) {
        const int si = shape(pair_i(k)), sj = shape(pair_j(k));
        const int most =
            points.value[pair_type_index(shapes.family(si), shapes.family(sj), List::size)];
        const int features = shapes.features(si) * shapes.features(sj);
        return features < most ? features : most;
      });
}

// Gives each wall entry as many contact slots as its particle has features, within its family's
// contact points, when some family in `present` has more than one; otherwise every entry keeps
// one slot.
template <class List>
void assign_wall_slots_by_family(WallContactList& list, const ParticleViews& p,
                                 const ShapeFamilies& shapes, int present) {
  PerPairType<List::size> points;
  bool several = false;
  for_each_family<List>([&](auto tag) {
    using F = typename decltype(tag)::type;
    constexpr int f = family_index_v<F, List>;
    points.value[f] = F::contact_points;
    several = several || ((present & (1 << f)) != 0 && F::contact_points > 1);
  });
  if (!several)
    return;
  auto shape = p.shape;
  assign_wall_contact_slots(
      list, p.count, KOKKOS_LAMBDA(int i) {
        const int most = points.value[shapes.family(shape(i))];
        const int features = shapes.features(shape(i));
        return features < most ? features : most;
      });
}

} // namespace kdem
