#pragma once
// The pair types with superquadrics, as narrow-phase functors of the one pair loop
// (families/pair_loop.hpp):
//   superquadric-superquadric: exact bounding-sphere test, the separation certificate of the
//     last steps (SeparationCertificates, issued by the narrow phase or by the box test), then
//     the oriented-box test (its last separating axis is tried first; skipped for pairs that
//     touched at the last step), survivors compacted
//     with a scan, then the midway-point Newton narrow phase on the compacted list only, so
//     that no lane idles in the expensive kernel for pairs that the cheap tests rule out;
//   sphere-superquadric: the closest-point narrow phase, on the candidate pairs of that type
//     within bounding-sphere reach and without a valid separation certificate.
// Included only by the translation units of kernels/pairs/.
#include "../../shapes/superquadric_contact.hpp"
#include "../../shapes/superquadric_lanes.hpp"
#include "../../shapes/superquadric_properties.hpp"
#include "../families/pair_loop.hpp"

namespace kdem {

// Hertz radius from the surface curvatures at the contact (the "mean curvature" variant of
// Podlozhnyuk et al., Comput. Part. Mech. 4 (2017) 101): R* = 1 / (kappa_i + kappa_j), kept
// within [1/limit, limit] x the R* of the volume-equivalent spheres. Flat faces have
// kappa -> 0 and would make the contact infinitely stiff; sharp corners kappa -> infinity and
// would make it infinitely soft; the limits keep the stiffness, and so the stable time step,
// within a factor sqrt(limit) of the equivalent spheres'.
KOKKOS_INLINE_FUNCTION double curvature_radius(double curvature_i, double curvature_j,
                                               double equivalent_radius, double limit) {
  const double curvature = curvature_i + curvature_j;
  const double lowest = equivalent_radius / limit, highest = equivalent_radius * limit;
  if (!(curvature > 0))
    return highest;
  return math::clamp(1.0 / curvature, lowest, highest);
}

// Separation certificates: a pair that did not touch gets a lower bound G on its gap (the
// narrow phase's NarrowPhaseResult::separation, or the gap of its bounding boxes along the axis
// that separated them, oriented_boxes_gap) with its centre offset and the turned angles of both
// bodies at that step. A point of body i moves by at most |delta x_i| + theta_i r_i (theta_i the
// angle it turned since, r_i its bounding radius; turning a sphere moves none of its surface), so
// while |delta (x_j - x_i)| + theta_i r_i + theta_j r_j < G the pair cannot touch: it skips the box
// test and the narrow phase and keeps its warm start.
// Before looking at the bodies, a certificate is tried against the engine's surface travel S
// (the farthest any surface point moved in a step, summed over the steps): each body's surface
// moved by at most S - S_issued since, so while S - S_issued < G / 2 the pair cannot touch. That
// test reads one number per pair; it holds for long in a bed near rest and expires soon where
// anything moves fast, and then the test above decides (and, when it holds, starts the cheap
// test again with the gap it leaves).
struct SeparationCertificates {
  ParticleViews p;
  ScalarView margin;
  Vec3View offset;
  ScalarView turned_i, turned_j;
  ScalarView expiry;
  double travel = 0;   // S now
  bool enabled = true; // false: none issued, so every pair is tested every step

  SeparationCertificates(const ParticleViews& p_, const PairList& list, double surface_travel,
                         bool enabled_)
      : p(p_), margin(list.separation_margin), offset(list.separation_offset),
        turned_i(list.turned_i_at_separation), turned_j(list.turned_j_at_separation),
        expiry(list.separation_expiry), travel(surface_travel), enabled(enabled_) {}

  // The pair's certificate holds by the surface travel alone (disabled: also those read from a
  // checkpoint are ignored).
  KOKKOS_INLINE_FUNCTION bool unexpired(int k) const { return enabled && travel < expiry(k); }

  // The test against the bodies, for a pair whose certificate has expired (both callers try
  // unexpired first); i_turns, j_turns: turning the body moves its surface (not a sphere's).
  KOKKOS_INLINE_FUNCTION bool still_apart(int k, int i, int j, bool i_turns, bool j_turns) const {
    const double gap = margin(k);
    if (!enabled || !(gap > 0))
      return false;
    const double reach_i = i_turns ? p.radius(i) : 0.0, reach_j = j_turns ? p.radius(j) : 0.0;
    const Vec3 moved = load3(p.position, j) - load3(p.position, i) - load3(offset, k);
    const double reach = norm(moved) + (p.turned_angle(i) - turned_i(k)) * reach_i +
                         (p.turned_angle(j) - turned_j(k)) * reach_j;
    if (!(reach < gap))
      return false;
    expiry(k) = expiry_after(gap - reach);
    return true;
  }
  KOKKOS_INLINE_FUNCTION void issue(int k, int i, int j, double separation) const {
    margin(k) = enabled ? separation : 0.0;
    if (margin(k) > 0) {
      store3(offset, k, load3(p.position, j) - load3(p.position, i));
      turned_i(k) = p.turned_angle(i);
      turned_j(k) = p.turned_angle(j);
      expiry(k) = expiry_after(margin(k));
    } else {
      expiry(k) = 0;
    }
  }
  KOKKOS_INLINE_FUNCTION void revoke(int k) const {
    margin(k) = 0;
    expiry(k) = 0;
  }

private:
  // The surface travel at which a gap G left now may have closed, less its rounding: S + G / 2.
  KOKKOS_INLINE_FUNCTION double expiry_after(double gap) const {
    constexpr double epsilon = 2.220446049250313e-16;
    return travel + 0.5 * gap * (1 - 1e-12) - 4 * epsilon * travel;
  }
};

// Pairs of one family with an implicit surface (superquadric, poly-superquadric) that pass the
// exact bounding-sphere test, hold no valid separation certificate and pass the oriented-box
// test (F::oriented_box), as rows of the pair list; the pairs that fail
// have their contact cleared and their warm start dropped. With `compact` the survivors are
// gathered by a scan, so that no lane of the narrow-phase kernel idles on a rejected pair;
// without, that kernel runs over every candidate and skips the rejected ones. The pass flags
// and survivors are sized once per list build.
template <class F>
PairsToEvaluate implicit_pairs_in_reach(const ParticleViews& p, const typename F::Table& table,
                                        const ShapeFamilies& shapes, const PairList& list,
                                        PairTypeRows& type_rows, double surface_travel,
                                        bool use_certificates, bool box_certificates,
                                        bool compact) {
  const RowSet rows = type_rows.rows;
  const int candidates = rows.count;
  if (int(type_rows.passes.extent(0)) != candidates) {
    type_rows.passes = uninitialized<IndexView>(std::string(F::name) + "_pair_passes", candidates);
    type_rows.survivors =
        uninitialized<IndexView>(std::string(F::name) + "_pairs_left", candidates);
  }
  auto passes = type_rows.passes;
  auto pairs_left = type_rows.survivors;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  auto axis = list.separating_axis;
  auto multiplier = list.midway_multiplier;
  auto overlap = list.overlap;
  const PairSlots slots(list);
  const ContactSlots contact_slots = list.slots();
  const SeparationCertificates certificates(p, list, surface_travel, use_certificates);
  // A pair whose bounding spheres or boxes are apart by `gap`: no contact, no warm start, and
  // the gap as its certificate.
  const auto set_apart = KOKKOS_LAMBDA(int k, int i, int j, double gap) {
    slots.clear(k);
    multiplier(contact_slots.first(k)) = 0;
    if (box_certificates && gap > 0)
      certificates.issue(k, i, j, gap);
    else
      certificates.revoke(k);
  };
  Kokkos::parallel_for(
      std::string("kdem::") + F::name + "_pair_prefilter", RangePolicy(0, candidates),
      KOKKOS_LAMBDA(int m) {
        const int k = rows(m);
        passes(m) = 0;
        if (certificates.unexpired(k))
          return;
        const int i = pair_i(k), j = pair_j(k);
        const double reach = p.radius(i) + p.radius(j);
        const double distance_squared = norm2(load3(p.position, i) - load3(p.position, j));
        if (!(distance_squared < reach * reach)) {
          set_apart(k, i, j, math::sqrt(distance_squared) - reach);
          return;
        }
        if (certificates.still_apart(k, i, j, true, true))
          return;
        // Pairs that touched at the last step almost surely still do: the box test is skipped
        // for them (the book's suggestion, Sect. 2.2.1); the narrow phase decides.
        if (overlap(contact_slots.first(k)) == 0) {
          int hint = axis(k);
          const double box_gap = oriented_boxes_gap(F::oriented_box(table, shapes, p, i),
                                                    F::oriented_box(table, shapes, p, j), hint);
          axis(k) = hint;
          if (box_gap > 0) {
            set_apart(k, i, j, box_gap);
            return;
          }
        }
        passes(m) = 1;
      });
  if (!compact)
    return PairsToEvaluate{rows, passes, true};
  int survivors = 0;
  Kokkos::parallel_scan(
      std::string("kdem::") + F::name + "_pair_compact", RangePolicy(0, candidates),
      KOKKOS_LAMBDA(int m, int& running, bool final) {
        // Branch only in the final pass: the pass flags follow no pattern a predictor learns.
        const int pass = passes(m);
        if (final && pass != 0)
          pairs_left(running) = rows(m);
        running += pass;
      },
      survivors);
  return PairsToEvaluate{RowSet{survivors, false, pairs_left}, passes, false};
}

// What the narrow phases of implicit surfaces share: the warm starts they read and write, the
// tally, the certificates, and how a narrow-phase result becomes the pair's contact.
struct ImplicitPairState {
  ParticleViews p;
  ShapeFamilies shapes;
  ContactSlots slots;
  Vec3View point;
  ScalarView multiplier;
  Vec3View step;
  SeparationCertificates certificates;
  NarrowPhaseControls controls;
  double limit = 2;
  bool extrapolate = true;
  bool use_lanes = true;
  int team_size = 0;

  ImplicitPairState(const ContactContext& c, const SuperquadricContactSettings& settings)
      : p(c.particles), shapes(c.shape_families), slots(c.pairs.slots()),
        point(c.pairs.midway_point), multiplier(c.pairs.midway_multiplier),
        step(c.pairs.midway_step),
        certificates(c.particles, c.pairs, c.surface_travel, settings.separation_certificates),
        controls(settings.newton), limit(settings.curvature_limit),
        extrapolate(settings.extrapolate_start), use_lanes(settings.lanes),
        team_size(settings.team_size) {}

  // The stored point is relative to the midpoint of the two centres, so that it moves with the
  // pair's mean translation (and is the same for both orders of i and j).
  KOKKOS_INLINE_FUNCTION Vec3 centres_midpoint(int i, int j) const {
    return 0.5 * (load3(p.position, i) + load3(p.position, j));
  }

  KOKKOS_INLINE_FUNCTION MidwayState warm_start(int slot, Vec3 midpoint) const {
    return MidwayState{load3(point, slot) + midpoint, multiplier(slot)};
  }

  // Bounding spheres and certificates, for the pair types without a prefilter kernel: apart
  // (contact cleared, warm start dropped), unchanged (a certificate holds) or to be evaluated.
  KOKKOS_INLINE_FUNCTION bool screened(const PairRef& r, bool i_turns, bool j_turns,
                                       PairOutcome& outcome) const {
    if (certificates.unexpired(r.k)) {
      outcome = PairOutcome::unchanged;
      return true;
    }
    const double reach = p.radius(r.i) + p.radius(r.j);
    if (norm2(load3(p.position, r.i) - load3(p.position, r.j)) >= reach * reach) {
      multiplier(slots.first(r.k)) = 0;
      certificates.revoke(r.k);
      outcome = PairOutcome::apart;
      return true;
    }
    if (certificates.still_apart(r.k, r.i, r.j, i_turns, j_turns)) {
      outcome = PairOutcome::unchanged;
      return true;
    }
    return false;
  }

  // Counts the evaluation, keeps its warm start (relative to `midpoint`, the centres' midpoint)
  // and certificate, and gives the contact with the normal of the narrow phase's order (from its
  // second body towards its first).
  KOKKOS_INLINE_FUNCTION PairOutcome record(const PairRef& ref, const NarrowPhaseResult& r,
                                            Vec3 midpoint, double equivalent_radius,
                                            PairContacts<1>& found, NarrowPhaseTally& tally) const {
    tally.add(r);
    const int slot = slots.first(ref.k);
    store3(point, slot, r.state.point - midpoint);
    multiplier(slot) = r.state.multiplier;
    certificates.issue(ref.k, ref.i, ref.j, r.separation);
    if (!r.geometry.touching)
      return PairOutcome::apart;
    found.contact[0].geometry = r.geometry;
    found.contact[0].effective_radius =
        curvature_radius(r.curvature_i, r.curvature_j, equivalent_radius, limit);
    found.count = 1;
    return PairOutcome::touching;
  }
};

// The harmonic Hertz radius of two equivalent radii.
KOKKOS_INLINE_FUNCTION double series_radius(double ri, double rj) {
  return ri * rj / (ri + rj);
}

struct SuperquadricPairState : ImplicitPairState {
  SuperquadricFamily::Table table;

  explicit SuperquadricPairState(const ContactContext& c)
      : ImplicitPairState(c, c.table<SuperquadricFamily>().settings),
        table(c.table<SuperquadricFamily>()) {}

  template <class FamilyI, class FamilyJ>
  KOKKOS_INLINE_FUNCTION double pair_equivalent_radius(int i, int j) const {
    return series_radius(equivalent_radius_of<FamilyI>(i), equivalent_radius_of<FamilyJ>(j));
  }
  template <class F> KOKKOS_INLINE_FUNCTION double equivalent_radius_of(int i) const {
    if constexpr (std::is_same_v<F, SuperquadricFamily>)
      return F::equivalent_radius(table, shapes, p, i);
    else
      return F::equivalent_radius(typename F::Table{}, shapes, p, i);
  }
};

template <> struct NarrowPhase<SuperquadricFamily, SuperquadricFamily> : SuperquadricPairState {
  static constexpr const char* label = "kdem::superquadric_pair_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = 1;

  explicit NarrowPhase(const ContactContext& c) : SuperquadricPairState(c) {}

  PairsToEvaluate select(const ContactContext& c, PairTypeRows& type_rows) const {
    return implicit_pairs_in_reach<SuperquadricFamily>(
        p, table, shapes, c.pairs, type_rows, c.surface_travel,
        table.settings.separation_certificates, table.settings.box_certificates,
        table.settings.compact_candidates);
  }

  // The Newton start is the last midway point moved on by its last step (relative to the
  // midpoint of the centres): in a bed, the point moves smoothly from step to step, and the
  // extrapolation leaves one Newton iteration (within the tolerance) where the last point often
  // needed two (measured in docs/performance.md, section 17). Any start that converges gives the
  // same point (see superquadric_pair_contact), so only the iteration count depends on it.
  struct Start {
    Vec3 midpoint, last;
    MidwayState state;
  };
  KOKKOS_INLINE_FUNCTION Start start_of(const PairRef& r) const {
    const int slot = slots.first(r.k);
    Start s;
    s.midpoint = centres_midpoint(r.i, r.j);
    s.last = load3(point, slot);
    const Vec3 ahead = extrapolate ? load3(step, slot) : Vec3{0, 0, 0};
    s.state = MidwayState{s.last + ahead + s.midpoint, multiplier(slot)};
    return s;
  }

  KOKKOS_INLINE_FUNCTION PairOutcome finish(const PairRef& r, const Start& start,
                                            const NarrowPhaseResult& result, PairContacts<1>& found,
                                            NarrowPhaseTally& tally) const {
    const bool continued = start.state.multiplier > 0 && result.status == 0;
    store3(step, slots.first(r.k),
           continued ? result.state.point - start.midpoint - start.last : Vec3{0, 0, 0});
    return record(r, result, start.midpoint,
                  pair_equivalent_radius<SuperquadricFamily, SuperquadricFamily>(r.i, r.j), found,
                  tally);
  }

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<1>& found,
                                                NarrowPhaseTally& tally) const {
    const Start start = start_of(r);
    const NarrowPhaseResult result = superquadric_pair_contact(
        SuperquadricFamily::pose(table, shapes, p, r.i),
        SuperquadricFamily::pose(table, shapes, p, r.j), start.state, controls);
    return finish(r, start, result, found, tally);
  }

#if KDEM_HOST_LANES
  // Host engines take the pairs four at a time: four pairs of one shape pair, all with a warm
  // start, are solved in lock step (shapes/superquadric_lanes.hpp), and what the lanes leave
  // is solved pair by pair as above. Which pairs share a group depends only on the order of the
  // compacted survivors, the same for every host backend.
  static constexpr int lane_width = lanes::width;

  void operator()(const PairRef* refs, int count, PairContacts<1>* found, PairOutcome* outcomes,
                  NarrowPhaseTally& tally) const {
    if (use_lanes && count == lane_width && lanes_apply(refs)) {
      solve_in_lanes(refs, found, outcomes, tally);
      return;
    }
    for (int q = 0; q < count; ++q)
      outcomes[q] = (*this)(refs[q], found[q], tally);
  }

  bool lanes_apply(const PairRef* refs) const {
    const int shape_i = shapes.template_index(p.shape(refs[0].i));
    const int shape_j = shapes.template_index(p.shape(refs[0].j));
    for (int q = 0; q < lane_width; ++q)
      if (shapes.template_index(p.shape(refs[q].i)) != shape_i ||
          shapes.template_index(p.shape(refs[q].j)) != shape_j ||
          !(multiplier(slots.first(refs[q].k)) > 0))
        return false;
    return true;
  }

  void solve_in_lanes(const PairRef* refs, PairContacts<1>* found, PairOutcome* outcomes,
                      NarrowPhaseTally& tally) const {
    Start starts[lane_width];
    lanes::PairInputs in;
    lanes::Real quaternion_i[4], quaternion_j[4]; // w, x, y, z
    for (int q = 0; q < lane_width; ++q) {
      starts[q] = start_of(refs[q]);
      lanes::set_lane(in, q, load3(p.position, refs[q].i), load3(p.position, refs[q].j),
                      starts[q].state);
      for (int c = 0; c < 4; ++c) {
        quaternion_i[c][q] = p.orientation(refs[q].i, c);
        quaternion_j[c][q] = p.orientation(refs[q].j, c);
      }
    }
    in.i.rotation =
        lanes::rotation_matrix(quaternion_i[0], quaternion_i[1], quaternion_i[2], quaternion_i[3]);
    in.j.rotation =
        lanes::rotation_matrix(quaternion_j[0], quaternion_j[1], quaternion_j[2], quaternion_j[3]);
    const SuperquadricShape& shape_i = table.shapes(shapes.template_index(p.shape(refs[0].i)));
    const SuperquadricShape& shape_j = table.shapes(shapes.template_index(p.shape(refs[0].j)));
    NarrowPhaseResult results[lane_width];
    const int solved = lanes::superquadric_pair_contact(shape_i, shape_j, in, controls, results);
    for (int q = 0; q < lane_width; ++q) {
      if (!(solved & (1 << q)))
        results[q] = superquadric_pair_contact(
            SuperquadricFamily::pose(table, shapes, p, refs[q].i),
            SuperquadricFamily::pose(table, shapes, p, refs[q].j), starts[q].state, controls);
      outcomes[q] = finish(refs[q], starts[q], results[q], found[q], tally);
    }
  }
#endif
};

// The sphere is body a of the narrow phase (the loop turns the normal back when it is j).
template <>
struct NarrowPhase<SphereFamily, SuperquadricFamily> : SuperquadricPairState, EveryRowOfTheType {
  static constexpr const char* label = "kdem::sphere_superquadric_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = 1;
  explicit NarrowPhase(const ContactContext& c) : SuperquadricPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<1>& found,
                                                NarrowPhaseTally& tally) const {
    if (certificates.unexpired(r.k))
      return PairOutcome::unchanged;
    const double reach = p.radius(r.i) + p.radius(r.j);
    if (norm2(load3(p.position, r.i) - load3(p.position, r.j)) >= reach * reach) {
      multiplier(slots.first(r.k)) = 0;
      certificates.revoke(r.k);
      return PairOutcome::apart;
    }
    if (certificates.still_apart(r.k, r.i, r.j, r.flipped, !r.flipped))
      return PairOutcome::unchanged;
    const Vec3 midpoint = centres_midpoint(r.i, r.j);
    const NarrowPhaseResult result = sphere_superquadric_contact(
        load3(p.position, r.a), p.radius(r.a), SuperquadricFamily::pose(table, shapes, p, r.b),
        warm_start(slots.first(r.k), midpoint), controls);
    const double radius = r.flipped
                              ? pair_equivalent_radius<SuperquadricFamily, SphereFamily>(r.i, r.j)
                              : pair_equivalent_radius<SphereFamily, SuperquadricFamily>(r.i, r.j);
    return record(r, result, midpoint, radius, found, tally);
  }
};

} // namespace kdem
