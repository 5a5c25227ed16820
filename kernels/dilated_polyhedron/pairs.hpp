#pragma once
// The pair types with dilated polyhedra, as narrow-phase functors of the one pair loop
// (families/pair_loop.hpp): a sphere against a dilated polyhedron, and two dilated polyhedra.
// After the bodies' bounding spheres, the contacts are the local minima of the core distance
// (shapes/dilated_polyhedron.hpp) found through the cores' sphere trees, in the frame of one
// body; each is a contact point keyed by the features that make it (a sphere's is 0), the
// deepest max_contacts kept, weighted by the book's averaging (DilatedContactSettings). The
// Hertz radius is that of the volume-equivalent spheres in series (book Sect. 4.2.3, Eq. 4.19:
// R* from the equivalent radii, not the dilation radius). A tree walk that overflows its stack
// counts as a failure.
// Included only by the translation units of kernels/pairs/.
#include "../families/pair_loop.hpp"
#include "family.hpp"

namespace kdem {

// Hands the contacts of one piece of body a (found with b's core as body A) on with the pair's
// order: normals from the polyhedron (b) towards the piece, keys (piece, core feature).
template <int K> struct PieceContactSink {
  DeepestContacts<K>& deepest;
  int piece = 0;
  KOKKOS_INLINE_FUNCTION void add(FeatureContact c) const {
    c.normal = -c.normal;
    c.feature_b = c.feature_a;
    c.feature_a = piece;
    deepest.add(c);
  }
};

struct DilatedPairState {
  ParticleViews p;
  ShapeFamilies shapes;
  DilatedPolyhedronFamily::Table table;
  int team_size = 0;

  explicit DilatedPairState(const ContactContext& c)
      : p(c.particles), shapes(c.shape_families), table(c.table<DilatedPolyhedronFamily>()) {}

  KOKKOS_INLINE_FUNCTION bool bounding_spheres_apart(const PairRef& r) const {
    const double reach = p.radius(r.i) + p.radius(r.j);
    return !(norm2(load3(p.position, r.i) - load3(p.position, r.j)) < reach * reach);
  }

  // A sphere (centre, radius; world) as piece `key` of body a against b's core (b's frame:
  // rotation_b, origin_b).
  template <int K>
  KOKKOS_INLINE_FUNCTION void
  sphere_piece(const DeviceCore& core, Vec3 centre, double radius, const Mat3& rotation_b,
               Vec3 origin_b, int key, DeepestContacts<K>& deepest, NarrowPhaseTally& tally) const {
    PieceContactSink<K> sink{deepest, key};
    if (!dilated_sphere_contacts(core, transpose_times(rotation_b, centre - origin_b), radius,
                                 table.settings.slack, sink))
      ++tally.failures;
  }

  // The contacts found in the frame (rotation, origin) turned into the world and into `found`,
  // with their weights; normals from b towards a as found (the caller's frame convention).
  // radius_of(contact): the contact's Hertz radius.
  template <int K, class RadiusOf>
  KOKKOS_INLINE_FUNCTION PairOutcome finish(const DeepestContacts<K>& deepest, const Mat3& rotation,
                                            Vec3 origin, const RadiusOf& radius_of,
                                            PairContacts<K>& found) const {
    if (deepest.count == 0)
      return PairOutcome::apart;
    for (int c = 0; c < deepest.count; ++c) {
      const FeatureContact& f = deepest.contact[c];
      PairContact& contact = found.add();
      contact.geometry =
          ContactGeometry{true, f.overlap, rotation * f.normal, origin + rotation * f.point};
      contact.effective_radius = radius_of(f);
      contact.feature_a = f.feature_a;
      contact.feature_b = f.feature_b;
    }
    deepest.weights(table.settings.averaging,
                    [&](int c, double w) { found.contact[c].weight = w; });
    return PairOutcome::touching;
  }
};

KOKKOS_INLINE_FUNCTION double equivalent_series_radius(double ri, double rj) {
  return ri * rj / (ri + rj);
}

// A sphere (body a) against a dilated polyhedron (body b): the sphere's centre in b's frame.
template <>
struct NarrowPhase<SphereFamily, DilatedPolyhedronFamily> : DilatedPairState, EveryRowOfTheType {
  static constexpr const char* label = "kdem::sphere_dilated_polyhedron_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = pair_contact_points<SphereFamily, DilatedPolyhedronFamily>;

  explicit NarrowPhase(const ContactContext& c) : DilatedPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    if (bounding_spheres_apart(r))
      return PairOutcome::apart;
    ++tally.evaluations;
    const DeviceCore core = DilatedPolyhedronFamily::core(table, shapes, p, r.b);
    const Mat3 rotation = rotation_matrix(load_quat(p.orientation, r.b));
    const Vec3 origin = load3(p.position, r.b);
    DeepestContacts<max_contacts> deepest(table.settings, core.dilation());
    sphere_piece(core, load3(p.position, r.a), p.radius(r.a), rotation, origin, 0, deepest, tally);
    const double radius = equivalent_series_radius(
        p.radius(r.a), DilatedPolyhedronFamily::equivalent_radius(table, shapes, p, r.b));
    return finish(
        deepest, rotation, origin, [&](const FeatureContact&) { return radius; }, found);
  }
};

// Two dilated polyhedra: b's core placed in a's frame.
template <>
struct NarrowPhase<DilatedPolyhedronFamily, DilatedPolyhedronFamily> : DilatedPairState,
                                                                       EveryRowOfTheType {
  static constexpr const char* label = "kdem::dilated_polyhedron_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts =
      pair_contact_points<DilatedPolyhedronFamily, DilatedPolyhedronFamily>;

  explicit NarrowPhase(const ContactContext& c) : DilatedPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    if (bounding_spheres_apart(r))
      return PairOutcome::apart;
    ++tally.evaluations;
    const DeviceCore core_a = DilatedPolyhedronFamily::core(table, shapes, p, r.a);
    const DeviceCore core_b = DilatedPolyhedronFamily::core(table, shapes, p, r.b);
    const Mat3 rotation_a = rotation_matrix(load_quat(p.orientation, r.a));
    const Mat3 rotation_b = rotation_matrix(load_quat(p.orientation, r.b));
    const Vec3 origin = load3(p.position, r.a);
    const RelativePose pose{transpose(rotation_a) * rotation_b,
                            transpose_times(rotation_a, load3(p.position, r.b) - origin)};
    DeepestContacts<max_contacts> deepest(table.settings,
                                          math::min(core_a.dilation(), core_b.dilation()));
    if (!dilated_pair_contacts(core_a, core_b, pose, table.settings.slack, deepest))
      ++tally.failures;
    const double radius =
        equivalent_series_radius(DilatedPolyhedronFamily::equivalent_radius(table, shapes, p, r.a),
                                 DilatedPolyhedronFamily::equivalent_radius(table, shapes, p, r.b));
    return finish(
        deepest, rotation_a, origin, [&](const FeatureContact&) { return radius; }, found);
  }
};

} // namespace kdem
