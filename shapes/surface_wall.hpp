#pragma once
// Convex bodies against walls, written against the posed-surface concept of
// implicit_surface.hpp (with its support point and body box): the contact geometry against
// planes, triangles (face, edge, vertex, with a rule that gives one contact per touched mesh
// feature) and the inside of cylinders. A superquadric (PosedSuperquadric) is one such body;
// poly-superquadric octants and clump elements are others.
// Host and device code: no exceptions, no recursion, no dynamic memory.
#include "implicit_surface.hpp"
#include "mat3.hpp"
#include "sphere.hpp"

namespace kdem {

// One particle-wall contact. geometry.normal is the unit normal on the particle, pointing from
// the wall to the particle (the force on the particle is +F_n normal); geometry.point lies midway
// between the particle point deepest in the wall and the wall.
struct SurfaceWallContact {
  ContactGeometry geometry;
  double curvature = 0; // 1/m, mean curvature of the particle surface at its deepest point
  // 0: face (planes and cylinders too); 1..3: edges ab, bc, ca; 4..6: vertices a, b, c.
  // -1: this triangle reports no feature for the particle (another triangle may).
  int feature = -1;
  Vec3 deepest_point; // the particle surface point deepest in the wall
};

// Body-frame components of a direction below this fraction of its largest component are the
// rounding of the rotation (a few 1e-16) and are set to zero: a flat face lying on a wall (the
// direction along a body axis up to rounding) then gets its support point at the face's centre
// rather than moved by (1e-16)^(1/(n - 1)) of the size (5e-3 for n = 8) towards an edge, which
// would give the contact force a spurious lever arm.
constexpr double rotation_rounding = 1e-14;

template <class Surface>
KOKKOS_INLINE_FUNCTION Vec3 direction_to_local(const Surface& p, Vec3 world) {
  Vec3 local = transpose_times(p.rotation, world);
  const double largest =
      math::max(math::fabs(local.x), math::max(math::fabs(local.y), math::fabs(local.z)));
  const double noise = rotation_rounding * largest;
  if (math::fabs(local.x) < noise)
    local.x = 0;
  if (math::fabs(local.y) < noise)
    local.y = 0;
  if (math::fabs(local.z) < noise)
    local.z = 0;
  return local;
}

// World-frame point of the particle furthest along the world direction.
template <class Surface>
KOKKOS_INLINE_FUNCTION Vec3 support_point_world(const Surface& p, Vec3 direction) {
  return p.to_world(p.support_local(direction_to_local(p, direction)));
}

// --- One-dimensional solvers --------------------------------------------------------------------

constexpr int wall_solver_iterations = 100;

// Root of f on [lo, hi] with f(lo) < 0 <= f(hi), f increasing there: Newton from `x`, replaced
// by bisection when a step leaves the bracket or does not halve the step before last (the
// safeguard of rtsafe, Press et al., Numerical Recipes, 9.4). Stops when the step or the bracket
// is below `tolerance`; the bracket halves at least every other iteration.
// `f(x, value, slope)` evaluates the function and its derivative.
template <class Function>
KOKKOS_INLINE_FUNCTION double bracketed_newton_root(const Function& f, double lo, double hi,
                                                    double x, double tolerance) {
  double step_before_last = hi - lo, last_step = step_before_last;
  for (int iteration = 0; iteration < wall_solver_iterations; ++iteration) {
    double value = 0, slope = 0;
    f(x, value, slope);
    if (value == 0)
      return x;
    if (value < 0)
      lo = x;
    else
      hi = x;
    const double newton = x - value / slope;
    const bool use_newton = slope > 0 && newton > lo && newton < hi &&
                            math::fabs(2.0 * value) <= math::fabs(step_before_last * slope);
    const double next = use_newton ? newton : 0.5 * (lo + hi);
    step_before_last = last_step;
    last_step = next - x;
    x = next;
    if (math::fabs(last_step) <= tolerance || hi - lo <= tolerance)
      return x;
  }
  return x;
}

// Parameter interval [t0, t1] (narrowed in place) of start + t step inside the body-frame box
// of the particle, which contains it; false when empty.
KOKKOS_INLINE_FUNCTION bool clip_to_bounding_box(const BodyBox& box, Vec3 start, Vec3 step,
                                                 double& t0, double& t1) {
  for (int k = 0; k < 3; ++k) {
    if (step[k] == 0) {
      if (start[k] < box.lo[k] || start[k] > box.hi[k])
        return false;
      continue;
    }
    const double enter = (box.lo[k] - start[k]) / step[k], leave = (box.hi[k] - start[k]) / step[k];
    t0 = math::max(t0, math::min(enter, leave));
    t1 = math::min(t1, math::max(enter, leave));
  }
  return t0 <= t1;
}

// Half the widths of the body box along the body axes (the semi-axes of a superquadric).
KOKKOS_INLINE_FUNCTION Vec3 half_widths(const BodyBox& box) {
  return 0.5 * (box.hi - box.lo);
}

KOKKOS_INLINE_FUNCTION double largest_half_width(const BodyBox& box) {
  const Vec3 h = half_widths(box);
  return math::max(h.x, math::max(h.y, h.z));
}

// Positions are resolved to this fraction of the particle size (a few rounding units).
constexpr double wall_length_tolerance = 1e-15;

// F along a body-frame line: value and slope for the root of F (depth along a direction).
template <class Surface> struct ShapeAlongLine {
  const Surface& shape;
  Vec3 start, step;
  KOKKOS_INLINE_FUNCTION void operator()(double t, double& value, double& slope) const {
    const ShapeFunction f = shape.template local<false>(start + t * step);
    value = f.value;
    slope = dot(f.gradient, step);
  }
};

// d/dt F along a body-frame line and its derivative: the minimiser of F is the root (F is convex).
template <class Surface> struct ShapeSlopeAlongLine {
  const Surface& shape;
  Vec3 start, step;
  KOKKOS_INLINE_FUNCTION void operator()(double t, double& value, double& slope) const {
    const ShapeFunction f = shape.template local<true>(start + t * step);
    value = dot(f.gradient, step);
    slope = dot(step, f.hessian * step);
  }
};

// Distance from a body-frame point inside the particle to its surface along the unit direction.
// F is convex, negative at the point and increasing along an outward direction, so the root is
// unique; the bracket ends where the ray leaves the bounding box, where F >= 0.
template <class Surface>
KOKKOS_INLINE_FUNCTION double depth_to_surface(const Surface& s, Vec3 inside, Vec3 unit_direction) {
  const BodyBox box = s.local_box();
  const Vec3 half = half_widths(box);
  double t0 = 0, t1 = 4.0 * (half.x + half.y + half.z);
  if (!clip_to_bounding_box(box, inside, unit_direction, t0, t1))
    return 0;
  const ShapeAlongLine<Surface> line{s, inside, unit_direction};
  return bracketed_newton_root(line, 0.0, t1, 0.0, wall_length_tolerance * largest_half_width(box));
}

// Parameter in [0, 1] of the point of the body-frame segment start + t (end - start) where F is
// smallest, or -1 when the segment misses the bounding box (F > 0 all along it).
template <class Surface>
KOKKOS_INLINE_FUNCTION double segment_minimiser(const Surface& s, Vec3 start, Vec3 end) {
  const Vec3 step = end - start;
  const BodyBox box = s.local_box();
  double t0 = 0, t1 = 1;
  if (!clip_to_bounding_box(box, start, step, t0, t1))
    return -1;
  const ShapeSlopeAlongLine<Surface> slope{s, start, step};
  double value = 0, curvature = 0;
  slope(t0, value, curvature);
  if (value >= 0)
    return t0;
  slope(t1, value, curvature);
  if (value <= 0)
    return t1;
  const double tolerance = wall_length_tolerance * largest_half_width(box) / norm(step);
  return bracketed_newton_root(slope, t0, t1, 0.5 * (t0 + t1), tolerance);
}

// --- Contacts from a particle point
// ----------------------------------------------------------------

template <class Surface>
KOKKOS_INLINE_FUNCTION void set_contact(const Surface& p, SurfaceWallContact& c,
                                        Vec3 wall_point_local, Vec3 outward_local, double depth) {
  const Vec3 deepest_local = wall_point_local + depth * outward_local;
  c.deepest_point = p.to_world(deepest_local);
  if (!(depth > 0))
    return;
  c.geometry.touching = true;
  c.geometry.overlap = depth;
  c.geometry.normal = -(p.rotation * outward_local);
  c.geometry.point = p.to_world(wall_point_local + (0.5 * depth) * outward_local);
  c.curvature = mean_curvature(p.template local<true>(deepest_local));
}

// Contact of a wall point (on an edge or a vertex) inside the particle: the normal is the
// particle's outward normal there, without its component along the edge (zero for a vertex),
// and the overlap is the distance from the point to the surface along it (book Sect. 2.2.2 as
// reconstructed, steps e3, e4). `free_normal` is the wall normal used when the gradient vanishes
// (the point at the particle centre).
template <class Surface>
KOKKOS_INLINE_FUNCTION SurfaceWallContact wall_point_contact(const Surface& p, Vec3 point_local,
                                                             Vec3 edge_local, Vec3 free_normal,
                                                             int feature) {
  SurfaceWallContact c;
  c.feature = feature;
  c.deepest_point = p.to_world(point_local);
  const ShapeFunction f = p.template local<false>(point_local);
  if (!(f.value < 0))
    return c;
  Vec3 outward = f.gradient;
  const double edge_length2 = norm2(edge_local);
  if (edge_length2 > 0)
    outward -= (dot(outward, edge_local) / edge_length2) * edge_local;
  const double length = norm(outward);
  outward = length > 0 ? (1.0 / length) * outward : direction_to_local(p, -free_normal);
  set_contact(p, c, point_local, outward, depth_to_surface(p, point_local, outward));
  return c;
}

// The point of the edge segment uv where F is smallest (found to the length tolerance above),
// taken as a contact point.
template <class Surface>
KOKKOS_INLINE_FUNCTION SurfaceWallContact surface_edge_contact(const Surface& p, Vec3 u, Vec3 v,
                                                               Vec3 free_normal, int feature) {
  const Vec3 start = p.to_local(u), end = p.to_local(v);
  const double t = segment_minimiser(p, start, end);
  if (t < 0) {
    SurfaceWallContact c;
    c.feature = feature;
    return c;
  }
  return wall_point_contact(p, start + t * (end - start), end - start, free_normal, feature);
}

template <class Surface>
KOKKOS_INLINE_FUNCTION SurfaceWallContact surface_vertex_contact(const Surface& p, Vec3 vertex,
                                                                 Vec3 free_normal, int feature) {
  return wall_point_contact(p, p.to_local(vertex), Vec3{0, 0, 0}, free_normal, feature);
}

// --- Plane
// ----------------------------------------------------------------------------------------

// Plane through `origin` with unit normal `free_normal` pointing to the particle's side: the
// deepest particle point is the support point in -free_normal (book Eqs. 2.11-2.13). Compiled
// once (KDEM_ONE_COPY_FUNCTION), so that a mesh face's contact is a plane wall's bit for bit.
template <class Surface>
KDEM_ONE_COPY_FUNCTION SurfaceWallContact surface_plane_contact(const Surface& p, Vec3 plane_origin,
                                                                Vec3 free_normal) {
  SurfaceWallContact c;
  c.feature = 0;
  const Vec3 deepest_local = p.support_local(direction_to_local(p, -free_normal));
  c.deepest_point = p.to_world(deepest_local);
  const double height = dot(c.deepest_point - plane_origin, free_normal);
  if (!(height < 0))
    return c;
  c.geometry.touching = true;
  c.geometry.overlap = -height;
  c.geometry.normal = free_normal;
  c.geometry.point = c.deepest_point - (0.5 * height) * free_normal;
  c.curvature = mean_curvature(p.template local<true>(deepest_local));
  return c;
}

// --- Triangles and meshes
// ---------------------------------------------------------------------------
//
// One contact per touched mesh feature. F + 1 is positively homogeneous, so the level sets of F
// are copies of the particle scaled about its centre, and the point of a wall where F is smallest
// is where the smallest scaled copy touches it. Every triangle, edge and vertex reports when that
// point of the local mesh surface lies on it; the tests are the optimality conditions of that
// minimum, written so that two triangles evaluating the same condition use the same numbers:
// - face: the minimiser of F over the triangle's plane lies in the triangle, tested edge by edge
//   in a canonical (lexicographic) vertex order with a half-open rule, so that across a shared
//   edge of a plane exactly one of the two triangles contains it (also on the edge and at inner
//   vertices). The contact is then the plane contact (book Eqs. 2.11-2.19).
// - edge (its owner reports): F falls from both ends into the edge, and the plane minimiser of
//   each adjacent face lies beyond the edge (the face test's own edge condition, negated). A
//   shared edge between coplanar faces therefore never reports: the faces cover it.
// - vertex (its owner reports, if the vertex is a corner): F falls along no edge leaving it, and
//   no face around it that the owner knows reports.
// Needs: triangles in one plane store the same normal bits (the support point of a blocky
// particle lying flat moves by (1e-16)^(1/(n-1)) of its size with the last bit of the normal),
// and the tests compiled once (view_face, minimiser_inside_edge, descends_from: see
// KDEM_ONE_COPY_FUNCTION), so that every triangle's call rounds alike.

// What a triangle knows about the mesh around it, filled once per mesh by the caller. Edge k joins
// vertices k and k + 1 (ab, bc, ca); vertex k is a, b, c.
struct TriangleNeighbourhood {
  Vec3 normal; // unit, as stored by the mesh; triangles in one plane store identical bits
  bool owns_edge[3] = {true, true, true}; // exactly one triangle per edge owns it
  bool has_neighbour[3] = {false, false, false};
  Vec3 neighbour_normal[3];   // the stored normal of the triangle across edge k
  Vec3 neighbour_opposite[3]; // its vertex off edge k
  // Owner of vertex k (one per vertex), and the vertex is a corner: on the mesh boundary or where
  // the faces around it are not all coplanar. False for the inner vertices of a flat patch.
  bool reports_vertex[3] = {true, true, true};
  // All vertices joined to vertex k by an edge, where the vertex has more of them than this
  // triangle and its neighbours across its two edges at k know; null: those are all.
  const Vec3* vertex_ring[3] = {nullptr, nullptr, nullptr};
  int vertex_ring_size[3] = {0, 0, 0};
};

// A triangle on its own: owns everything, no neighbours.
KOKKOS_INLINE_FUNCTION TriangleNeighbourhood isolated_triangle(Vec3 a, Vec3 b, Vec3 c) {
  TriangleNeighbourhood t;
  const Vec3 n = cross(b - a, c - a);
  t.normal = (1.0 / norm(n)) * n;
  return t;
}

KOKKOS_INLINE_FUNCTION bool lexicographically_before(Vec3 p, Vec3 q) {
  if (p.x != q.x)
    return p.x < q.x;
  if (p.y != q.y)
    return p.y < q.y;
  return p.z < q.z;
}

KOKKOS_INLINE_FUNCTION Vec3 lexicographic_first(Vec3 u, Vec3 v, Vec3 w) {
  const Vec3 first = lexicographically_before(u, v) ? u : v;
  return lexicographically_before(first, w) ? first : w;
}

// A face seen from the particle: its normal turned to the particle's side, the particle point
// deepest towards it, and the particle's extent from its centre down to that point.
struct FaceView {
  Vec3 normal;
  Vec3 support;
  double extent = 0;
};

template <class Surface>
KDEM_ONE_COPY_FUNCTION FaceView view_face(const Surface& p, Vec3 stored_normal, Vec3 u, Vec3 v,
                                          Vec3 w) {
  FaceView f;
  const double side = dot(p.centre - lexicographic_first(u, v, w), stored_normal);
  f.normal = side >= 0 ? stored_normal : -stored_normal;
  f.support = support_point_world(p, -f.normal);
  f.extent = dot(p.centre - f.support, f.normal);
  return f;
}

// The point where the scaled copy of the particle through its support point touches the face's
// plane, which minimises F over the plane: centre + (height / extent) (support - centre), the
// height measured from `on_plane`, a point of the plane.
template <class Surface>
KOKKOS_INLINE_FUNCTION Vec3 plane_minimiser(const Surface& p, const FaceView& f, Vec3 on_plane) {
  const double height = math::max(dot(p.centre - on_plane, f.normal), 0.0);
  const double scale = f.extent > 0 ? height / f.extent : 0.0;
  return p.centre + scale * (f.support - p.centre);
}

// Whether the minimiser of F over the face's plane lies on the triangle's side of edge uv
// (w: the triangle's third vertex). The edge runs from its lexicographically first vertex, and a
// point exactly on it belongs to the triangle on its left. Two coplanar triangles of the edge
// compute the same side with opposite signs of their third vertex, so exactly one contains the
// point. At an inner vertex of a plane, the neighbours after it in that order fill one
// half-plane, so exactly one triangle of its fan has the point on its side of both its edges
// there. That needs every edge at the vertex to see the same minimiser at the same offset from
// it: the minimiser is measured from the edge's end nearer to it (the first end on a tie), so
// near a vertex every edge there measures from the vertex, and the small offset is a difference
// of nearby doubles, exact. Measured from the far end, the offset would differ from the edge by
// a rounding, whose cross product with the edge a fused multiply-add does not cancel.
template <class Surface>
KDEM_ONE_COPY_FUNCTION bool minimiser_inside_edge(const Surface& p, const FaceView& f, Vec3 u,
                                                  Vec3 v, Vec3 w) {
  const bool forward = lexicographically_before(u, v);
  const Vec3 first = forward ? u : v, second = forward ? v : u;
  const Vec3 edge = second - first;
  const Vec3 from_first = plane_minimiser(p, f, first);
  const bool nearer_second = norm2(from_first - second) < norm2(from_first - first);
  const Vec3 anchor = nearer_second ? second : first;
  const Vec3 minimiser = nearer_second ? plane_minimiser(p, f, second) : from_first;
  // cross(edge, m - second) = cross(edge, m - first): the side of the same directed edge.
  const bool left = dot(cross(edge, minimiser - anchor), f.normal) >= 0;
  return left == (dot(cross(edge, w - first), f.normal) > 0);
}

template <class Surface>
KOKKOS_INLINE_FUNCTION bool face_reports(const Surface& p, const FaceView& f, Vec3 a, Vec3 b,
                                         Vec3 c) {
  return minimiser_inside_edge(p, f, a, b, c) && minimiser_inside_edge(p, f, b, c, a) &&
         minimiser_inside_edge(p, f, c, a, b);
}

// F decreases from `from` towards `to` (the same numbers wherever the pair is evaluated).
template <class Surface>
KDEM_ONE_COPY_FUNCTION bool descends_from(const Surface& p, Vec3 from, Vec3 to) {
  const Vec3 start = p.to_local(from);
  return dot(p.template local<false>(start).gradient, p.to_local(to) - start) < 0;
}

template <class Surface>
KOKKOS_INLINE_FUNCTION bool edge_reports(const Surface& p, const FaceView& own,
                                         const Vec3 (&vertex)[3], const TriangleNeighbourhood& t,
                                         int k) {
  const Vec3 u = vertex[k], v = vertex[(k + 1) % 3], w = vertex[(k + 2) % 3];
  if (minimiser_inside_edge(p, own, u, v, w))
    return false;
  if (t.has_neighbour[k]) {
    const Vec3 other = t.neighbour_opposite[k];
    if (minimiser_inside_edge(p, view_face(p, t.neighbour_normal[k], u, v, other), u, v, other))
      return false;
  }
  return descends_from(p, u, v) && descends_from(p, v, u);
}

template <class Surface>
KOKKOS_INLINE_FUNCTION bool vertex_reports(const Surface& p, const Vec3 (&vertex)[3],
                                           const TriangleNeighbourhood& t, int k) {
  const Vec3 corner = vertex[k];
  const int edges_at_corner[2] = {k, (k + 2) % 3};
  if (descends_from(p, corner, vertex[(k + 1) % 3]) ||
      descends_from(p, corner, vertex[(k + 2) % 3]))
    return false;
  for (int i = 0; i < t.vertex_ring_size[k]; ++i)
    if (t.vertex_ring[k] && descends_from(p, corner, t.vertex_ring[k][i]))
      return false;
  for (int e : edges_at_corner) {
    if (!t.has_neighbour[e])
      continue;
    const Vec3 u = vertex[e], v = vertex[(e + 1) % 3], other = t.neighbour_opposite[e];
    if (descends_from(p, corner, other) ||
        face_reports(p, view_face(p, t.neighbour_normal[e], u, v, other), u, v, other))
      return false;
  }
  return true;
}

// Contact of a particle with triangle abc of a mesh (a two-sided wall): the face, edge or vertex
// this triangle reports under the rule above (feature -1 if none), and whether it touches.
template <class Surface>
KOKKOS_INLINE_FUNCTION SurfaceWallContact surface_triangle_contact(const Surface& p, Vec3 a, Vec3 b,
                                                                   Vec3 c,
                                                                   const TriangleNeighbourhood& t) {
  const Vec3 vertex[3] = {a, b, c};
  const FaceView own = view_face(p, t.normal, a, b, c);
  if (face_reports(p, own, a, b, c))
    return surface_plane_contact(p, a, own.normal);
  for (int k = 0; k < 3; ++k)
    if (t.owns_edge[k] && edge_reports(p, own, vertex, t, k))
      return surface_edge_contact(p, vertex[k], vertex[(k + 1) % 3], own.normal, 1 + k);
  for (int k = 0; k < 3; ++k)
    if (t.reports_vertex[k] && vertex_reports(p, vertex, t, k))
      return surface_vertex_contact(p, vertex[k], own.normal, 4 + k);
  return SurfaceWallContact{};
}

// --- Inside of a cylinder
// ---------------------------------------------------------------------------

// A unit vector perpendicular to the unit vector `axis`.
KOKKOS_INLINE_FUNCTION Vec3 perpendicular_to(Vec3 axis) {
  const double ax = math::fabs(axis.x), ay = math::fabs(axis.y), az = math::fabs(axis.z);
  const Vec3 helper =
      ax <= ay && ax <= az ? Vec3{1, 0, 0} : (ay <= az ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  const Vec3 p = cross(axis, helper);
  return (1.0 / norm(p)) * p;
}

struct RadialFrame {
  Vec3 origin, first, second; // first, second: orthonormal, perpendicular to the axis
};

KOKKOS_INLINE_FUNCTION Vec3 radial_direction(const RadialFrame& f, double angle) {
  return math::cos(angle) * f.first + math::sin(angle) * f.second;
}

// How far the particle reaches from the axis in the radial direction at `angle`: the support
// function, whose maximum over the angle is the particle's largest distance from the axis.
template <class Surface>
KOKKOS_INLINE_FUNCTION double radial_reach(const Surface& p, const RadialFrame& f, double angle) {
  const Vec3 d = radial_direction(f, angle);
  return dot(support_point_world(p, d) - f.origin, d);
}

constexpr int cylinder_scan_samples = 16;
constexpr double cylinder_angle_tolerance = 1e-9; // rad: the reach is flat there, error ~1e-18

// Particle inside a cylinder of the given radius (a drum or silo wall). The furthest particle
// point from the axis maximises the support function over the radial directions:
//   max_x |x_perp| = max_angle max_x d(angle) . x.
// The angles the particle can span are scanned and the best bracket refined by golden-section
// search to cylinder_angle_tolerance. Overlap = that distance - radius.
template <class Surface>
KOKKOS_INLINE_FUNCTION SurfaceWallContact
surface_inside_cylinder_contact(const Surface& p, Vec3 axis_point, Vec3 unit_axis, double radius) {
  const Vec3 offset = p.centre - axis_point;
  const Vec3 radial = offset - dot(offset, unit_axis) * unit_axis;
  const double centre_distance = norm(radial);
  const double bound = p.reach();
  RadialFrame frame;
  frame.origin = axis_point;
  frame.first = centre_distance > 1e-12 * bound ? (1.0 / centre_distance) * radial
                                                : perpendicular_to(unit_axis);
  frame.second = cross(unit_axis, frame.first);
  // asin(x) <= x pi / 2 on [0, 1]: the window covers every direction that meets the particle.
  const double half_window =
      centre_distance > bound ? math::min(pi, 0.5 * pi * bound / centre_distance) : pi;
  const double spacing = 2.0 * half_window / (cylinder_scan_samples - 1);
  int best = 0;
  double best_reach = -1e300;
  for (int i = 0; i < cylinder_scan_samples; ++i) {
    const double reach = radial_reach(p, frame, -half_window + i * spacing);
    if (reach > best_reach)
      best_reach = reach, best = i;
  }
  const double golden = 0.6180339887498949;
  double lo = -half_window + (best - 1) * spacing, hi = lo + 2.0 * spacing;
  double left = hi - golden * (hi - lo), right = lo + golden * (hi - lo);
  double left_reach = radial_reach(p, frame, left), right_reach = radial_reach(p, frame, right);
  for (int iteration = 0; iteration < wall_solver_iterations && hi - lo > cylinder_angle_tolerance;
       ++iteration) {
    if (left_reach < right_reach) {
      lo = left, left = right, left_reach = right_reach;
      right = lo + golden * (hi - lo), right_reach = radial_reach(p, frame, right);
    } else {
      hi = right, right = left, right_reach = left_reach;
      left = hi - golden * (hi - lo), left_reach = radial_reach(p, frame, left);
    }
  }
  const double angle = left_reach > right_reach ? left : right;
  const Vec3 deepest_local = p.support_local(direction_to_local(p, radial_direction(frame, angle)));
  SurfaceWallContact c;
  c.feature = 0;
  c.deepest_point = p.to_world(deepest_local);
  const Vec3 out = c.deepest_point - axis_point;
  const Vec3 out_radial = out - dot(out, unit_axis) * unit_axis;
  const double distance = norm(out_radial);
  if (!(distance > radius))
    return c;
  const Vec3 outward = (1.0 / distance) * out_radial;
  c.geometry.touching = true;
  c.geometry.overlap = distance - radius;
  c.geometry.normal = -outward;
  c.geometry.point = c.deepest_point - (0.5 * c.geometry.overlap) * outward;
  c.curvature = mean_curvature(p.template local<true>(deepest_local));
  return c;
}

} // namespace kdem
