#pragma once
// Distance between two convex bodies known only by their support points (GJK: Gilbert, Johnson
// and Keerthi 1988, with the closest point of each simplex found by Voronoi regions as in
// Ericson, Real-Time Collision Detection, Sect. 5.1), with the two closest points. Host and
// device. A support is a callable support(d) returning a body point furthest along d (d need not
// be unit).
//
// Each iteration adds the support point w of A - B along -v, v being the point of the current
// simplex nearest the origin; |v| - v.w/|v| bounds the error of |v| as the distance (v.w/|v| is
// the separation of the two bodies along v), so the loop stops when it falls below the
// tolerance. The bodies intersect when the simplex comes to hold the origin.
#include "math.hpp"
#include "vec3.hpp"

namespace kdem {

struct ConvexDistance {
  bool intersecting = false;
  double distance = 0;   // when apart, within the tolerance
  Vec3 point_a, point_b; // the closest points when apart
  int iterations = 0;
  int status = 0; // 0 converged, 2 the iterations ran out (the last simplex's result kept)
  // Apart beyond the controls' cutoff: `distance` is a lower bound, the points are not set.
  KOKKOS_INLINE_FUNCTION bool beyond(double cutoff) const {
    return !intersecting && distance >= cutoff;
  }
};

struct ConvexDistanceControls {
  double tolerance = 1e-12; // m, on the distance
  int max_iterations = 64;
  // m: once the bodies are known to be at least this far apart the search stops, with that lower
  // bound as the distance (a contact search needs no more).
  double cutoff = 1e300;
};

namespace gjk {

// A vertex of the simplex in A - B, with the points of A and B that make it.
struct Vertex {
  Vec3 w, a, b;
};

// A simplex of up to four vertices with the barycentric weights of its point nearest the origin
// (set by the nearest_* functions, which keep only the vertices that carry weight).
struct Simplex {
  Vertex vertex[4];
  double weight[4] = {0, 0, 0, 0};
  int count = 0;

  KOKKOS_INLINE_FUNCTION Vec3 point() const {
    Vec3 v;
    for (int k = 0; k < count; ++k)
      v += weight[k] * vertex[k].w;
    return v;
  }
};

KOKKOS_INLINE_FUNCTION Simplex one(const Vertex& a) {
  Simplex s;
  s.vertex[0] = a;
  s.weight[0] = 1;
  s.count = 1;
  return s;
}

KOKKOS_INLINE_FUNCTION Simplex two(const Vertex& a, const Vertex& b, double t) {
  Simplex s;
  s.vertex[0] = a, s.vertex[1] = b;
  s.weight[0] = 1 - t, s.weight[1] = t;
  s.count = 2;
  return s;
}

KOKKOS_INLINE_FUNCTION Simplex nearest_on_segment(const Vertex& a, const Vertex& b) {
  const Vec3 ab = b.w - a.w;
  const double length2 = norm2(ab);
  if (!(length2 > 0))
    return one(a);
  const double t = -dot(a.w, ab) / length2;
  if (t <= 0)
    return one(a);
  if (t >= 1)
    return one(b);
  return two(a, b, t);
}

// The point of triangle abc nearest the origin (Ericson's ClosestPtPointTriangle with p = 0); a
// degenerate (collinear) triangle gives the nearest of its edges' points.
KOKKOS_INLINE_FUNCTION Simplex nearest_on_triangle(const Vertex& a, const Vertex& b,
                                                   const Vertex& c) {
  const Vec3 ab = b.w - a.w, ac = c.w - a.w;
  const double d1 = -dot(ab, a.w), d2 = -dot(ac, a.w);
  if (d1 <= 0 && d2 <= 0)
    return one(a);
  const double d3 = -dot(ab, b.w), d4 = -dot(ac, b.w);
  if (d3 >= 0 && d4 <= d3)
    return one(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return two(a, b, d1 / (d1 - d3));
  const double d5 = -dot(ab, c.w), d6 = -dot(ac, c.w);
  if (d6 >= 0 && d5 <= d6)
    return one(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return two(a, c, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return two(b, c, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    Simplex best = nearest_on_segment(a, b);
    const Simplex candidates[2] = {nearest_on_segment(b, c), nearest_on_segment(a, c)};
    for (const Simplex& s : candidates)
      if (norm2(s.point()) < norm2(best.point()))
        best = s;
    return best;
  }
  Simplex s;
  s.vertex[0] = a, s.vertex[1] = b, s.vertex[2] = c;
  s.weight[1] = vb / sum, s.weight[2] = vc / sum;
  s.weight[0] = 1 - s.weight[1] - s.weight[2];
  s.count = 3;
  return s;
}

// Whether the origin lies on the other side of plane abc than d, or on it; a flat tetrahedron
// (d on the plane) counts every face as facing the origin.
KOKKOS_INLINE_FUNCTION bool faces_origin(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const Vec3 n = cross(b - a, c - a);
  return -dot(a, n) * dot(d - a, n) <= 0;
}

// The point of tetrahedron abcd nearest the origin; `inside` when it holds the origin.
KOKKOS_INLINE_FUNCTION Simplex nearest_on_tetrahedron(const Vertex& a, const Vertex& b,
                                                      const Vertex& c, const Vertex& d,
                                                      bool& inside) {
  inside = true;
  Simplex best;
  double best2 = 0;
  const auto consider = [&](const Vertex& p, const Vertex& q, const Vertex& r, const Vertex& s) {
    if (!faces_origin(p.w, q.w, r.w, s.w))
      return;
    const Simplex candidate = nearest_on_triangle(p, q, r);
    const double candidate2 = norm2(candidate.point());
    if (inside || candidate2 < best2) {
      best = candidate;
      best2 = candidate2;
    }
    inside = false;
  };
  consider(a, b, c, d);
  consider(a, c, d, b);
  consider(a, d, b, c);
  consider(b, d, c, a);
  return best;
}

KOKKOS_INLINE_FUNCTION Simplex nearest(const Simplex& s, bool& inside) {
  inside = false;
  if (s.count == 1)
    return one(s.vertex[0]);
  if (s.count == 2)
    return nearest_on_segment(s.vertex[0], s.vertex[1]);
  if (s.count == 3)
    return nearest_on_triangle(s.vertex[0], s.vertex[1], s.vertex[2]);
  return nearest_on_tetrahedron(s.vertex[0], s.vertex[1], s.vertex[2], s.vertex[3], inside);
}

// The largest distance of a simplex vertex from the origin: the scale of its rounding.
KOKKOS_INLINE_FUNCTION double simplex_size(const Simplex& s) {
  double largest2 = 0;
  for (int k = 0; k < s.count; ++k)
    largest2 = math::max(largest2, norm2(s.vertex[k].w));
  return math::sqrt(largest2);
}

} // namespace gjk

// The distance between convex bodies A and B, starting from a guess of the direction from B to A
// (e.g. centre of A minus centre of B).
template <class SupportA, class SupportB>
KOKKOS_INLINE_FUNCTION ConvexDistance convex_distance(const SupportA& support_a,
                                                      const SupportB& support_b, Vec3 guess,
                                                      const ConvexDistanceControls& controls) {
  using namespace gjk;
  ConvexDistance result;
  Vec3 v = norm2(guess) > 0 ? guess : Vec3{1, 0, 0};
  Simplex simplex;
  double best2 = 1e300;
  result.status = 2;
  for (int iteration = 1; iteration <= controls.max_iterations; ++iteration) {
    result.iterations = iteration;
    Vertex w;
    w.a = support_a(-v);
    w.b = support_b(v);
    w.w = w.a - w.b;
    if (simplex.count > 0) {
      const double length = math::sqrt(best2);
      const double separation = dot(v, w.w) / length; // a lower bound on the distance
      if (separation >= controls.cutoff) {
        result.status = 0;
        result.distance = separation;
        return result;
      }
      if (length - separation <= controls.tolerance) {
        result.status = 0;
        break;
      }
    }
    simplex.vertex[simplex.count++] = w;
    bool inside = false;
    const Simplex reduced = nearest(simplex, inside);
    const Vec3 next = reduced.point();
    const double next2 = norm2(next);
    // The origin on the simplex to rounding (a segment or triangle through it) counts as inside.
    const double touching = 1e-14 * simplex_size(simplex);
    if (inside || !(next2 > touching * touching)) {
      result.intersecting = true;
      result.status = 0;
      return result;
    }
    if (simplex.count > 1 && !(next2 < best2)) {
      result.status = 0; // no progress: v is as near as the arithmetic allows
      break;
    }
    simplex = reduced;
    v = next;
    best2 = next2;
  }
  result.distance = math::sqrt(best2);
  for (int k = 0; k < simplex.count; ++k) {
    result.point_a += simplex.weight[k] * simplex.vertex[k].a;
    result.point_b += simplex.weight[k] * simplex.vertex[k].b;
  }
  return result;
}

// The support of a triangle (any of its corners furthest along d).
struct TriangleSupport {
  Vec3 corner[3];
  KOKKOS_INLINE_FUNCTION Vec3 operator()(Vec3 d) const {
    int best = 0;
    double reach = dot(corner[0], d);
    for (int k = 1; k < 3; ++k) {
      const double r = dot(corner[k], d);
      if (r > reach)
        best = k, reach = r;
    }
    return corner[best];
  }
};

} // namespace kdem
