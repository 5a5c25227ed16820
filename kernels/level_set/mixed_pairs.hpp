#pragma once
// The pair types of a level-set body (always body b: its family is the last) with the families
// that have an exact surface of their own: superquadrics, poly-superquadrics, clumps and dilated
// polyhedra. Both ways, in b's frame:
// - b's surface points inside body a, each measured against a's exact surface: the closest point
//   of a superquadric or poly-superquadric (the sphere narrow phase's, for a point), of a dilated
//   polyhedron's core within its dilation (the local minima of the core distance); overlap the
//   point's depth, keys (piece, 1 + point index);
// - a's features in b's grid, which find what lies between b's points (a corner of a pressing
//   into a face of b): the deepest point of each convex piece of a, found by its support point
//   against b's outward normal (x <- support(-grad phi_b(x)), the deepest of the iterates kept); a
//   dilated core's vertices and samples of its convex edges, each the centre of a sphere of the
//   dilation radius; keys (piece or core feature, 0).
// A clump's sphere element is a sphere against b (sphere_level_set_contacts), keyed by element.
// The contacts go into patches (patches.hpp), as for two level-set bodies; the Hertz radius is
// that of the piece's and b's volume-equivalent spheres in series. A closest point that does not
// converge counts as a failure. Included only by the translation units of kernels/pairs/.
#include <type_traits>

#include "../../shapes/poly_superquadric_contact.hpp"
#include "../clump/family.hpp"
#include "../poly_superquadric/family.hpp"
#include "../superquadric/family.hpp"
#include "pairs.hpp"

namespace kdem {

namespace level_set {

// The depth of point x (a's frame of reference, radius 0) inside a convex piece: the closest
// point of its surface (a failed result where Newton does not converge).
KOKKOS_INLINE_FUNCTION NarrowPhaseResult point_depth(Vec3 x, const PosedSuperquadric& piece,
                                                     const NarrowPhaseControls& controls) {
  return sphere_superquadric_contact(x, 0.0, piece, MidwayState{}, controls);
}
KOKKOS_INLINE_FUNCTION NarrowPhaseResult point_depth(Vec3 x, const PosedPolySuperquadric& piece,
                                                     const NarrowPhaseControls& controls) {
  return sphere_poly_superquadric_contact(x, 0.0, piece, MidwayState{}, controls);
}

} // namespace level_set

// Hands on contacts with the key of the piece of body a they were found with.
template <int K> struct PieceKeySink {
  LevelSetPatches<K>& patches;
  int piece = 0;
  KOKKOS_INLINE_FUNCTION void add(FeatureContact c) const {
    c.feature_a = piece;
    patches.add(c);
  }
};

// What the mixed narrow phases share: b's body and pose, and the patches' linking.
struct MixedLevelSetState : LevelSetPairState {
  explicit MixedLevelSetState(const ContactContext& c) : LevelSetPairState(c) {}

  // The surface points of b (its frame) within `reach` of a piece's centre that inside(x, c)
  // finds inside it, with their keys (piece, 1 + point index).
  template <class Inside, int K>
  KOKKOS_INLINE_FUNCTION void points_in_piece(const LevelSetBodyView& b, Vec3 centre, double reach,
                                              int piece, const Inside& inside,
                                              LevelSetPatches<K>& patches) const {
    b.for_points_in_ball_box(centre, reach, [&](int q) {
      const Vec3 x = b.points[q];
      if (!(norm2(x - centre) < reach * reach))
        return;
      FeatureContact c;
      if (!inside(x, c))
        return;
      c.feature_a = piece;
      c.feature_b = 1 + q;
      patches.add(c);
    });
  }

  // A superquadric or poly-superquadric piece, posed in b's frame: b's points inside it, and its
  // deepest point in b's grid.
  template <class Posed, int K>
  KOKKOS_INLINE_FUNCTION void
  convex_piece(const LevelSetBodyView& b, const Posed& piece, NarrowPhaseControls controls, int key,
               LevelSetPatches<K>& patches, NarrowPhaseTally& tally) const {
    controls.length = piece.smallest_length();
    controls.use_fallback = false;
    points_in_piece(
        b, piece.centre, piece.reach(), key,
        [&](Vec3 x, FeatureContact& c) {
          if (!(piece.value(x) < 0))
            return false;
          const NarrowPhaseResult r = level_set::point_depth(x, piece, controls);
          tally.iterations += r.iterations;
          if (r.status == 2) {
            ++tally.failures;
            return false;
          }
          if (!r.geometry.touching)
            return false;
          c.overlap = r.geometry.overlap;
          c.normal = -1.0 * r.geometry.normal; // the piece's outward normal, turned from b to a
          c.point = r.geometry.point;
          return true;
        },
        patches);
    const auto support = [&](Vec3 d) {
      return piece.centre +
             piece.rotation * piece.support_local(transpose_times(piece.rotation, d));
    };
    FeatureContact c;
    const double from_origin = norm(piece.centre);
    const Vec3 towards_b = from_origin > 0 ? (-1.0 / from_origin) * piece.centre : Vec3{0, 0, 1};
    if (level_set::deepest_support_point(b, support, towards_b, c)) {
      c.feature_a = key;
      c.feature_b = 0;
      patches.add(c);
    }
  }

  // A sphere piece (centre and radius in b's frame), as a sphere against b with the piece's key.
  template <int K>
  KOKKOS_INLINE_FUNCTION void sphere_piece(const LevelSetBodyView& b, Vec3 centre, double radius,
                                           int key, LevelSetPatches<K>& patches) const {
    PieceKeySink<K> sink{patches, key};
    sphere_level_set_contacts(b, centre, radius, sink);
  }

  // The pose of a placed piece (world) in b's frame.
  template <class Posed>
  KOKKOS_INLINE_FUNCTION static Posed in_frame(Posed piece, const Mat3& rotation_b, Vec3 origin_b) {
    piece.centre = transpose_times(rotation_b, piece.centre - origin_b);
    piece.rotation = transpose(rotation_b) * piece.rotation;
    return piece;
  }
};

template <class A> struct NewtonControlsOf {
  static KOKKOS_INLINE_FUNCTION NarrowPhaseControls of(const typename A::Table& t) {
    return t.settings.newton;
  }
};
template <> struct NewtonControlsOf<ClumpFamily> {
  static KOKKOS_INLINE_FUNCTION NarrowPhaseControls of(const ClumpFamily::Table& t) {
    return t.settings.newton.newton;
  }
};

// A superquadric, a poly-superquadric or a clump (body a) against a level-set body b.
template <class A> struct ConvexLevelSetNarrowPhase : MixedLevelSetState, EveryRowOfTheType {
  static constexpr bool tallied = true;
  static constexpr int max_contacts = pair_contact_points<A, LevelSetFamily>;
  typename A::Table bodies;
  NarrowPhaseControls controls;

  explicit ConvexLevelSetNarrowPhase(const ContactContext& c)
      : MixedLevelSetState(c), bodies(c.table<A>()),
        controls(NewtonControlsOf<A>::of(c.table<A>())) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    if (bounding_spheres_apart(r))
      return PairOutcome::apart;
    ++tally.evaluations;
    const LevelSetBodyView body_b = LevelSetFamily::body(table, shapes, p, r.b);
    const Mat3 rotation_b = rotation_matrix(load_quat(p.orientation, r.b));
    const Vec3 origin_b = load3(p.position, r.b);
    const double radius_b = LevelSetFamily::equivalent_radius(table, shapes, p, r.b);
    if constexpr (std::is_same_v<A, ClumpFamily>) {
      const Mat3 rotation_a = rotation_matrix(load_quat(p.orientation, r.a));
      const int template_a = shapes.template_index(p.shape(r.a));
      LevelSetPatches<max_contacts> patches(
          table.settings, math::min(A::equivalent_radius(bodies, shapes, p, r.a), radius_b));
      const int elements = bodies.elements.size(template_a);
      for (int e = 0; e < elements; ++e) {
        const PlacedElement element = A::element(bodies, shapes, p, r.a, rotation_a, e);
        if (norm(element.body.centre - origin_b) >= element.bounding_radius + p.radius(r.b))
          continue;
        const auto piece = in_frame(element.body, rotation_b, origin_b);
        if (element.sphere)
          sphere_piece(body_b, piece.centre, piece.shape.a, e, patches);
        else
          convex_piece(body_b, piece, controls, e, patches, tally);
      }
      return finish(
          patches, rotation_b, origin_b,
          [&](const FeatureContact& c) {
            return equivalent_series_radius(
                bodies.elements(template_a, c.feature_a).equivalent_radius, radius_b);
          },
          found);
    } else {
      const double radius_a = A::equivalent_radius(bodies, shapes, p, r.a);
      LevelSetPatches<max_contacts> patches(table.settings, math::min(radius_a, radius_b));
      convex_piece(body_b, in_frame(A::pose(bodies, shapes, p, r.a), rotation_b, origin_b),
                   controls, 0, patches, tally);
      return finish(patches, rotation_b, origin_b, equivalent_series_radius(radius_a, radius_b),
                    found);
    }
  }
};

template <>
struct NarrowPhase<SuperquadricFamily, LevelSetFamily>
    : ConvexLevelSetNarrowPhase<SuperquadricFamily> {
  static constexpr const char* label = "kdem::superquadric_level_set_forces";
  using ConvexLevelSetNarrowPhase::ConvexLevelSetNarrowPhase;
};

template <>
struct NarrowPhase<PolySuperquadricFamily, LevelSetFamily>
    : ConvexLevelSetNarrowPhase<PolySuperquadricFamily> {
  static constexpr const char* label = "kdem::poly_superquadric_level_set_forces";
  using ConvexLevelSetNarrowPhase::ConvexLevelSetNarrowPhase;
};

template <>
struct NarrowPhase<ClumpFamily, LevelSetFamily> : ConvexLevelSetNarrowPhase<ClumpFamily> {
  static constexpr const char* label = "kdem::clump_level_set_forces";
  using ConvexLevelSetNarrowPhase::ConvexLevelSetNarrowPhase;
};

// Hands on the contacts of a point of b with a's core (a's frame; normals from the point towards
// the core, key (core feature, 0)) in b's frame, keyed (core feature, 1 + point index).
template <int K> struct CorePointSink {
  LevelSetPatches<K>& patches;
  const RelativePose& a_in_b;
  int point_key = 0;
  KOKKOS_INLINE_FUNCTION void add(FeatureContact c) const {
    c.normal = a_in_b.rotation * c.normal;
    c.point = a_in_b.point(c.point);
    c.feature_b = point_key;
    patches.add(c);
  }
};

// A dilated polyhedron (body a) against a level-set body b.
template <>
struct NarrowPhase<DilatedPolyhedronFamily, LevelSetFamily> : MixedLevelSetState,
                                                              EveryRowOfTheType {
  static constexpr const char* label = "kdem::dilated_polyhedron_level_set_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = pair_contact_points<DilatedPolyhedronFamily, LevelSetFamily>;
  DilatedPolyhedronFamily::Table polyhedra;

  explicit NarrowPhase(const ContactContext& c)
      : MixedLevelSetState(c), polyhedra(c.table<DilatedPolyhedronFamily>()) {}

  // b's points within the core's dilation (the core distance's local minima, in a's frame).
  template <int K>
  KOKKOS_INLINE_FUNCTION void points_in_core(const LevelSetBodyView& b, const DeviceCore& core,
                                             const RelativePose& b_in_a, const RelativePose& a_in_b,
                                             double reach_a, LevelSetPatches<K>& patches,
                                             NarrowPhaseTally& tally) const {
    b.for_points_in_ball_box(a_in_b.translation, reach_a, [&](int q) {
      const Vec3 x = b_in_a.point(b.points[q]);
      if (!(norm2(x) < reach_a * reach_a))
        return;
      CorePointSink<K> sink{patches, a_in_b, 1 + q};
      if (!dilated_sphere_contacts(core, x, 0.0, polyhedra.settings.slack, sink))
        ++tally.failures;
    });
  }

  // The core's vertices and samples of its convex edges (at most a grid spacing apart), each
  // the centre of a sphere of the dilation radius, in b's grid.
  template <int K>
  KOKKOS_INLINE_FUNCTION void core_in_grid(const LevelSetBodyView& b, const DeviceCore& core,
                                           const RelativePose& a_in_b,
                                           LevelSetPatches<K>& patches) const {
    const double radius = core.dilation();
    const double reach = b.reach + radius;
    const FeatureNumbering keys = core.numbering();
    const auto test = [&](Vec3 centre, int key) {
      FeatureContact c;
      if (!(norm2(centre) < reach * reach) || !level_set::sphere_in_grid(b, centre, radius, c))
        return;
      c.feature_a = key;
      c.feature_b = 0;
      patches.add(c);
    };
    for (int v = 0; v < core.vertex_count; ++v)
      test(a_in_b.point(core.vertex(v).position), keys.vertex(v));
    for (int e = 0; e < core.edge_count; ++e) {
      const CoreEdge& edge = core.edge(e);
      if (!edge.convex)
        continue;
      const Vec3 from = a_in_b.point(core.vertex(edge.vertex[0]).position);
      const Vec3 to = a_in_b.point(core.vertex(edge.vertex[1]).position);
      const Vec3 mid = 0.5 * (from + to);
      const double half = 0.5 * norm(to - from);
      if (!(norm(mid) < reach + half))
        continue;
      const int samples = 1 + int(2 * half / b.grid.spacing);
      for (int k = 1; k < samples; ++k)
        test(from + (double(k) / samples) * (to - from), keys.edge(e));
    }
  }

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    if (bounding_spheres_apart(r))
      return PairOutcome::apart;
    ++tally.evaluations;
    const LevelSetBodyView body_b = LevelSetFamily::body(table, shapes, p, r.b);
    const DeviceCore core = DilatedPolyhedronFamily::core(polyhedra, shapes, p, r.a);
    const Poses q = poses(r);
    const double radius_a = DilatedPolyhedronFamily::equivalent_radius(polyhedra, shapes, p, r.a);
    const double radius_b = LevelSetFamily::equivalent_radius(table, shapes, p, r.b);
    LevelSetPatches<max_contacts> patches(table.settings, math::min(radius_a, radius_b));
    points_in_core(body_b, core, q.b_in_a, q.a_in_b, p.radius(r.a), patches, tally);
    core_in_grid(body_b, core, q.a_in_b, patches);
    return finish(patches, q.rotation_b, q.origin_b, equivalent_series_radius(radius_a, radius_b),
                  found);
  }
};

} // namespace kdem
