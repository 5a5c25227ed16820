#pragma once
// The pair types with clumps, as narrow-phase functors of the one pair loop
// (families/pair_loop.hpp): sphere, superquadric, poly-superquadric or clump against a clump.
// After the bodies' bounding spheres and the pair's separation certificate, every element of
// one body (a convex body is its own one element) is tested against every element of the clump
// by their bounding spheres, and the pairs within reach solved (shapes/clump.hpp). Each touching
// element pair is a contact point keyed by its two elements; its Newton warm start lives in the
// slot of its contact, found again by the key, so an element pair that separates starts cold
// when it touches again. Seam duplicates are weighted (SeamSettings). The smallest gap bound over
// the element pairs certifies a pair that does not touch.
// Included only by the translation units of kernels/pairs/.
#include <type_traits>

#include "../poly_superquadric/pairs.hpp"
#include "family.hpp"

namespace kdem {

struct ClumpPairState : ImplicitPairState {
  ClumpFamily::Table clumps;
  SuperquadricFamily::Table superquadrics;
  PolySuperquadricFamily::Table polys;
  IndexView feature_i, feature_j;
  SeamSettings seam;

  explicit ClumpPairState(const ContactContext& c)
      : ImplicitPairState(c, c.table<ClumpFamily>().settings.newton),
        clumps(c.table<ClumpFamily>()), superquadrics(c.table<SuperquadricFamily>()),
        polys(c.table<PolySuperquadricFamily>()), feature_i(c.pairs.feature_i),
        feature_j(c.pairs.feature_j), seam(c.table<ClumpFamily>().settings.seam) {}

  // A convex body (not a clump) as the one piece of its contacts, with its equivalent radius.
  template <class A> KOKKOS_INLINE_FUNCTION auto whole_body(int a) const {
    if constexpr (std::is_same_v<A, SphereFamily>)
      return SpherePiece{load3(p.position, a), p.radius(a)};
    else if constexpr (std::is_same_v<A, SuperquadricFamily>)
      return A::pose(superquadrics, shapes, p, a);
    else
      return A::pose(polys, shapes, p, a);
  }
  template <class A> KOKKOS_INLINE_FUNCTION double whole_equivalent_radius(int a) const {
    if constexpr (std::is_same_v<A, SphereFamily>)
      return p.radius(a);
    else if constexpr (std::is_same_v<A, SuperquadricFamily>)
      return A::equivalent_radius(superquadrics, shapes, p, a);
    else
      return A::equivalent_radius(polys, shapes, p, a);
  }

  // The element keys (of i, of j) of the pair's slots at the last step, read once per pair (the
  // element pairs look them up many times); plain arrays, set only as far as there are slots.
  struct SlotKeys {
    int first = 0, count = 0;
    int on_i[clump_max_elements], on_j[clump_max_elements];
  };
  KOKKOS_INLINE_FUNCTION SlotKeys slot_keys(int k) const {
    SlotKeys keys;
    keys.first = slots.first(k);
    const int end = slots.end(k);
    for (int s = keys.first; s < end && keys.count < clump_max_elements; ++s, ++keys.count) {
      keys.on_i[keys.count] = feature_i(s);
      keys.on_j[keys.count] = feature_j(s);
    }
    return keys;
  }

  // The warm start the slot of the element pair `key` kept at the last step; none where no slot
  // holds it. The narrow phase writes the slots only when it has found every contact (finish).
  KOKKOS_INLINE_FUNCTION MidwayState kept_start(const SlotKeys& keys, const FeaturePair& key,
                                                Vec3 midpoint) const {
    for (int m = 0; m < keys.count; ++m)
      if (keys.on_i[m] == key.on_i && keys.on_j[m] == key.on_j) {
        const int s = keys.first + m;
        return MidwayState{load3(point, s) + midpoint, multiplier(s)};
      }
    return MidwayState{};
  }

  // What one pair's element loop gathers (plain arrays, set only as far as they are used: see
  // PairContacts).
  template <int K> struct Gathered {
    PairContacts<K>& found;
    double start_point[K][3]; // warm starts of the contacts, order (i, j), absolute points
    double start_multiplier[K];
    double size[K];     // the smaller equivalent radius of each contact's two pieces
    double gap = 1e300; // smallest gap bound over the element pairs that do not touch

    KOKKOS_INLINE_FUNCTION explicit Gathered(PairContacts<K>& f) : found(f) {}
  };

  // One piece of body a (feature_a; centre and reach of its bounding sphere) against element
  // feature_b of the clump b (its template, and b's position and axes): placed only when the
  // bounding spheres meet, as most element pairs of two clumps do not.
  template <int K, class PieceA>
  KOKKOS_INLINE_FUNCTION void
  element_pair(const PairRef& r, const PieceA& piece_a, int feature_a, Vec3 centre_a,
               double reach_a, double equivalent_a, const ClumpElementTemplate& template_b,
               Vec3 position_b, const Mat3& rotation_b, int feature_b, const SlotKeys& keys,
               Vec3 midpoint, Gathered<K>& g, NarrowPhaseTally& tally) const {
    const double reach = reach_a + template_b.bounding_radius;
    const double distance = norm(position_b + rotation_b * template_b.centre - centre_a);
    if (!(distance < reach)) {
      g.gap = math::min(g.gap, distance - reach);
      return;
    }
    const PlacedElement element_b = place_element(template_b, position_b, rotation_b);
    using clump_contact::reversed;
    const FeaturePair key =
        r.flipped ? FeaturePair{feature_b, feature_a} : FeaturePair{feature_a, feature_b};
    const MidwayState stored = kept_start(keys, key, midpoint);
    const NarrowPhaseResult result =
        piece_contact(piece_a, element_b, r.flipped ? reversed(stored) : stored, controls);
    if (iterative_pair(piece_a, element_b))
      tally.add(result);
    if (!result.geometry.touching) {
      g.gap = math::min(g.gap, result.separation);
      return;
    }
    g.gap = 0;
    if (g.found.count == K) {
      ++tally.failures; // more contacts than a pair keeps: counted as missed
      return;
    }
    const int c = g.found.count;
    PairContact& contact = g.found.add();
    contact.geometry = result.geometry;
    contact.effective_radius =
        curvature_radius(result.curvature_i, result.curvature_j,
                         series_radius(equivalent_a, element_b.equivalent_radius), limit);
    contact.feature_a = feature_a;
    contact.feature_b = feature_b;
    const MidwayState kept = r.flipped ? reversed(result.state) : result.state;
    for (int d = 0; d < 3; ++d)
      g.start_point[c][d] = kept.point[d];
    g.start_multiplier[c] = kept.multiplier;
    g.size[c] = math::min(equivalent_a, element_b.equivalent_radius);
  }

  // Weights the seam duplicates, keeps the contacts' warm starts in their slots and the gap as
  // the pair's certificate.
  template <int K>
  KOKKOS_INLINE_FUNCTION PairOutcome finish(const PairRef& r, Gathered<K>& g, Vec3 midpoint) const {
    PairContacts<K>& found = g.found;
    seam_weights(
        found.count, [&](int c) -> const ContactGeometry& { return found.contact[c].geometry; },
        [&](int c) { return g.size[c]; }, seam,
        [&](int c, double w) { found.contact[c].weight = w; });
    const int first = slots.first(r.k), capacity = slots.end(r.k) - first;
    for (int c = 0; c < found.count && c < capacity; ++c) {
      const Vec3 start{g.start_point[c][0], g.start_point[c][1], g.start_point[c][2]};
      store3(point, first + c, start - midpoint);
      multiplier(first + c) = g.start_multiplier[c];
    }
    certificates.issue(r.k, r.i, r.j, found.count > 0 ? 0.0 : g.gap);
    return found.count > 0 ? PairOutcome::touching : PairOutcome::apart;
  }
};

// Body a (family A: a convex body or a clump) against the clump b.
template <class A> struct ClumpNarrowPhaseOf : ClumpPairState, EveryRowOfTheType {
  static constexpr bool tallied = true;
  static constexpr int max_contacts = pair_contact_points<A, ClumpFamily>;

  explicit ClumpNarrowPhaseOf(const ContactContext& c) : ClumpPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    PairOutcome outcome;
    const bool a_turns = A::surface_turns;
    if (screened(r, r.flipped || a_turns, !r.flipped || a_turns, outcome))
      return outcome;
    const Vec3 midpoint = centres_midpoint(r.i, r.j);
    const SlotKeys keys = slot_keys(r.k);
    Gathered<max_contacts> g(found);
    const Mat3 rotation_b = rotation_matrix(load_quat(p.orientation, r.b));
    const Vec3 position_b = load3(p.position, r.b);
    const int template_b = shapes.template_index(p.shape(r.b));
    const int elements_b = clumps.elements.size(template_b);
    if constexpr (std::is_same_v<A, ClumpFamily>) {
      const Mat3 rotation_a = rotation_matrix(load_quat(p.orientation, r.a));
      const int elements_a = ClumpFamily::element_count(clumps, shapes, p, r.a);
      for (int e = 0; e < elements_a; ++e) {
        const PlacedElement element_a = ClumpFamily::element(clumps, shapes, p, r.a, rotation_a, e);
        for (int f = 0; f < elements_b; ++f)
          element_pair(r, element_a, e, element_a.body.centre, element_a.bounding_radius,
                       element_a.equivalent_radius, clumps.elements(template_b, f), position_b,
                       rotation_b, f, keys, midpoint, g, tally);
      }
    } else {
      const auto body_a = whole_body<A>(r.a);
      const Vec3 centre_a = load3(p.position, r.a);
      const double equivalent_a = whole_equivalent_radius<A>(r.a);
      for (int f = 0; f < elements_b; ++f)
        element_pair(r, body_a, 0, centre_a, p.radius(r.a), equivalent_a,
                     clumps.elements(template_b, f), position_b, rotation_b, f, keys, midpoint, g,
                     tally);
    }
    return finish(r, g, midpoint);
  }
};

template <> struct NarrowPhase<SphereFamily, ClumpFamily> : ClumpNarrowPhaseOf<SphereFamily> {
  static constexpr const char* label = "kdem::sphere_clump_forces";
  using ClumpNarrowPhaseOf::ClumpNarrowPhaseOf;
};
template <>
struct NarrowPhase<SuperquadricFamily, ClumpFamily> : ClumpNarrowPhaseOf<SuperquadricFamily> {
  static constexpr const char* label = "kdem::superquadric_clump_forces";
  using ClumpNarrowPhaseOf::ClumpNarrowPhaseOf;
};
template <>
struct NarrowPhase<PolySuperquadricFamily, ClumpFamily>
    : ClumpNarrowPhaseOf<PolySuperquadricFamily> {
  static constexpr const char* label = "kdem::poly_superquadric_clump_forces";
  using ClumpNarrowPhaseOf::ClumpNarrowPhaseOf;
};
template <> struct NarrowPhase<ClumpFamily, ClumpFamily> : ClumpNarrowPhaseOf<ClumpFamily> {
  static constexpr const char* label = "kdem::clump_forces";
  using ClumpNarrowPhaseOf::ClumpNarrowPhaseOf;
};

} // namespace kdem
