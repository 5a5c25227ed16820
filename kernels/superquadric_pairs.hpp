#pragma once
// Contact forces of pairs with superquadrics, one statically typed kernel per pair type:
//   superquadric-superquadric: exact bounding-sphere test, the separation certificate of the
//     last steps (SeparationCertificates), then the oriented-box test (its
//     last separating axis is tried first; skipped for pairs that touched at the last step),
//     survivors compacted with a scan, then the
//     midway-point Newton narrow phase on the compacted list only, so that no lane idles in
//     the expensive kernel for pairs that the cheap tests rule out;
//   sphere-superquadric: the closest-point narrow phase, on the candidate pairs of that type
//     within bounding-sphere reach and without a valid separation certificate.
// Forces are stored per pair like sphere pairs and summed per particle by sum_forces.
#include "../shapes/superquadric_contact.hpp"
#include "../shapes/superquadric_properties.hpp"
#include "launch.hpp"
#include "pair_forces.hpp"
#include "shape_table.hpp"

namespace kdem {

// Newton controls and the contact-radius rule of the superquadric kernels.
struct SuperquadricContactSettings {
  NarrowPhaseControls newton;
  double curvature_limit = 2;
  bool separation_certificates = true; // see SeparationCertificates
  bool compact_candidates = true;      // see superquadric_pairs_in_reach
  int team_size = 0;                   // of the narrow-phase kernel, see reduce_over_items
};

// Sums over narrow-phase evaluations, reduced over a kernel's pairs rather than counted with
// atomics: on a GPU thousands of lanes adding to one address would serialise. Integers, so the
// sums do not depend on the order of the reduction.
struct NarrowPhaseTally {
  std::int64_t evaluations = 0, iterations = 0, fallbacks = 0, failures = 0;

  KOKKOS_INLINE_FUNCTION void add(const NarrowPhaseResult& r) {
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

// Running totals of the superquadric narrow-phase evaluations, kept in the engine's memory: each
// kernel reduces its own tally into `kernel_tally` (no host wait) and a one-lane kernel adds it.
struct NarrowPhaseCounters {
  DeviceView<NarrowPhaseTally> totals;
  DeviceView<NarrowPhaseTally> kernel_tally;
  NarrowPhaseCounters() : totals("narrow_phase_totals"), kernel_tally("narrow_phase_tally") {}

  Kokkos::Sum<NarrowPhaseTally, MemSpace> reducer() const {
    return Kokkos::Sum<NarrowPhaseTally, MemSpace>(kernel_tally);
  }
  void add_kernel_tally() const {
    auto sum = totals;
    auto part = kernel_tally;
    Kokkos::parallel_for(
        "kdem::narrow_phase_tally", RangePolicy(0, 1), KOKKOS_LAMBDA(int) { sum() += part(); });
  }
};

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

KOKKOS_INLINE_FUNCTION double equivalent_radius_of(const ShapeTable& shapes, const ParticleViews& p,
                                                   int i) {
  const int shape = p.shape(i);
  return is_superquadric(shape) ? shapes.equivalent_radius(superquadric_template(shape))
                                : p.radius(i);
}

KOKKOS_INLINE_FUNCTION double pair_equivalent_radius(const ShapeTable& shapes,
                                                     const ParticleViews& p, int i, int j) {
  const double ri = equivalent_radius_of(shapes, p, i), rj = equivalent_radius_of(shapes, p, j);
  return ri * rj / (ri + rj);
}

// Separation certificates: a pair that did not touch gets a lower bound G on its gap
// (NarrowPhaseResult::separation) with its centre offset and the turned angles of both bodies at
// that step. A point of body i moves by at most |delta x_i| + theta_i r_i (theta_i the angle it
// turned since, r_i its bounding radius; turning a sphere moves none of its surface), so while
// |delta (x_j - x_i)| + theta_i r_i + theta_j r_j < G the pair cannot touch: it skips the box
// test and the narrow phase and keeps its warm start.
struct SeparationCertificates {
  ParticleViews p;
  ScalarView margin;
  Vec3View offset;
  ScalarView turned_i, turned_j;
  bool enabled = true; // false: none issued, so every pair is tested every step

  SeparationCertificates(const ParticleViews& p_, const PairList& list, bool enabled_)
      : p(p_), margin(list.separation_margin), offset(list.separation_offset),
        turned_i(list.turned_i_at_separation), turned_j(list.turned_j_at_separation),
        enabled(enabled_) {}

  KOKKOS_INLINE_FUNCTION double turning_reach(int i) const {
    return is_superquadric(p.shape(i)) ? p.radius(i) : 0.0;
  }
  KOKKOS_INLINE_FUNCTION bool still_apart(int k, int i, int j) const {
    const double gap = margin(k);
    if (!enabled || !(gap > 0)) // disabled: also those read from a checkpoint are ignored
      return false;
    const Vec3 moved = load3(p.position, j) - load3(p.position, i) - load3(offset, k);
    const double reach = norm(moved) + (p.turned_angle(i) - turned_i(k)) * turning_reach(i) +
                         (p.turned_angle(j) - turned_j(k)) * turning_reach(j);
    return reach < gap;
  }
  KOKKOS_INLINE_FUNCTION void issue(int k, int i, int j, double separation) const {
    margin(k) = enabled ? separation : 0.0;
    if (margin(k) > 0) {
      store3(offset, k, load3(p.position, j) - load3(p.position, i));
      turned_i(k) = p.turned_angle(i);
      turned_j(k) = p.turned_angle(j);
    }
  }
  KOKKOS_INLINE_FUNCTION void revoke(int k) const { margin(k) = 0; }
};

// The superquadric pairs the narrow phase evaluates this step: rows(s) for s < count, except
// those with passes(s) == 0 when the list was not compacted.
struct PairsToEvaluate {
  IndexView rows;
  IndexView passes;
  int count = 0;
  bool compacted = true;

  KOKKOS_INLINE_FUNCTION bool skipped(int s) const { return !compacted && passes(s) == 0; }
};

// Superquadric pairs that pass the exact bounding-sphere test, hold no valid separation
// certificate and pass the oriented-box test, as rows of the pair list; the pairs that fail
// have their contact cleared and their warm start dropped. With `compact` the survivors are
// gathered by a scan, so that no lane of the narrow-phase kernel idles on a rejected pair;
// without, that kernel runs over every candidate and skips the rejected ones.
inline PairsToEvaluate superquadric_pairs_in_reach(const ParticleViews& p, const ShapeTable& shapes,
                                                   PairList& list, const FamilyLists& families,
                                                   bool use_certificates, bool compact) {
  const int candidates = families.superquadric_pair_count;
  auto passes = families.superquadric_pair_passes;
  auto pairs_left = families.superquadric_pairs_left;
  auto rows = families.superquadric_pairs;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  auto axis = list.separating_axis;
  auto multiplier = list.midway_multiplier;
  auto overlap = list.overlap;
  const PairSlots slots(list);
  const SeparationCertificates certificates(p, list, use_certificates);
  Kokkos::parallel_for(
      "kdem::superquadric_pair_prefilter", RangePolicy(0, candidates), KOKKOS_LAMBDA(int m) {
        const int k = rows(m), i = pair_i(k), j = pair_j(k);
        const double reach = p.radius(i) + p.radius(j);
        bool near = norm2(load3(p.position, i) - load3(p.position, j)) < reach * reach;
        if (near && certificates.still_apart(k, i, j)) {
          passes(m) = 0;
          return;
        }
        // Pairs that touched at the last step almost surely still do: the box test is skipped
        // for them (the book's suggestion, Sect. 2.2.1); the narrow phase decides.
        if (near && overlap(k) == 0) {
          int hint = axis(k);
          near = bounding_boxes_overlap(posed_particle(shapes, p, i), posed_particle(shapes, p, j),
                                        hint);
          axis(k) = hint;
        }
        passes(m) = near ? 1 : 0;
        if (!near) {
          slots.clear(k);
          multiplier(k) = 0;
          certificates.revoke(k);
        }
      });
  if (!compact)
    return PairsToEvaluate{rows, passes, candidates, false};
  int survivors = 0;
  Kokkos::parallel_scan(
      "kdem::superquadric_pair_compact", RangePolicy(0, candidates),
      KOKKOS_LAMBDA(int m, int& running, bool final) {
        if (passes(m) == 0)
          return;
        if (final)
          pairs_left(running) = rows(m);
        ++running;
      },
      survivors);
  return PairsToEvaluate{pairs_left, passes, survivors, true};
}

// What the superquadric pair kernels share: the warm starts they read and write, the tally,
// and how a narrow-phase result becomes the pair's force.
template <bool RollingResistance> struct SuperquadricPairKernel {
  ParticleViews p;
  ShapeTable shapes;
  PairSlots slots;
  Vec3View point;
  ScalarView multiplier;
  SeparationCertificates certificates;
  CoefficientTable table;
  NarrowPhaseControls controls;
  double limit = 2;
  double dt = 0;

  SuperquadricPairKernel(const ParticleViews& p_, const ShapeTable& shapes_, const PairList& list,
                         const CoefficientTable& table_,
                         const SuperquadricContactSettings& settings, double dt_)
      : p(p_), shapes(shapes_), slots(list), point(list.midway_point),
        multiplier(list.midway_multiplier),
        certificates(p_, list, settings.separation_certificates), table(table_),
        controls(settings.newton), limit(settings.curvature_limit), dt(dt_) {}

  // The stored point is relative to the midpoint of the two centres, so that it moves with the
  // pair's mean translation (and is the same for both orders of i and j).
  KOKKOS_INLINE_FUNCTION Vec3 centres_midpoint(int i, int j) const {
    return 0.5 * (load3(p.position, i) + load3(p.position, j));
  }

  KOKKOS_INLINE_FUNCTION MidwayState warm_start(int k, int i, int j) const {
    MidwayState previous;
    previous.point = load3(point, k) + centres_midpoint(i, j);
    previous.multiplier = multiplier(k);
    return previous;
  }

  // Counts the evaluation, keeps its warm start and applies (or clears) the contact; `normal`
  // is the result's normal turned to point from j towards i of the stored pair.
  KOKKOS_INLINE_FUNCTION void record(int k, int i, int j, const NarrowPhaseResult& r,
                                     double normal_sign, NarrowPhaseTally& tally) const {
    tally.add(r);
    store3(point, k, r.state.point - centres_midpoint(i, j));
    multiplier(k) = r.state.multiplier;
    certificates.issue(k, i, j, r.separation);
    if (!r.geometry.touching) {
      slots.clear(k);
      return;
    }
    ContactGeometry geometry = r.geometry;
    geometry.normal = normal_sign * geometry.normal;
    const double radius = curvature_radius(r.curvature_i, r.curvature_j,
                                           pair_equivalent_radius(shapes, p, i, j), limit);
    slots.template apply<RollingResistance>(k, p, i, j, geometry, radius,
                                            table(p.material(i), p.material(j)), dt);
  }
};

template <bool RollingResistance>
void compute_superquadric_pair_forces(const ParticleViews& p, const ShapeTable& shapes,
                                      PairList& list, const FamilyLists& families,
                                      const CoefficientTable& table,
                                      const SuperquadricContactSettings& settings,
                                      const NarrowPhaseCounters& counters, double dt) {
  if (families.superquadric_pair_count == 0)
    return;
  const PairsToEvaluate todo = superquadric_pairs_in_reach(
      p, shapes, list, families, settings.separation_certificates, settings.compact_candidates);
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  const SuperquadricPairKernel<RollingResistance> kernel(p, shapes, list, table, settings, dt);
  reduce_over_items<NarrowPhaseTally>(
      "kdem::superquadric_pair_forces", todo.count, settings.team_size,
      KOKKOS_LAMBDA(int s, NarrowPhaseTally& tally) {
        if (todo.skipped(s))
          return;
        const int k = todo.rows(s), i = pair_i(k), j = pair_j(k);
        const NarrowPhaseResult r = superquadric_pair_contact(
            posed_particle(kernel.shapes, kernel.p, i), posed_particle(kernel.shapes, kernel.p, j),
            kernel.warm_start(k, i, j), kernel.controls);
        kernel.record(k, i, j, r, 1.0, tally);
      },
      counters.reducer());
  counters.add_kernel_tally();
}

// The sphere is body i of the narrow phase; pairs stored with the superquadric first get the
// geometry's normal reversed, so that it points from j towards i of the stored pair.
template <bool RollingResistance>
void compute_sphere_superquadric_forces(const ParticleViews& p, const ShapeTable& shapes,
                                        PairList& list, const FamilyLists& families,
                                        const CoefficientTable& table,
                                        const SuperquadricContactSettings& settings,
                                        const NarrowPhaseCounters& counters, double dt) {
  if (families.mixed_pair_count == 0)
    return;
  auto rows = families.mixed_pairs;
  auto pair_i = list.pair_i, pair_j = list.pair_j;
  const SuperquadricPairKernel<RollingResistance> kernel(p, shapes, list, table, settings, dt);
  reduce_over_items<NarrowPhaseTally>(
      "kdem::sphere_superquadric_forces", families.mixed_pair_count, settings.team_size,
      KOKKOS_LAMBDA(int m, NarrowPhaseTally& tally) {
        const int k = rows(m), i = pair_i(k), j = pair_j(k);
        const bool sphere_first = !is_superquadric(p.shape(i));
        const int sphere = sphere_first ? i : j, body = sphere_first ? j : i;
        const double reach = p.radius(i) + p.radius(j);
        if (norm2(load3(p.position, i) - load3(p.position, j)) >= reach * reach) {
          kernel.slots.clear(k);
          kernel.multiplier(k) = 0;
          kernel.certificates.revoke(k);
          return;
        }
        if (kernel.certificates.still_apart(k, i, j))
          return;
        const NarrowPhaseResult r = sphere_superquadric_contact(
            load3(p.position, sphere), p.radius(sphere), posed_particle(shapes, p, body),
            kernel.warm_start(k, i, j), kernel.controls);
        kernel.record(k, i, j, r, sphere_first ? 1.0 : -1.0, tally);
      },
      counters.reducer());
  counters.add_kernel_tally();
}

} // namespace kdem
