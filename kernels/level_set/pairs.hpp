#pragma once
// The pair types with level-set bodies, as narrow-phase functors of the one pair loop
// (families/pair_loop.hpp): a sphere against a level-set body, and two level-set bodies.
// After the bodies' bounding spheres, a level-set body's surface points are tested against the
// other body: against a sphere's exact distance, against another level-set body's grid (digest
// B5), in the frame of body a; a sphere's centre is also tested against the grid, which finds a
// sphere smaller than the points' spacing. The penetrating points are grouped into patches, the
// connected regions of penetration (LevelSetPatches, patches.hpp), each a contact at its deepest
// point with that point's key, weighted by the book's averaging. The Hertz radius is that of the
// volume-equivalent spheres in series (Eq. 5.17). Included only by the translation units of
// kernels/pairs/.
#include "../dilated_polyhedron/pairs.hpp"
#include "../families/pair_loop.hpp"
#include "family.hpp"
#include "patches.hpp"

namespace kdem {

// Hands on contacts found with the bodies' roles swapped (in b's frame, normals from a towards
// b, keys (b's, a's)) in a's frame with the pair's order.
template <int K> struct SwappedContactSink {
  LevelSetPatches<K>& patches;
  RelativePose b_in_a;
  KOKKOS_INLINE_FUNCTION void add(FeatureContact c) const {
    c.normal = -(b_in_a.rotation * c.normal);
    c.point = b_in_a.point(c.point);
    const int key_b = c.feature_a;
    c.feature_a = c.feature_b;
    c.feature_b = key_b;
    patches.add(c);
  }
};

struct LevelSetPairState {
  ParticleViews p;
  ShapeFamilies shapes;
  LevelSetFamily::Table table;
  int team_size = 0;

  explicit LevelSetPairState(const ContactContext& c)
      : p(c.particles), shapes(c.shape_families), table(c.table<LevelSetFamily>()) {}

  // The poses of a pair's bodies in the world and in each other's frame.
  struct Poses {
    Mat3 rotation_a, rotation_b;
    Vec3 origin_a, origin_b;
    RelativePose b_in_a, a_in_b;
  };
  KOKKOS_INLINE_FUNCTION Poses poses(const PairRef& r) const {
    Poses q;
    q.rotation_a = rotation_matrix(load_quat(p.orientation, r.a));
    q.rotation_b = rotation_matrix(load_quat(p.orientation, r.b));
    q.origin_a = load3(p.position, r.a);
    q.origin_b = load3(p.position, r.b);
    q.b_in_a = RelativePose{transpose(q.rotation_a) * q.rotation_b,
                            transpose_times(q.rotation_a, q.origin_b - q.origin_a)};
    q.a_in_b = RelativePose{transpose(q.rotation_b) * q.rotation_a,
                            transpose_times(q.rotation_b, q.origin_a - q.origin_b)};
    return q;
  }

  KOKKOS_INLINE_FUNCTION bool bounding_spheres_apart(const PairRef& r) const {
    const double reach = p.radius(r.i) + p.radius(r.j);
    return !(norm2(load3(p.position, r.i) - load3(p.position, r.j)) < reach * reach);
  }

  // The patches found in the frame (rotation, origin) turned into the world and into `found`,
  // with their weights; normals from b towards a. radius_of(contact): its Hertz radius.
  template <int K, class RadiusOf>
  KOKKOS_INLINE_FUNCTION PairOutcome finish(const LevelSetPatches<K>& patches, const Mat3& rotation,
                                            Vec3 origin, const RadiusOf& radius_of,
                                            PairContacts<K>& found) const {
    if (patches.count == 0)
      return PairOutcome::apart;
    for (int c = 0; c < patches.count; ++c) {
      const FeatureContact& f = patches.contact[c];
      PairContact& contact = found.add();
      contact.geometry =
          ContactGeometry{true, f.overlap, rotation * f.normal, origin + rotation * f.point};
      contact.effective_radius = radius_of(f);
      contact.feature_a = f.feature_a;
      contact.feature_b = f.feature_b;
    }
    patches.weights(table.settings.averaging,
                    [&](int c, double w) { found.contact[c].weight = w; });
    return PairOutcome::touching;
  }
  template <int K>
  KOKKOS_INLINE_FUNCTION PairOutcome finish(const LevelSetPatches<K>& patches, const Mat3& rotation,
                                            Vec3 origin, double radius,
                                            PairContacts<K>& found) const {
    return finish(
        patches, rotation, origin, [=](const FeatureContact&) { return radius; }, found);
  }
};

namespace level_set {

// Support-point iterations of the deepest-point search; each costs one support point and one
// grid sample, and a smooth convex piece against a flat face settles in two or three.
constexpr int support_iterations = 8;

// A sphere (centre, radius; b's frame) against b's grid: overlap radius minus the value at the
// centre, normal b's outward normal (from b towards the sphere); false beyond the grid.
KOKKOS_INLINE_FUNCTION bool sphere_in_grid(const LevelSetBodyView& b, Vec3 centre, double radius,
                                           FeatureContact& c) {
  LevelSetSample s;
  if (!b.sample(centre, s) || !(s.value < radius))
    return false;
  const Vec3 out = outward(s, centre);
  c.overlap = radius - s.value;
  c.normal = out;
  c.point = centre - (radius - 0.5 * c.overlap) * out;
  return true;
}

// The deepest point in b's grid of a convex piece (support(d): its point furthest along d, b's
// frame), starting from its point furthest towards b's origin.
template <class Support>
KOKKOS_INLINE_FUNCTION bool deepest_support_point(const LevelSetBodyView& b, const Support& support,
                                                  Vec3 towards_b, FeatureContact& c) {
  Vec3 x = support(towards_b);
  bool found = false;
  for (int k = 0; k < support_iterations; ++k) {
    LevelSetSample s;
    if (!b.sample(x, s))
      break;
    const Vec3 out = outward(s, x);
    if (s.value < 0 && (!found || -s.value > c.overlap)) {
      found = true;
      c.overlap = -s.value;
      c.normal = out;
      c.point = x + (0.5 * c.overlap) * out;
    }
    const Vec3 next = support(-1.0 * out);
    if (norm2(next - x) <= 1e-24 * b.reach * b.reach)
      break;
    x = next;
  }
  return found;
}

} // namespace level_set

// A sphere (body a, centre c and radius r in b's frame) against a level-set body b, three ways
// into the same patches: the centre in b's grid (overlap r minus the value there, key (0, 0)),
// which finds a sphere smaller than the points' spacing; b's surface points inside the sphere
// (overlap r minus their distance from c, normal along the line from the point to c, keys
// (0, 1 + point index)), exact at b's corners, where the grid's value at a distant centre is
// not (a convex body's distance is convex, so its trilinear value errs high and the overlap
// low); and the sphere's deepest point in b's grid (key (0, 0)), which finds a face of b
// pressed into a sphere too large for its centre to lie in the grid (through b's points alone,
// such a sphere sank until a point lay inside it). The patch keeps the deepest. The trilinear
// value of a body's exact distance errs by less than a cell's diagonal (1-Lipschitz), so a
// centre beyond r plus that is apart. Contacts in b's frame, normals from b towards a.
template <class Sink>
KOKKOS_INLINE_FUNCTION void sphere_level_set_contacts(const LevelSetBodyView& b, Vec3 centre,
                                                      double radius, Sink& sink) {
  FeatureContact c;
  c.feature_a = 0;
  c.feature_b = 0;
  LevelSetSample s;
  if (interpolate_level_set(b.grid, b.values, centre, s)) {
    if (!(s.value < radius + 1.7320508075688772 * b.grid.spacing))
      return;
    if (s.value < radius) {
      const Vec3 out = level_set::outward(s, centre);
      c.overlap = radius - s.value;
      c.normal = out;
      c.point = centre - (radius - 0.5 * c.overlap) * out;
      sink.add(c);
    }
  }
  b.for_points_in_ball_box(centre, radius, [&](int q) {
    const Vec3 x = b.points[q];
    const double distance = norm(centre - x);
    if (!(distance < radius) || !(distance > 0))
      return;
    FeatureContact p;
    p.overlap = radius - distance;
    p.normal = (1.0 / distance) * (centre - x);
    p.point = x - (0.5 * p.overlap) * p.normal;
    p.feature_a = 0;
    p.feature_b = 1 + q;
    sink.add(p);
  });
  const double from_origin = norm(centre);
  const Vec3 towards_b = from_origin > 0 ? (-1.0 / from_origin) * centre : Vec3{0, 0, -1};
  const auto support = [&](Vec3 d) {
    const double length = norm(d);
    return length > 0 ? centre + (radius / length) * d : centre;
  };
  if (level_set::deepest_support_point(b, support, towards_b, c))
    sink.add(c);
}

template <>
struct NarrowPhase<SphereFamily, LevelSetFamily> : LevelSetPairState, EveryRowOfTheType {
  static constexpr const char* label = "kdem::sphere_level_set_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = pair_contact_points<SphereFamily, LevelSetFamily>;

  explicit NarrowPhase(const ContactContext& c) : LevelSetPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    if (bounding_spheres_apart(r))
      return PairOutcome::apart;
    ++tally.evaluations;
    const LevelSetBodyView body = LevelSetFamily::body(table, shapes, p, r.b);
    const Mat3 rotation = rotation_matrix(load_quat(p.orientation, r.b));
    const Vec3 origin = load3(p.position, r.b);
    const double radius_b = LevelSetFamily::equivalent_radius(table, shapes, p, r.b);
    LevelSetPatches<max_contacts> patches(table.settings, math::min(p.radius(r.a), radius_b));
    sphere_level_set_contacts(body, transpose_times(rotation, load3(p.position, r.a) - origin),
                              p.radius(r.a), patches);
    return finish(patches, rotation, origin, equivalent_series_radius(p.radius(r.a), radius_b),
                  found);
  }
};

// Two level-set bodies, in a's frame: b's points in a's grid and, both ways, a's points in b's;
// after the bounding spheres, the bodies' boxes (no point outside a body's box is inside it).
template <>
struct NarrowPhase<LevelSetFamily, LevelSetFamily> : LevelSetPairState, EveryRowOfTheType {
  static constexpr const char* label = "kdem::level_set_forces";
  static constexpr bool tallied = true;
  static constexpr int max_contacts = pair_contact_points<LevelSetFamily, LevelSetFamily>;

  explicit NarrowPhase(const ContactContext& c) : LevelSetPairState(c) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<max_contacts>& found,
                                                NarrowPhaseTally& tally) const {
    if (bounding_spheres_apart(r))
      return PairOutcome::apart;
    int separating_axis = -1;
    if (!oriented_boxes_overlap(LevelSetFamily::oriented_box(table, shapes, p, r.a),
                                LevelSetFamily::oriented_box(table, shapes, p, r.b),
                                separating_axis))
      return PairOutcome::apart;
    ++tally.evaluations;
    const LevelSetBodyView body_a = LevelSetFamily::body(table, shapes, p, r.a);
    const LevelSetBodyView body_b = LevelSetFamily::body(table, shapes, p, r.b);
    const Poses q = poses(r);
    const double radius_a = LevelSetFamily::equivalent_radius(table, shapes, p, r.a);
    const double radius_b = LevelSetFamily::equivalent_radius(table, shapes, p, r.b);
    LevelSetPatches<max_contacts> patches(table.settings, math::min(radius_a, radius_b));
    // One way: the points of the body of the higher index (j) in the other's grid.
    if (table.settings.both_ways || r.b == r.j)
      points_inside(body_a, body_b, q.b_in_a, patches);
    if (table.settings.both_ways || r.a == r.j) {
      SwappedContactSink<max_contacts> swapped{patches, q.b_in_a};
      points_inside(body_b, body_a, q.a_in_b, swapped);
    }
    return finish(patches, q.rotation_a, q.origin_a, equivalent_series_radius(radius_a, radius_b),
                  found);
  }
};

} // namespace kdem
