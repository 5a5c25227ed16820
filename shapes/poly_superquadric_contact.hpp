#pragma once
// Narrow phases with poly-superquadrics (book Sect. 3.2.3): the contact problem is handed to the
// basic elements, octant k of a poly-superquadric being solved as the whole superquadric of its
// semi-axes (PosedPolySuperquadric::element), with the midway-point Newton of
// superquadric_contact.hpp and its fallbacks; a solution is accepted only when its point lies in
// the octant of each body that was solved for.
//
// Why one accepted pair is the contact: both bodies are convex with C1 shape functions, so the
// midway point of the whole bodies (the minimiser of max(F_i, F_j)) is unique, and an element
// pair's solution inside its own octants satisfies the whole bodies' conditions there, since
// F = F_k in octant k and the gradients agree across the octant planes. So in exact arithmetic
// exactly one octant pair is accepted (several only for a point on an octant plane, and then they
// give the same point), and a pair of poly-superquadrics has at most one contact.
//
// Which pair is solved: the octants of the start point (the kept midway point, or the midway
// point of the equivalent spheres), then the octants the last solution fell into (a walk that
// ends at the accepted pair, in one solve when the contact stays in its octants, as it does from
// step to step); the walk is kept in a mask so that it never revisits a pair. Where the walk
// fails, every octant pair is solved from the cold start, in a fixed order, and the first
// accepted is taken (counted as a fallback); none accepted is a failure.
//
// The octant test allows a point within a rounding slack of the octant's planes (1e-9 of the
// smallest extent): on the plane the neighbouring pieces agree to first order, and without slack
// a point that rounding puts a hair across the plane would be rejected by both sides. The octant
// chosen for a point is the half-open one of poly_superquadric.hpp.
//
// The surface points, overlap, curvatures and separation bound are the whole bodies' at the
// accepted point (see whole_body_result).
//
// The pieces are solved in the whole bodies' unit of length (the smallest half-width), not in
// their own: the book's hemisphere cap is a piece 1/600 of the body thick, and Newton in its
// thickness moves at most half of it per step, so a contact on the flat face a body size from the
// start was out of reach (12 % of the pair evaluations failed in a pile of such hemispheres).
#include <cstdint>

#include "poly_superquadric.hpp"
#include "superquadric_contact.hpp"

namespace kdem {

namespace piecewise {

constexpr int max_walk = 8;
constexpr double octant_slack = 1e-9; // of the smallest extent, see the header

// A superquadric is a body of one piece; a poly-superquadric one of eight.
KOKKOS_INLINE_FUNCTION int pieces_of(const PosedSuperquadric&) {
  return 1;
}
KOKKOS_INLINE_FUNCTION int pieces_of(const PosedPolySuperquadric&) {
  return octant_count;
}
KOKKOS_INLINE_FUNCTION int piece_at(const PosedSuperquadric&, Vec3) {
  return 0;
}
KOKKOS_INLINE_FUNCTION int piece_at(const PosedPolySuperquadric& body, Vec3 x) {
  return body.octant_at(x);
}
// The whole body's size, the unit of its pieces' solves (NarrowPhaseControls::length).
KOKKOS_INLINE_FUNCTION double body_length(const PosedSuperquadric& body) {
  return body.smallest_length();
}
KOKKOS_INLINE_FUNCTION double body_length(const PosedPolySuperquadric& body) {
  return smallest_half_width(body.shape);
}
// The controls of the pieces' solves: the bodies' unit of length unless one is set.
KOKKOS_INLINE_FUNCTION NarrowPhaseControls piece_controls(NarrowPhaseControls controls,
                                                          double length) {
  if (!(controls.length > 0))
    controls.length = length;
  return controls;
}

KOKKOS_INLINE_FUNCTION PosedSuperquadric piece(const PosedSuperquadric& body, int) {
  return body;
}
KOKKOS_INLINE_FUNCTION PosedSuperquadric piece(const PosedPolySuperquadric& body, int octant) {
  return body.element(octant);
}

// Whether x lies in piece k of the body, within the slack of its octant planes.
KOKKOS_INLINE_FUNCTION bool in_piece(const PosedSuperquadric&, Vec3, int) {
  return true;
}
KOKKOS_INLINE_FUNCTION bool in_piece(const PosedPolySuperquadric& body, Vec3 x, int octant) {
  const Vec3 local = body.to_local(x);
  const Vec3 sign = octant_signs(octant);
  const double slack = octant_slack * body.smallest_length();
  return sign.x * local.x >= -slack && sign.y * local.y >= -slack && sign.z * local.z >= -slack;
}

// Pieces (k_i, k_j) as one number, for the walk's mask.
template <class BodyJ> KOKKOS_INLINE_FUNCTION int piece_pair(int ki, int kj, const BodyJ& j) {
  return ki * pieces_of(j) + kj;
}

// The whole bodies' contact at their midway point x0 (accepted by the octant tests). Where both
// surface points of the element solve lie in its octants, the chord lies in them too (octants are
// convex), where F is the element's: its geometry is the whole bodies'. Otherwise the chord is
// measured again on the whole bodies. The separation bound is always the whole bodies' (it uses
// their reach).
template <class BodyI, class BodyJ>
KOKKOS_INLINE_FUNCTION NarrowPhaseResult whole_body_result(const BodyI& i, const BodyJ& j, int ki,
                                                           int kj, const NarrowPhaseResult& solved,
                                                           int iterations, int status) {
  using namespace narrow_phase;
  const Vec3 x0 = solved.state.point;
  NarrowPhaseResult result = solved;
  result.iterations = iterations;
  result.status = status;
  if (solved.geometry.touching) {
    const Vec3 half = (0.5 * solved.geometry.overlap) * solved.geometry.normal;
    if (in_piece(i, solved.geometry.point - half, ki) &&
        in_piece(j, solved.geometry.point + half, kj))
      return result;
    const ShapeFunction fi = i.template evaluate_with_body_hessian<true>(x0);
    const ShapeFunction fj = j.template evaluate_with_body_hessian<true>(x0);
    const Vec3 normal = unit_or_zero(unit_or_zero(fj.gradient) - unit_or_zero(fi.gradient));
    if (!chord_geometry(i, j, x0, normal, fi, fj, result))
      return failed_result(iterations);
    return result;
  }
  result.separation =
      separation_bound(i, j, x0, i.template evaluate<false>(x0), j.template evaluate<false>(x0));
  return result;
}

} // namespace piecewise

// Two convex bodies of superquadric pieces (poly-superquadric against poly-superquadric or
// superquadric): the walk over octant pairs, then the cold fallback (see the header).
template <class BodyI, class BodyJ>
KDEM_WHOLE_FUNCTION NarrowPhaseResult
piecewise_pair_contact(const BodyI& i, const BodyJ& j, const MidwayState& previous,
                       const NarrowPhaseControls& body_controls) {
  using namespace piecewise;
  const NarrowPhaseControls controls =
      piece_controls(body_controls, math::min(body_length(i), body_length(j)));
  const Vec3 start =
      previous.multiplier > 0 ? previous.point : narrow_phase::sphere_midway_point(i, j);
  int ki = piece_at(i, start), kj = piece_at(j, start);
  MidwayState state = previous;
  std::uint64_t walked = 0;
  int iterations = 0, status = 0;
  for (int step = 0; step < max_walk; ++step) {
    const std::uint64_t bit = std::uint64_t(1) << piece_pair(ki, kj, j);
    if (walked & bit)
      break;
    walked |= bit;
    const NarrowPhaseResult r =
        superquadric_pair_contact(piece(i, ki), piece(j, kj), state, controls);
    iterations += r.iterations;
    if (r.status == 2)
      break;
    status = r.status;
    const Vec3 x = r.state.point;
    if (in_piece(i, x, ki) && in_piece(j, x, kj))
      return whole_body_result(i, j, ki, kj, r, iterations, status);
    state = r.state;
    ki = piece_at(i, x);
    kj = piece_at(j, x);
  }
  if (!controls.use_fallback)
    return narrow_phase::failed_result(iterations);
  for (int a = 0; a < pieces_of(i); ++a)
    for (int b = 0; b < pieces_of(j); ++b) {
      const NarrowPhaseResult r =
          superquadric_pair_contact(piece(i, a), piece(j, b), MidwayState{}, controls);
      iterations += r.iterations;
      if (r.status != 2 && in_piece(i, r.state.point, a) && in_piece(j, r.state.point, b))
        return whole_body_result(i, j, a, b, r, iterations, 1);
    }
  return narrow_phase::failed_result(iterations);
}

// Sphere (body i) against a poly-superquadric: the closest point of an octant's element to the
// centre (sphere_superquadric_contact), accepted when it lies in that octant, by the same walk and
// fallback. An accepted point is the whole body's closest point, with its normal, curvature and
// separation bound: the body lies behind its tangent plane there, F being convex and equal to the
// element's F to first order at the point.
KDEM_WHOLE_FUNCTION NarrowPhaseResult sphere_poly_superquadric_contact(
    Vec3 sphere_centre, double sphere_radius, const PosedPolySuperquadric& j,
    const MidwayState& previous, const NarrowPhaseControls& body_controls) {
  using namespace piecewise;
  const NarrowPhaseControls controls =
      piece_controls(body_controls, math::min(body_length(j), sphere_radius));
  int k = j.octant_at(previous.multiplier > 0 ? previous.point : sphere_centre);
  MidwayState state = previous;
  unsigned walked = 0;
  int iterations = 0, status = 0;
  for (int step = 0; step < max_walk; ++step) {
    if (walked & (1u << k))
      break;
    walked |= 1u << k;
    NarrowPhaseResult r =
        sphere_superquadric_contact(sphere_centre, sphere_radius, j.element(k), state, controls);
    iterations += r.iterations;
    if (r.status == 2)
      break;
    status = r.status;
    if (in_piece(j, r.state.point, k)) {
      r.iterations = iterations;
      r.status = status;
      return r;
    }
    state = r.state;
    k = j.octant_at(r.state.point);
  }
  if (!controls.use_fallback)
    return narrow_phase::failed_result(iterations);
  for (int octant = 0; octant < octant_count; ++octant) {
    NarrowPhaseResult r = sphere_superquadric_contact(sphere_centre, sphere_radius,
                                                      j.element(octant), MidwayState{}, controls);
    iterations += r.iterations;
    if (r.status != 2 && in_piece(j, r.state.point, octant)) {
      r.iterations = iterations;
      r.status = 1;
      return r;
    }
  }
  return narrow_phase::failed_result(iterations);
}

} // namespace kdem
