#pragma once
// The pair types with poly-superquadrics, as narrow-phase functors of the one pair loop
// (families/pair_loop.hpp):
//   poly-superquadric pairs: the superquadrics' prefilter (bounding spheres, separation
//     certificates, oriented boxes of the whole bodies, survivors compacted), then the
//     octant-pair Newton of shapes/poly_superquadric_contact.hpp;
//   superquadric or sphere against a poly-superquadric: bounding spheres and certificates in the
//     kernel, then the same octant search against the superquadric, or the closest point of the
//     octant elements to the sphere's centre.
// The warm start is the midway point (or closest point) of the last step, relative to the
// midpoint of the centres; the octant pair it was accepted in is kept with it, as the octants the
// kept point lies in (in the bodies' current poses: the last step's pair, unless the bodies moved
// the point across an octant plane, and then the pair it lies in now).
// Included only by the translation units of kernels/pairs/.
#include "../../shapes/poly_superquadric_contact.hpp"
#include "../superquadric/pairs.hpp"
#include "family.hpp"

namespace kdem {

struct PolySuperquadricPairState : ImplicitPairState {
  PolySuperquadricFamily::Table table;
  SuperquadricFamily::Table superquadrics;

  explicit PolySuperquadricPairState(const ContactContext& c)
      : ImplicitPairState(c, c.table<PolySuperquadricFamily>().settings),
        table(c.table<PolySuperquadricFamily>()), superquadrics(c.table<SuperquadricFamily>()) {}

  template <class F> KOKKOS_INLINE_FUNCTION double equivalent_radius_of(int i) const {
    if constexpr (std::is_same_v<F, PolySuperquadricFamily>)
      return F::equivalent_radius(table, shapes, p, i);
    else if constexpr (std::is_same_v<F, SuperquadricFamily>)
      return F::equivalent_radius(superquadrics, shapes, p, i);
    else
      return F::equivalent_radius(typename F::Table{}, shapes, p, i);
  }

  // The Hertz radius of the equivalent spheres of the pair's bodies a (of family A) and b.
  template <class A, class B>
  KOKKOS_INLINE_FUNCTION double pair_equivalent_radius(const PairRef& r) const {
    return series_radius(equivalent_radius_of<A>(r.a), equivalent_radius_of<B>(r.b));
  }
};

template <>
struct NarrowPhase<PolySuperquadricFamily, PolySuperquadricFamily> : PolySuperquadricPairState {
  static constexpr const char* label = "kdem::poly_superquadric_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = 1;

  explicit NarrowPhase(const ContactContext& c) : PolySuperquadricPairState(c) {}

  PairsToEvaluate select(const ContactContext& c, PairTypeRows& type_rows) const {
    return implicit_pairs_in_reach<PolySuperquadricFamily>(
        p, table, shapes, c.pairs, type_rows, c.surface_travel,
        table.settings.separation_certificates, table.settings.box_certificates,
        table.settings.compact_candidates);
  }

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<1>& found,
                                                NarrowPhaseTally& tally) const {
    const Vec3 midpoint = centres_midpoint(r.i, r.j);
    const NarrowPhaseResult result =
        piecewise_pair_contact(PolySuperquadricFamily::pose(table, shapes, p, r.i),
                               PolySuperquadricFamily::pose(table, shapes, p, r.j),
                               warm_start(slots.first(r.k), midpoint), controls);
    return record(r, result, midpoint,
                  pair_equivalent_radius<PolySuperquadricFamily, PolySuperquadricFamily>(r), found,
                  tally);
  }
};

// The superquadric is body a of the narrow phase (the loop turns the normal back when it is j).
template <>
struct NarrowPhase<SuperquadricFamily, PolySuperquadricFamily> : PolySuperquadricPairState,
                                                                 EveryRowOfTheType {
  static constexpr const char* label = "kdem::superquadric_poly_superquadric_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = 1;

  explicit NarrowPhase(const ContactContext& c) : PolySuperquadricPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<1>& found,
                                                NarrowPhaseTally& tally) const {
    PairOutcome outcome;
    if (screened(r, true, true, outcome))
      return outcome;
    // The stored warm start belongs to the pair's order (i, j); the search runs in (a, b).
    const Vec3 midpoint = centres_midpoint(r.i, r.j);
    MidwayState start = warm_start(slots.first(r.k), midpoint);
    if (r.flipped && start.multiplier > 0)
      start.multiplier = 1.0 / start.multiplier;
    NarrowPhaseResult result = piecewise_pair_contact(
        SuperquadricFamily::pose(superquadrics, shapes, p, r.a),
        PolySuperquadricFamily::pose(table, shapes, p, r.b), start, controls);
    if (r.flipped && result.state.multiplier > 0)
      result.state.multiplier = 1.0 / result.state.multiplier;
    return record(r, result, midpoint,
                  pair_equivalent_radius<SuperquadricFamily, PolySuperquadricFamily>(r), found,
                  tally);
  }
};

// The sphere is body a of the narrow phase.
template <>
struct NarrowPhase<SphereFamily, PolySuperquadricFamily> : PolySuperquadricPairState,
                                                           EveryRowOfTheType {
  static constexpr const char* label = "kdem::sphere_poly_superquadric_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = 1;

  explicit NarrowPhase(const ContactContext& c) : PolySuperquadricPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<1>& found,
                                                NarrowPhaseTally& tally) const {
    PairOutcome outcome;
    if (screened(r, r.flipped, !r.flipped, outcome))
      return outcome;
    const Vec3 midpoint = centres_midpoint(r.i, r.j);
    const NarrowPhaseResult result = sphere_poly_superquadric_contact(
        load3(p.position, r.a), p.radius(r.a), PolySuperquadricFamily::pose(table, shapes, p, r.b),
        warm_start(slots.first(r.k), midpoint), controls);
    return record(r, result, midpoint,
                  pair_equivalent_radius<SphereFamily, PolySuperquadricFamily>(r), found, tally);
  }
};

} // namespace kdem
