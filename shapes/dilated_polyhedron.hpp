#pragma once
// Dilated (Minkowski-sum) polyhedra (book chapter 4; digest ch4_5 part A): a closed, outward
// oriented triangulated core swept by a sphere of dilation radius r. Host and device.
//
// Contacts of two dilated cores are the local minima of the distance between the cores that lie
// within the sum of the radii (the book's virtual spheres: the two closest core points, each the
// centre of a sphere of its body's dilation radius). A local minimum pairs a feature of each core
// (vertex, edge interior, face interior) whose closest points are stationary within both features
// and whose connecting direction lies in the normal cone of the core at each: vertex-face,
// vertex-edge, vertex-vertex and edge-edge pairs (face-face and face-edge pairs are stationary
// only when parallel, and then the extremes of their contact patch are vertex-face, vertex-edge
// and edge-edge pairs: the book's 3 to 6 points of two parallel faces, Sect. 4.2.2). Each feature
// is tested once per body, by the face that owns it (the lowest-numbered face it belongs to), so
// every feature pair is tested once; normal cones are tested with a small angular slack, beyond
// which a contact fades out over a further angle (ConeSlack), so that the points of nearly
// parallel faces leave continuously.
#include "mat3.hpp"
#include "math.hpp"
#include "vec3.hpp"

namespace kdem {

// A core vertex, with the unit directions of its edges (entries cone_first .. cone_first +
// cone_count of the template's cone list). A point x = vertex + t d (t > 0) has the vertex as a
// local minimum of its distance to the surface when d . e <= 0 for every edge direction e (the
// faces at the vertex then lie behind the plane through it normal to d), and lies outside when
// d . outward > 0 (outward: the angle-weighted pseudonormal, which signs the distance at a
// closest point, Baerentzen and Aanaes 2005). `convex`: every edge at it is convex or flat, so
// that the first condition implies the second; a saddle vertex of a fine, nearly flat mesh can
// be a closest point too, and is tested with both.
struct CoreVertex {
  Vec3 position;
  Vec3 outward; // unit
  int cone_first = 0, cone_count = 0;
  int owner = 0;  // the face that tests this vertex
  int convex = 0; // 1 or 0
};

// A core edge between two faces. `inward[k]`: in face k's plane, perpendicular to the edge,
// pointing into face k (unit). The normal cone of a convex edge is the wedge of directions d
// perpendicular to it with d . inward[k] <= 0 for both faces; a reflex edge has none.
struct CoreEdge {
  int vertex[2] = {0, 0};
  Vec3 inward[2];
  int owner = 0;
  int convex = 0;
};

// A core face: corners counter-clockwise seen from outside, edges (v0 v1), (v1 v2), (v2 v0).
struct CoreFace {
  int vertex[3] = {0, 0, 0};
  int edge[3] = {0, 0, 0};
  Vec3 normal; // unit, outward
};

// A node of the bounding-sphere tree over the faces (root: node 0). A leaf holds one face:
// left < 0 and right is the face; an inner node has children left and right.
// Its cap (axis, and the cosine and sine of its half-angle) holds every outward direction in
// which a feature tested under the node (a face, or an edge or vertex its face owns) can meet
// another body: their normal cones widened by the slack and fade the core's caps were bound for
// (bound_normal_cones). Half-angle pi (cosine -1): any direction, so nothing is pruned.
struct SphereNode {
  Vec3 centre;
  double radius = 0;
  int left = -1, right = 0;
  Vec3 cap_axis{0, 0, 1};
  double cap_cos = -1, cap_sin = 0;
};

// Feature keys of a core of V vertices and E edges: vertex k is k, edge k is V + k, face k is
// V + E + k.
struct FeatureNumbering {
  int vertices = 0, edges = 0;
  KOKKOS_INLINE_FUNCTION int vertex(int k) const { return k; }
  KOKKOS_INLINE_FUNCTION int edge(int k) const { return vertices + k; }
  KOKKOS_INLINE_FUNCTION int face(int k) const { return vertices + edges + k; }
};

// Where the normal cones are tested with slack: a direction within `angle` (rad) of a cone
// counts as in it. Enough to keep the points of exactly parallel features (which lie on cone
// boundaries) from rounding; a larger slack also keeps near-minima, which differ from the
// minimum by up to the slack in normal and by its square times the distance in overlap.
// Beyond the slack a contact fades: its weight falls smoothly from 1 to 0 over a further `fade`
// (a sine; 0: cut at the slack). Two faces resting on each other touch at their corners, and a
// tilt of the order of overlap / face size takes every corner but the lowest out of its cone
// while its overlap is still large; cut there, the force jumps and feeds a rocking of the bodies
// that never dies out (cases/stack). Fading, it is continuous.
struct ConeSlack {
  double sine = 1e-6, cosine = 1.0 - 5e-13;
  double fade = 0;
  KOKKOS_INLINE_FUNCTION static ConeSlack of_angle(double angle, double fade_angle = 0) {
    return ConeSlack{math::sin(angle), math::cos(angle), math::sin(fade_angle)};
  }
  // The weight of a direction whose largest excursion out of a cone is `outside` (a sine):
  // math::falloff of t = (outside - sine) / fade.
  KOKKOS_INLINE_FUNCTION double weight(double outside) const {
    if (!(outside > sine))
      return 1.0;
    return math::falloff(fade > 0 ? (outside - sine) / fade : 1.0);
  }
};

// Body B's frame in body A's: x_A = rotation x_B + translation.
struct RelativePose {
  Mat3 rotation;
  Vec3 translation;
  KOKKOS_INLINE_FUNCTION Vec3 point(Vec3 x_b) const { return rotation * x_b + translation; }
  KOKKOS_INLINE_FUNCTION Vec3 direction_in_b(Vec3 d_a) const {
    return transpose_times(rotation, d_a);
  }
};

// One contact of two dilated cores (or of a core and a sphere or a wall), in the frame it was
// computed in: normal from B towards A, the book's contact point (midway between the two
// dilated surfaces on the line of the core points), overlap r_A + r_B - distance, and the
// feature keys of each body.
struct FeatureContact {
  double overlap = 0;
  double cone_weight = 1; // in (0, 1]: see ConeSlack
  Vec3 normal, point;
  int feature_a = -1, feature_b = -1;
};

namespace dilated {

// Normal cones (see CoreVertex, CoreEdge): the weight (ConeSlack::weight) of the outward
// direction d (unit) of the core at the feature, 1 in its cone or within the slack, 0 beyond the
// fade.
template <class Core>
KOKKOS_INLINE_FUNCTION double vertex_cone_weight(const Core& core, int v, Vec3 d,
                                                 const ConeSlack& s) {
  const CoreVertex& vertex = core.vertex(v);
  if (!vertex.convex && !(dot(d, vertex.outward) > 0))
    return 0.0;
  double outside = -1;
  for (int m = 0; m < vertex.cone_count; ++m)
    outside = math::max(outside, dot(d, core.cone(vertex.cone_first + m)));
  return s.weight(outside);
}

template <class Core>
KOKKOS_INLINE_FUNCTION double edge_cone_weight(const Core& core, int e, Vec3 d,
                                               const ConeSlack& s) {
  const CoreEdge& edge = core.edge(e);
  if (!edge.convex)
    return 0.0;
  return s.weight(math::max(dot(d, edge.inward[0]), dot(d, edge.inward[1])));
}

KOKKOS_INLINE_FUNCTION double face_cone_weight(Vec3 normal, Vec3 d, const ConeSlack& s) {
  const double along = dot(d, normal);
  if (along >= s.cosine)
    return 1.0;
  if (!(along > 0))
    return 0.0;
  return s.weight(math::sqrt(math::max(0.0, 1.0 - along * along)));
}

// The parameter of the point of segment [p, q] nearest to x, and whether it lies strictly inside.
KOKKOS_INLINE_FUNCTION bool segment_interior(Vec3 p, Vec3 q, Vec3 x, double& t) {
  const Vec3 pq = q - p;
  const double length2 = norm2(pq);
  if (!(length2 > 0))
    return false;
  t = dot(x - p, pq) / length2;
  return t > 0 && t < 1;
}

// Whether the projection of x onto the plane of triangle (a, b, c) (unit normal n, either side)
// lies strictly inside it; the projection in `foot`. The sides are tested against the corners'
// own winding, so that a two-sided wall triangle whose normal was turned to a particle's side
// tests alike.
KOKKOS_INLINE_FUNCTION bool face_interior(Vec3 a, Vec3 b, Vec3 c, Vec3 n, Vec3 x, Vec3& foot) {
  foot = x - dot(x - a, n) * n;
  const Vec3 winding = cross(b - a, c - a);
  return dot(cross(b - a, foot - a), winding) > 0 && dot(cross(c - b, foot - b), winding) > 0 &&
         dot(cross(a - c, foot - c), winding) > 0;
}

// Parameters (s on [p1, q1], t on [p2, q2]) of the closest points of the two lines, and whether
// both lie strictly inside their segments; parallel segments have no isolated closest pair.
KOKKOS_INLINE_FUNCTION bool segments_interior(Vec3 p1, Vec3 q1, Vec3 p2, Vec3 q2, double& s,
                                              double& t) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = dot(d1, d1), e = dot(d2, d2), b = dot(d1, d2);
  const double c = dot(d1, r), f = dot(d2, r);
  const double denominator = a * e - b * b;
  if (!(denominator > 1e-12 * a * e))
    return false;
  s = (b * f - c * e) / denominator;
  t = (b * s + f) / e;
  return s > 0 && s < 1 && t > 0 && t < 1;
}

} // namespace dilated

// A candidate pair of core points (pa on A, pb on B, in A's frame) with their features: the
// contact it makes when the points lie within reach and the direction between them lies in both
// normal cones (the caller's `cones(direction_from_b_to_a)`: the product of both cones' weights,
// 0 where it lies out of either).
template <class Cones>
KOKKOS_INLINE_FUNCTION bool feature_contact(Vec3 pa, Vec3 pb, double radius_a, double radius_b,
                                            int feature_a, int feature_b, const Cones& cones,
                                            FeatureContact& contact) {
  const Vec3 between = pa - pb;
  const double distance2 = norm2(between);
  const double reach = radius_a + radius_b;
  if (!(distance2 < reach * reach) || !(distance2 > 0))
    return false;
  const double distance = math::sqrt(distance2);
  const Vec3 u = (1.0 / distance) * between;
  const double cone_weight = cones(u);
  if (!(cone_weight > 0))
    return false;
  contact.cone_weight = cone_weight;
  contact.overlap = reach - distance;
  contact.normal = u;
  contact.point = 0.5 * ((pa - radius_a * u) + (pb + radius_b * u));
  contact.feature_a = feature_a;
  contact.feature_b = feature_b;
  return true;
}

// A core placed in a frame: its vertices as seen there (the template's for the body itself, or
// turned and moved into the other body's frame), and directions turned back into its own frame
// for the cone tests.
template <class Core> struct PlacedCore {
  const Core& core;
  RelativePose pose; // this core's frame in the working frame
  bool moved = false;

  KOKKOS_INLINE_FUNCTION Vec3 vertex(int v) const {
    const Vec3 x = core.vertex(v).position;
    return moved ? pose.point(x) : x;
  }
  KOKKOS_INLINE_FUNCTION Vec3 own(Vec3 d) const { return moved ? pose.direction_in_b(d) : d; }
  KOKKOS_INLINE_FUNCTION Vec3 face_normal(int f) const {
    const Vec3 n = core.face(f).normal;
    return moved ? pose.rotation * n : n;
  }
};

// Tests every pair of a feature of face fa of A with one of face fb of B that these faces own, in
// A's frame, and passes each contact to sink.add(contact).
template <class CoreA, class CoreB, class Sink>
KOKKOS_INLINE_FUNCTION void face_pair_contacts(const PlacedCore<CoreA>& a, int fa,
                                               const PlacedCore<CoreB>& b, int fb,
                                               const ConeSlack& slack, Sink& sink) {
  using namespace dilated;
  const CoreFace& face_a = a.core.face(fa);
  const CoreFace& face_b = b.core.face(fb);
  const double ra = a.core.dilation(), rb = b.core.dilation();
  const FeatureNumbering keys_a = a.core.numbering(), keys_b = b.core.numbering();
  Vec3 xa[3], xb[3];
  for (int k = 0; k < 3; ++k) {
    xa[k] = a.vertex(face_a.vertex[k]);
    xb[k] = b.vertex(face_b.vertex[k]);
  }
  const Vec3 na = a.face_normal(fa), nb = b.face_normal(fb);
  const auto a_vertex = [&](int v, Vec3 u) {
    return vertex_cone_weight(a.core, v, a.own(-u), slack);
  };
  const auto b_vertex = [&](int v, Vec3 u) {
    return vertex_cone_weight(b.core, v, b.own(u), slack);
  };
  const auto a_edge = [&](int e, Vec3 u) { return edge_cone_weight(a.core, e, a.own(-u), slack); };
  const auto b_edge = [&](int e, Vec3 u) { return edge_cone_weight(b.core, e, b.own(u), slack); };
  FeatureContact contact;
  for (int k = 0; k < 3; ++k) {
    const int v = face_a.vertex[k];
    if (a.core.vertex(v).owner != fa)
      continue;
    Vec3 foot;
    if (face_interior(xb[0], xb[1], xb[2], nb, xa[k], foot) &&
        feature_contact(
            xa[k], foot, ra, rb, keys_a.vertex(v), keys_b.face(fb),
            [&](Vec3 u) { return face_cone_weight(nb, u, slack) * a_vertex(v, u); }, contact))
      sink.add(contact);
    for (int m = 0; m < 3; ++m) {
      const int e = face_b.edge[m];
      double t;
      if (b.core.edge(e).owner == fb && segment_interior(xb[m], xb[(m + 1) % 3], xa[k], t) &&
          feature_contact(
              xa[k], xb[m] + t * (xb[(m + 1) % 3] - xb[m]), ra, rb, keys_a.vertex(v),
              keys_b.edge(e), [&](Vec3 u) { return b_edge(e, u) * a_vertex(v, u); }, contact))
        sink.add(contact);
      const int w = face_b.vertex[m];
      if (b.core.vertex(w).owner == fb &&
          feature_contact(
              xa[k], xb[m], ra, rb, keys_a.vertex(v), keys_b.vertex(w),
              [&](Vec3 u) { return b_vertex(w, u) * a_vertex(v, u); }, contact))
        sink.add(contact);
    }
  }
  for (int m = 0; m < 3; ++m) {
    const int w = face_b.vertex[m];
    if (b.core.vertex(w).owner != fb)
      continue;
    Vec3 foot;
    if (face_interior(xa[0], xa[1], xa[2], na, xb[m], foot) &&
        feature_contact(
            foot, xb[m], ra, rb, keys_a.face(fa), keys_b.vertex(w),
            [&](Vec3 u) { return face_cone_weight(na, -u, slack) * b_vertex(w, u); }, contact))
      sink.add(contact);
    for (int k = 0; k < 3; ++k) {
      const int e = face_a.edge[k];
      double t;
      if (a.core.edge(e).owner == fa && segment_interior(xa[k], xa[(k + 1) % 3], xb[m], t) &&
          feature_contact(
              xa[k] + t * (xa[(k + 1) % 3] - xa[k]), xb[m], ra, rb, keys_a.edge(e),
              keys_b.vertex(w), [&](Vec3 u) { return a_edge(e, u) * b_vertex(w, u); }, contact))
        sink.add(contact);
    }
  }
  for (int k = 0; k < 3; ++k) {
    const int e = face_a.edge[k];
    if (a.core.edge(e).owner != fa)
      continue;
    for (int m = 0; m < 3; ++m) {
      const int g = face_b.edge[m];
      double s, t;
      if (b.core.edge(g).owner == fb &&
          segments_interior(xa[k], xa[(k + 1) % 3], xb[m], xb[(m + 1) % 3], s, t) &&
          feature_contact(
              xa[k] + s * (xa[(k + 1) % 3] - xa[k]), xb[m] + t * (xb[(m + 1) % 3] - xb[m]), ra, rb,
              keys_a.edge(e), keys_b.edge(g), [&](Vec3 u) { return a_edge(e, u) * b_edge(g, u); },
              contact))
        sink.add(contact);
    }
  }
}

// The contacts of a sphere (centre x, radius r, in the core's frame) with the edges and vertices
// of face f that it owns: the closest point of the face's boundary to x, when x lies in that
// feature's normal cone.
template <class Core, class Sink>
KOKKOS_INLINE_FUNCTION void face_boundary_contacts(const Core& core, int f, Vec3 x, double radius,
                                                   const ConeSlack& slack, Sink& sink) {
  using namespace dilated;
  const CoreFace& face = core.face(f);
  const FeatureNumbering keys = core.numbering();
  Vec3 c[3];
  for (int k = 0; k < 3; ++k)
    c[k] = core.vertex(face.vertex[k]).position;
  FeatureContact contact;
  for (int k = 0; k < 3; ++k) {
    const int v = face.vertex[k], e = face.edge[k];
    double t;
    if (core.edge(e).owner == f && segment_interior(c[k], c[(k + 1) % 3], x, t) &&
        feature_contact(
            c[k] + t * (c[(k + 1) % 3] - c[k]), x, core.dilation(), radius, keys.edge(e), 0,
            [&](Vec3 u) { return edge_cone_weight(core, e, -u, slack); }, contact))
      sink.add(contact);
    if (core.vertex(v).owner == f &&
        feature_contact(
            c[k], x, core.dilation(), radius, keys.vertex(v), 0,
            [&](Vec3 u) { return vertex_cone_weight(core, v, -u, slack); }, contact))
      sink.add(contact);
  }
}

// The contacts of a sphere (centre x, radius r, in the core's frame) with face f's features that
// it owns: the closest point of the face to x, when it is a feature the face owns and x lies in
// that feature's normal cone.
template <class Core, class Sink>
KOKKOS_INLINE_FUNCTION void face_sphere_contacts(const Core& core, int f, Vec3 x, double radius,
                                                 const ConeSlack& slack, Sink& sink) {
  using namespace dilated;
  const CoreFace& face = core.face(f);
  Vec3 c[3];
  for (int k = 0; k < 3; ++k)
    c[k] = core.vertex(face.vertex[k]).position;
  Vec3 foot;
  if (!face_interior(c[0], c[1], c[2], face.normal, x, foot)) {
    face_boundary_contacts(core, f, x, radius, slack, sink);
    return;
  }
  FeatureContact contact;
  if (feature_contact(
          foot, x, core.dilation(), radius, core.numbering().face(f), 0,
          [&](Vec3 u) { return face_cone_weight(face.normal, -u, slack); }, contact))
    sink.add(contact);
}

// The reach of a slack into the sine of the angle out of a cone (ConeSlack::weight): directions
// beyond it weigh 0. Node caps bound for a reach hold the cones of every smaller one.
KOKKOS_INLINE_FUNCTION double cone_reach(const ConeSlack& slack) {
  return slack.sine + slack.fade;
}

namespace dilated {

// Whether two unit directions (the cosine between them) are at most the sum of two angles in
// [0, pi] (cosines and sines) apart, rounding towards yes.
KOKKOS_INLINE_FUNCTION bool within_angles(double between, double cos_a, double sin_a, double cos_b,
                                          double sin_b) {
  if (cos_a + cos_b <= 0) // a + b >= pi
    return true;
  return between >= cos_a * cos_b - sin_a * sin_b - 1e-12;
}

// Whether some direction within `spread` (cosine, sine) of the unit direction d lies in the
// node's cap.
KOKKOS_INLINE_FUNCTION bool cap_meets(const SphereNode& node, Vec3 d, double spread_cos,
                                      double spread_sin) {
  return within_angles(dot(node.cap_axis, d), node.cap_cos, node.cap_sin, spread_cos, spread_sin);
}

// The directions from the points of a sphere (centre, radius) to the point x: within `spread`
// of `direction`; false where x lies in the sphere (any direction).
struct DirectionSpread {
  Vec3 direction;
  double spread_cos = 1, spread_sin = 0;
};
KOKKOS_INLINE_FUNCTION bool direction_spread(Vec3 centre, double radius, Vec3 x,
                                             DirectionSpread& spread) {
  const double distance = norm(x - centre);
  if (!(distance > radius * (1 + 1e-12)))
    return false;
  spread.direction = (1.0 / distance) * (x - centre);
  spread.spread_sin = radius / distance;
  spread.spread_cos = math::sqrt(math::max(0.0, 1.0 - spread.spread_sin * spread.spread_sin));
  return true;
}

// Whether node a of body A and node b of body B (placed by `pose` in A's frame) can hold a
// contact: its direction u (from B towards A) must have -u in a's cap and u in b's, and lie
// within the directions from b's sphere to a's.
KOKKOS_INLINE_FUNCTION bool caps_meet(const SphereNode& a, const SphereNode& b,
                                      const RelativePose& pose) {
  const Vec3 axis_b = pose.rotation * b.cap_axis;
  if (!within_angles(-dot(a.cap_axis, axis_b), a.cap_cos, a.cap_sin, b.cap_cos, b.cap_sin))
    return false;
  DirectionSpread from_b;
  if (!direction_spread(pose.point(b.centre), a.radius + b.radius, a.centre, from_b))
    return true;
  return cap_meets(a, -from_b.direction, from_b.spread_cos, from_b.spread_sin) &&
         within_angles(dot(axis_b, from_b.direction), b.cap_cos, b.cap_sin, from_b.spread_cos,
                       from_b.spread_sin);
}

} // namespace dilated

// Depth of the fixed stacks of the tree walks: a tree of n faces built by median splits is about
// log2(n) deep, and a walk of two trees holds at most the sum of their depths plus one.
constexpr int sphere_tree_stack = 96;

// Calls visit(face) for every face whose tree nodes, from the root down to its leaf, all pass
// near(node). False when the stack overflowed (a tree deeper than the stack allows).
template <class Core, class Near, class Visit>
KOKKOS_INLINE_FUNCTION bool for_each_face_where(const Core& core, const Near& near, Visit&& visit) {
  int stack[sphere_tree_stack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const SphereNode& node = core.node(stack[--top]);
    if (!near(node))
      continue;
    if (node.left < 0) {
      visit(node.right);
      continue;
    }
    if (top + 2 > sphere_tree_stack)
      return false;
    stack[top++] = node.right;
    stack[top++] = node.left;
  }
  return true;
}

// Calls visit(face) for every face of the core whose node sphere comes within `reach` of x
// (core frame); with `caps`, only those whose node caps hold a direction from the node's sphere
// towards x.
template <class Core, class Visit>
KOKKOS_INLINE_FUNCTION bool for_each_face_near(const Core& core, Vec3 x, double reach,
                                               Visit&& visit, bool caps = false) {
  return for_each_face_where(
      core,
      [&](const SphereNode& node) {
        const double within = node.radius + reach;
        if (!(norm2(x - node.centre) < within * within))
          return false;
        dilated::DirectionSpread towards_x;
        return !caps || !dilated::direction_spread(node.centre, node.radius, x, towards_x) ||
               dilated::cap_meets(node, towards_x.direction, towards_x.spread_cos,
                                  towards_x.spread_sin);
      },
      visit);
}

// Calls visit(face) for every face whose node sphere comes within `reach` of the plane through
// `origin` with unit normal n, on its front side (signed distance < node radius + reach); with
// `caps`, only those whose node caps hold -n.
template <class Core, class Visit>
KOKKOS_INLINE_FUNCTION bool for_each_face_near_plane(const Core& core, Vec3 origin, Vec3 n,
                                                     double reach, Visit&& visit,
                                                     bool caps = false) {
  return for_each_face_where(
      core,
      [&](const SphereNode& node) {
        return dot(node.centre - origin, n) < node.radius + reach &&
               (!caps || dilated::cap_meets(node, -n, 1.0, 0.0));
      },
      visit);
}

// Calls visit(face_a, face_b) for every pair of faces whose node spheres (B's placed in A's frame
// by `pose`) come within `reach`, and with `caps` whose node caps can hold a contact
// (dilated::caps_meet); the larger node of a pair is split first.
template <class CoreA, class CoreB, class Visit>
KOKKOS_INLINE_FUNCTION bool for_each_face_pair_near(const CoreA& a, const CoreB& b,
                                                    const RelativePose& pose, double reach,
                                                    Visit&& visit, bool caps = false) {
  int stack_a[sphere_tree_stack], stack_b[sphere_tree_stack];
  int top = 0;
  stack_a[top] = 0, stack_b[top] = 0, ++top;
  while (top > 0) {
    --top;
    const int na = stack_a[top], nb = stack_b[top];
    const SphereNode& node_a = a.node(na);
    const SphereNode& node_b = b.node(nb);
    const double within = node_a.radius + node_b.radius + reach;
    if (!(norm2(pose.point(node_b.centre) - node_a.centre) < within * within))
      continue;
    if (caps && !dilated::caps_meet(node_a, node_b, pose))
      continue;
    const bool leaf_a = node_a.left < 0, leaf_b = node_b.left < 0;
    if (leaf_a && leaf_b) {
      visit(node_a.right, node_b.right);
      continue;
    }
    if (top + 2 > sphere_tree_stack)
      return false;
    if (leaf_b || (!leaf_a && node_a.radius >= node_b.radius)) {
      stack_a[top] = node_a.right, stack_b[top] = nb, ++top;
      stack_a[top] = node_a.left, stack_b[top] = nb, ++top;
    } else {
      stack_a[top] = na, stack_b[top] = node_b.right, ++top;
      stack_a[top] = na, stack_b[top] = node_b.left, ++top;
    }
  }
  return true;
}

// The contacts of two dilated cores, in A's frame (B placed by `pose`), passed to sink.add.
// False when a tree walk overflowed its stack (no contact is then missing from what was passed,
// but some may not have been looked for).
template <class CoreA, class CoreB, class Sink>
KOKKOS_INLINE_FUNCTION bool dilated_pair_contacts(const CoreA& a, const CoreB& b,
                                                  const RelativePose& pose, const ConeSlack& slack,
                                                  Sink& sink) {
  const PlacedCore<CoreA> placed_a{a, RelativePose{identity3(), Vec3{}}, false};
  const PlacedCore<CoreB> placed_b{b, pose, true};
  const double reach = cone_reach(slack);
  return for_each_face_pair_near(
      a, b, pose, a.dilation() + b.dilation(),
      [&](int fa, int fb) { face_pair_contacts(placed_a, fa, placed_b, fb, slack, sink); },
      a.cap_reach() >= reach && b.cap_reach() >= reach);
}

// The contacts of a dilated core with a sphere (centre x in the core's frame, radius r).
template <class Core, class Sink>
KOKKOS_INLINE_FUNCTION bool dilated_sphere_contacts(const Core& core, Vec3 x, double radius,
                                                    const ConeSlack& slack, Sink& sink) {
  return for_each_face_near(
      core, x, core.dilation() + radius,
      [&](int f) { face_sphere_contacts(core, f, x, radius, slack, sink); },
      core.cap_reach() >= cone_reach(slack));
}

// The contacts of a dilated core with the front side of a plane (origin, unit normal n, in the
// core's frame): its convex vertices within reach whose cone holds -n (feature_b = 0). A core
// face or edge lying on the plane touches it with its vertices.
template <class Core, class Sink>
KOKKOS_INLINE_FUNCTION bool dilated_plane_contacts(const Core& core, Vec3 origin, Vec3 n,
                                                   const ConeSlack& slack, Sink& sink) {
  const FeatureNumbering keys = core.numbering();
  const double r = core.dilation();
  const bool caps = core.cap_reach() >= cone_reach(slack);
  return for_each_face_near_plane(
      core, origin, n, r,
      [&](int f) {
        const CoreFace& face = core.face(f);
        for (int k = 0; k < 3; ++k) {
          const int v = face.vertex[k];
          if (core.vertex(v).owner != f)
            continue;
          const Vec3 x = core.vertex(v).position;
          const double height = dot(x - origin, n);
          const double cone_weight = dilated::vertex_cone_weight(core, v, -n, slack);
          if (!(height < r) || !(cone_weight > 0))
            continue;
          FeatureContact contact;
          contact.cone_weight = cone_weight;
          contact.overlap = r - height;
          contact.normal = n;
          contact.point = x - (0.5 * (r + height)) * n;
          contact.feature_a = keys.vertex(v);
          contact.feature_b = 0;
          sink.add(contact);
        }
      },
      caps);
}

// The contacts of a dilated core with the inside of a cylinder (axis through `base` along the
// unit `axis`, `radius`, `length` from the base; in the core's frame): its convex vertices within
// the length whose distance to the curved wall is below the dilation and whose cone holds the
// outward radial direction (feature_b = 0). The farthest point of a face or an edge from the axis
// is one of its vertices, so vertices are every local minimum there.
template <class Core, class Sink>
KOKKOS_INLINE_FUNCTION bool dilated_cylinder_contacts(const Core& core, Vec3 base, Vec3 axis,
                                                      double radius, double length,
                                                      const ConeSlack& slack, Sink& sink) {
  const FeatureNumbering keys = core.numbering();
  const double r = core.dilation();
  const auto radial = [&](Vec3 x) {
    const Vec3 from_base = x - base;
    return from_base - dot(from_base, axis) * axis;
  };
  const auto near_wall = [&](const SphereNode& node) {
    return radius - norm(radial(node.centre)) < node.radius + r;
  };
  return for_each_face_where(core, near_wall, [&](int f) {
    const CoreFace& face = core.face(f);
    for (int k = 0; k < 3; ++k) {
      const int v = face.vertex[k];
      if (core.vertex(v).owner != f)
        continue;
      const Vec3 x = core.vertex(v).position;
      const double along = dot(x - base, axis);
      const Vec3 out = radial(x);
      const double rho = norm(out);
      const double gap = radius - rho;
      if (!(gap < r) || !(along >= 0 && along <= length) || !(rho > 0))
        continue;
      const Vec3 outward = (1.0 / rho) * out;
      const double cone_weight = dilated::vertex_cone_weight(core, v, outward, slack);
      if (!(cone_weight > 0))
        continue;
      FeatureContact contact;
      contact.cone_weight = cone_weight;
      contact.overlap = r - gap;
      contact.normal = -outward;
      contact.point = x + (0.5 * (r + gap)) * outward;
      contact.feature_a = keys.vertex(v);
      contact.feature_b = 0;
      sink.add(contact);
    }
  });
}

} // namespace kdem
