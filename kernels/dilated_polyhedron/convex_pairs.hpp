#pragma once
// The pair types of a superquadric, a poly-superquadric or a clump (body a) with a dilated
// polyhedron (body b), as narrow-phase functors of the one pair loop (families/pair_loop.hpp).
// Each convex piece of a (the body itself, or a clump's element) is placed in b's frame by its
// support point and met with b's core by the generic convex narrow phase
// (shapes/dilated_convex_contact.hpp: GJK distance to each core face near it); a clump's sphere
// elements by the sphere's closed form. Contacts are keyed (piece, core feature), the deepest
// max_contacts kept and weighted as the other dilated pairs (pairs.hpp). The Hertz radius is
// that of the piece's and the polyhedron's volume-equivalent spheres in series. GJK distances
// that did not converge and tree walks that overflowed count as failures, faces crossed by a
// piece (contacts deeper than the dilation) as fallbacks.
// Included only by the translation units of kernels/pairs/.
#include <type_traits>

#include "../../shapes/dilated_convex_contact.hpp"
#include "../clump/family.hpp"
#include "../poly_superquadric/family.hpp"
#include "../superquadric/family.hpp"
#include "pairs.hpp"

namespace kdem {

// GJK's tolerance on a distance, relative to the piece's bounding radius: far below the overlaps
// a contact law sees (1e-4 to 1e-2 of a radius), above the rounding of the support points, and
// small enough that the closest point's tangential error, sqrt(2 R tol) = 1.4e-6 R, leaves the
// normal of an edge or vertex contact within about 1e-5 (tests/engine/test_dilated_convex.cpp).
constexpr double dilated_convex_relative_tolerance = 1e-12;

template <class A> struct ConvexDilatedNarrowPhase : DilatedPairState, EveryRowOfTheType {
  static constexpr bool tallied = true;
  static constexpr int max_contacts = pair_contact_points<A, DilatedPolyhedronFamily>;
  typename A::Table bodies;

  explicit ConvexDilatedNarrowPhase(const ContactContext& c)
      : DilatedPairState(c), bodies(c.table<A>()) {}

  // A piece with a support function, posed in the world (centre, rotation, reach), against the
  // core in b's frame (rotation_b, origin_b).
  template <class Posed, int K>
  KOKKOS_INLINE_FUNCTION void
  convex_piece(const DeviceCore& core, const Posed& piece, double reach, const Mat3& rotation_b,
               Vec3 origin_b, int key, DeepestContacts<K>& deepest, NarrowPhaseTally& tally) const {
    const SupportInFrame<Posed> support{piece, transpose(rotation_b) * piece.rotation,
                                        transpose_times(rotation_b, piece.centre - origin_b)};
    const ConvexDistanceControls controls{dilated_convex_relative_tolerance * reach, 64};
    PieceContactSink<K> sink{deepest, key};
    const DilatedConvexTally t = dilated_convex_contacts(core, support, support.translation, reach,
                                                         controls, table.settings.slack, sink);
    tally.iterations += t.iterations;
    tally.fallbacks += t.deep;
    tally.failures += t.unconverged + (t.tree_walk_complete ? 0 : 1);
  }

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    if (bounding_spheres_apart(r))
      return PairOutcome::apart;
    ++tally.evaluations;
    const DeviceCore core = DilatedPolyhedronFamily::core(table, shapes, p, r.b);
    const Mat3 rotation_b = rotation_matrix(load_quat(p.orientation, r.b));
    const Vec3 origin_b = load3(p.position, r.b);
    const double radius_b = DilatedPolyhedronFamily::equivalent_radius(table, shapes, p, r.b);
    DeepestContacts<max_contacts> deepest(table.settings, core.dilation());
    if constexpr (std::is_same_v<A, ClumpFamily>) {
      const Mat3 rotation_a = rotation_matrix(load_quat(p.orientation, r.a));
      const int template_a = shapes.template_index(p.shape(r.a));
      const int elements = bodies.elements.size(template_a);
      for (int e = 0; e < elements; ++e) {
        const PlacedElement element = A::element(bodies, shapes, p, r.a, rotation_a, e);
        if (norm(element.body.centre - origin_b) >= element.bounding_radius + p.radius(r.b))
          continue;
        if (element.sphere)
          sphere_piece(core, element.body.centre, element.body.shape.a, rotation_b, origin_b, e,
                       deepest, tally);
        else
          convex_piece(core, element.body, element.bounding_radius, rotation_b, origin_b, e,
                       deepest, tally);
      }
      return finish(
          deepest, rotation_b, origin_b,
          [&](const FeatureContact& c) {
            return equivalent_series_radius(
                bodies.elements(template_a, c.feature_a).equivalent_radius, radius_b);
          },
          found);
    } else {
      const auto body = A::pose(bodies, shapes, p, r.a);
      convex_piece(core, body, body.reach(), rotation_b, origin_b, 0, deepest, tally);
      const double radius =
          equivalent_series_radius(A::equivalent_radius(bodies, shapes, p, r.a), radius_b);
      return finish(
          deepest, rotation_b, origin_b, [&](const FeatureContact&) { return radius; }, found);
    }
  }
};

template <>
struct NarrowPhase<SuperquadricFamily, DilatedPolyhedronFamily>
    : ConvexDilatedNarrowPhase<SuperquadricFamily> {
  static constexpr const char* label = "kdem::superquadric_dilated_polyhedron_forces";
  using ConvexDilatedNarrowPhase::ConvexDilatedNarrowPhase;
};

template <>
struct NarrowPhase<PolySuperquadricFamily, DilatedPolyhedronFamily>
    : ConvexDilatedNarrowPhase<PolySuperquadricFamily> {
  static constexpr const char* label = "kdem::poly_superquadric_dilated_polyhedron_forces";
  using ConvexDilatedNarrowPhase::ConvexDilatedNarrowPhase;
};

template <>
struct NarrowPhase<ClumpFamily, DilatedPolyhedronFamily> : ConvexDilatedNarrowPhase<ClumpFamily> {
  static constexpr const char* label = "kdem::clump_dilated_polyhedron_forces";
  using ConvexDilatedNarrowPhase::ConvexDilatedNarrowPhase;
};

} // namespace kdem
