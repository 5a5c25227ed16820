#pragma once
// The one pair loop: for one pair type (families A, B), run its narrow phase over the rows the
// type selects this step and apply the contact law to the contacts it finds, storing the force
// per pair (summed per particle by sum_forces). NarrowPhase<A, B> is the pair type's functor:
//   NarrowPhase(const ContactContext&)                  built on the host each step
//   static constexpr const char* label;                 the kernel's name
//   static constexpr bool tallied;                      iterative: its evaluations are counted
//   static constexpr int max_contacts;                  contact points one pair may have
//   int team_size;                                      layout of the kernel, see launch.hpp
//   PairsToEvaluate select(const ContactContext&, PairTypeRows&) const
//                                                       the rows to evaluate (may launch a
//                                                       prefilter that clears rejected pairs)
//   KOKKOS_FUNCTION PairOutcome operator()(const PairRef&, PairContacts<max_contacts>&,
//                                          NarrowPhaseTally&) const
// Included only by the translation units of kernels/pairs/, which instantiate it.
#include <type_traits>

#include "../launch.hpp"
#include "../pair_forces.hpp"
#include "registry.hpp"

namespace kdem {

// A candidate pair as its narrow phase sees it: the stored row k with bodies i and j, and the
// same bodies as (a, b) with a of family A; flipped when a is j.
struct PairRef {
  int k, i, j;
  int a, b;
  bool flipped;
};

// What a narrow phase found: contact points (PairContacts, normals from b towards a), no
// contact (the pair's stored contacts are cleared), or nothing to do (a pair proven apart keeps
// what it stores).
enum class PairOutcome { touching, apart, unchanged };

// The rows a pair type evaluates this step: rows(s) for s < rows.count, except those with
// passes(s) == 0 when flagged (a prefilter that did not compact its survivors).
struct PairsToEvaluate {
  RowSet rows;
  IndexView passes;
  bool flagged = false;

  KOKKOS_INLINE_FUNCTION bool skipped(int s) const { return flagged && passes(s) == 0; }
};

template <class A, class B> struct NarrowPhase;

// Whether the stored pair's body i is not of family A (then the narrow phase's a is j); never
// for pairs of one family.
template <class A, class B>
KOKKOS_INLINE_FUNCTION bool pair_is_flipped(const ShapeFamilies& shapes, const ParticleViews& p,
                                            int i) {
  if constexpr (std::is_same_v<A, B>)
    return false;
  else
    return shapes.family(p.shape(i)) != family_index_v<A, Families>;
}

// Stores what a narrow phase found: one contact point into the pair's one slot, several into its
// slots by feature (PairSlots::apply_several).
template <class Law, int K>
KOKKOS_INLINE_FUNCTION void store_contacts(const PairSlots& slots, int k, const ParticleViews& p,
                                           int i, int j, const PairContacts<K>& found, bool flipped,
                                           const PairCoefficients& coefficients, double dt) {
  if constexpr (K == 1)
    slots.template apply<Law>(k, p, i, j, found.contact[0].geometry,
                              found.contact[0].effective_radius, coefficients, dt);
  else
    slots.template apply_several<Law, K>(k, p, i, j, found, flipped, coefficients, dt);
}

// The narrow phases without a prefilter evaluate every row of their type.
struct EveryRowOfTheType {
  PairsToEvaluate select(const ContactContext&, PairTypeRows& type_rows) const {
    return PairsToEvaluate{type_rows.rows, {}, false};
  }
};

// Pairs a narrow phase takes at a time: 1, or its lane_width where it has one (a host narrow
// phase that solves several pairs in lock step through
//   void operator()(const PairRef*, int count, PairContacts<max_contacts>*, PairOutcome*,
//                   NarrowPhaseTally&) const).
template <class Narrow, class = void> struct lane_width_of : std::integral_constant<int, 1> {};
template <class Narrow>
struct lane_width_of<Narrow, std::void_t<decltype(Narrow::lane_width)>>
    : std::integral_constant<int, Narrow::lane_width> {};

template <class A, class B, class Law>
void compute_pair_type(const ContactContext& c, PairTypeRows& type_rows) {
  using Narrow = NarrowPhase<A, B>;
  static_assert(Narrow::max_contacts == pair_contact_points<A, B>,
                "a narrow phase finds at most the contact points its pair type has slots for");
  const Narrow narrow(c);
  const PairsToEvaluate todo = narrow.select(c, type_rows);
  if (todo.rows.count == 0)
    return;
  const PairSlots slots(c.pairs);
  const ParticleViews p = c.particles;
  auto pair_i = c.pairs.pair_i, pair_j = c.pairs.pair_j;
  const ShapeFamilies shapes = c.shape_families;
  const CoefficientTable table = c.coefficients;
  const double dt = c.dt;
  constexpr int K = Narrow::max_contacts;
  const auto pair_ref = KOKKOS_LAMBDA(int s) {
    const int k = todo.rows(s), i = pair_i(k), j = pair_j(k);
    const bool flipped = pair_is_flipped<A, B>(shapes, p, i);
    return PairRef{k, i, j, flipped ? j : i, flipped ? i : j, flipped};
  };
  const auto apply =
      KOKKOS_LAMBDA(const PairRef& ref, PairOutcome outcome, PairContacts<K>& found) {
    if (outcome == PairOutcome::unchanged)
      return;
    if (outcome == PairOutcome::apart) {
      slots.clear(ref.k);
      return;
    }
    if (ref.flipped)
      for (int c = 0; c < found.count; ++c)
        found.contact[c].geometry.normal = -found.contact[c].geometry.normal;
    store_contacts<Law>(slots, ref.k, p, ref.i, ref.j, found, ref.flipped,
                        table(p.material(ref.i), p.material(ref.j)), dt);
  };
  const auto body = KOKKOS_LAMBDA(int s, NarrowPhaseTally& tally) {
    if (todo.skipped(s))
      return;
    const PairRef ref = pair_ref(s);
    PairContacts<K> found;
    const PairOutcome outcome = narrow(ref, found, tally);
    apply(ref, outcome, found);
  };
  const auto untallied = KOKKOS_LAMBDA(int s) {
    NarrowPhaseTally unused;
    body(s, unused);
  };
  constexpr int W = lane_width_of<Narrow>::value;
  if constexpr (W > 1) {
    static_assert(Narrow::tallied, "the pair types solved in lanes are tallied");
    const int count = todo.rows.count;
    // A host lambda: lane widths above 1 exist only in host builds (shapes/lanes.hpp).
    const auto group = [=](int g, NarrowPhaseTally& tally) {
      PairRef refs[W];
      PairContacts<K> found[W];
      PairOutcome outcomes[W];
      int taken = 0;
      for (int s = g * W; s < count && s < (g + 1) * W; ++s)
        if (!todo.skipped(s))
          refs[taken++] = pair_ref(s);
      narrow(refs, taken, found, outcomes, tally);
      for (int q = 0; q < taken; ++q)
        apply(refs[q], outcomes[q], found[q]);
    };
    reduce_over_items<NarrowPhaseTally>(Narrow::label, (count + W - 1) / W, narrow.team_size, group,
                                        c.counters.reducer());
    c.counters.add_kernel_tally();
  } else if constexpr (Narrow::tallied) {
    reduce_over_items<NarrowPhaseTally>(Narrow::label, todo.rows.count, narrow.team_size, body,
                                        c.counters.reducer());
    c.counters.add_kernel_tally();
  } else {
    Kokkos::parallel_for(Narrow::label, RangePolicy(0, todo.rows.count), untallied);
  }
}

// The one wall loop of a family: its wall-contact functor over its particles' wall candidates.
template <class F, class Law>
void compute_family_wall_contacts(const ContactContext& c, const RowSet& rows) {
  if (rows.count == 0)
    return;
  compute_wall_contacts<Law>(
      F::wall_label, c.particles, c.walls, c.wall_contacts, c.coefficients, c.dt, rows.count, rows,
      F::wall_contact(c.template table<F>(), c.shape_families, c.walls.elements, c.particles));
}

} // namespace kdem
