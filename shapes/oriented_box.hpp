#pragma once
// Oriented boxes: the bounding box of a family's body in the world (a trait member of each
// family, see docs/architecture.md), and the separating-axis test that the broad phase of a pair
// type runs on two of them.
#include <type_traits>

#include "implicit_surface.hpp"

namespace kdem {

// A box with half-extents half_extent along the columns of rotation, about centre.
struct OrientedBox {
  Vec3 centre;
  Mat3 rotation;
  Vec3 half_extent;
};

// The world box of a posed surface's body-frame box (shapes/implicit_surface.hpp).
template <class S> KOKKOS_INLINE_FUNCTION OrientedBox oriented_box_of(const S& s) {
  static_assert(is_wall_surface<S>::value, "a posed surface with a body box");
  const BodyBox box = s.local_box();
  return OrientedBox{s.to_world(0.5 * (box.lo + box.hi)), s.rotation, 0.5 * (box.hi - box.lo)};
}

// The separating-axis test (Eberly 2002; Gottschalk et al. 1996)
// numbers its 15 axes as: 0-2 the body axes A_k of i, 3-5 the body axes B_l of j, and
// 6 + 3 k + l the cross product A_k x B_l.
constexpr int obb_axis_count = 15;

// Cross products with |A_k x B_l|^2 below this (axes within 1e-6 rad of parallel) are not tested:
// rounding makes their direction meaningless, and the face axes decide parallel pairs.
constexpr double obb_min_cross_length2 = 1e-12;

// Absolute tolerance of every comparison, relative to the pair's size: an axis separates only when
// the gap exceeds it, so rounding can report a touching pair as overlapping but never the reverse.
constexpr double obb_relative_margin = 1e-12;

// Pair geometry in the frame of box i: rotation[k][l] = A_k . B_l, offset = centre_j - centre_i.
struct ObbPair {
  double rotation[3][3];
  double abs_rotation[3][3];
  double offset[3];
  double extent_i[3], extent_j[3];
  double margin;
};

KOKKOS_INLINE_FUNCTION ObbPair make_obb_pair(const OrientedBox& i, const OrientedBox& j) {
  ObbPair p;
  const Vec3 d = j.centre - i.centre;
  for (int k = 0; k < 3; ++k) {
    const Vec3 axis_i = column(i.rotation, k);
    p.offset[k] = dot(axis_i, d);
    for (int l = 0; l < 3; ++l) {
      p.rotation[k][l] = dot(axis_i, column(j.rotation, l));
      p.abs_rotation[k][l] = math::fabs(p.rotation[k][l]);
    }
  }
  const Vec3 ei = i.half_extent, ej = j.half_extent;
  p.extent_i[0] = ei.x, p.extent_i[1] = ei.y, p.extent_i[2] = ei.z;
  p.extent_j[0] = ej.x, p.extent_j[1] = ej.y, p.extent_j[2] = ej.z;
  const double size = norm(d) + ei.x + ei.y + ei.z + ej.x + ej.y + ej.z;
  p.margin = obb_relative_margin * size;
  return p;
}

// The gap between the projections of the two boxes on one numbered axis L, less the margin, in
// length units (divided by |L|, which is 1 for the face axes): a lower bound on the distance
// between any point of one box and any of the other. 0 where the projections are not farther
// apart than the margin, and for cross axes of near-parallel edges.
KOKKOS_INLINE_FUNCTION double obb_gap_along(const ObbPair& p, int axis) {
  const double(*r)[3] = p.rotation;
  const double(*abs_r)[3] = p.abs_rotation;
  const double* t = p.offset;
  const double* ei = p.extent_i;
  const double* ej = p.extent_j;
  double distance, reach, axis_length2 = 1;
  if (axis < 3) {
    const int k = axis;
    distance = math::fabs(t[k]);
    reach = ei[k] + ej[0] * abs_r[k][0] + ej[1] * abs_r[k][1] + ej[2] * abs_r[k][2];
  } else if (axis < 6) {
    const int l = axis - 3;
    distance = math::fabs(t[0] * r[0][l] + t[1] * r[1][l] + t[2] * r[2][l]);
    reach = ei[0] * abs_r[0][l] + ei[1] * abs_r[1][l] + ei[2] * abs_r[2][l] + ej[l];
  } else {
    // L = A_k x B_l = r[k1][l] A_k2 - r[k2][l] A_k1 for the cyclic order (k, k1, k2); the
    // projections of B_l1 and B_l2 on L are A_k . (B_l x B_l1) = A_k . B_l2 and the like.
    const int k = (axis - 6) / 3, l = (axis - 6) % 3;
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3, l1 = (l + 1) % 3, l2 = (l + 2) % 3;
    axis_length2 = r[k1][l] * r[k1][l] + r[k2][l] * r[k2][l];
    if (axis_length2 < obb_min_cross_length2)
      return 0;
    distance = math::fabs(t[k2] * r[k1][l] - t[k1] * r[k2][l]);
    reach = ei[k1] * abs_r[k2][l] + ei[k2] * abs_r[k1][l] + ej[l1] * abs_r[k][l2] +
            ej[l2] * abs_r[k][l1];
  }
  // Positive exactly when distance > reach + margin (a rounded difference keeps its sign).
  const double excess = distance - (reach + p.margin);
  return excess > 0 ? excess / math::sqrt(axis_length2) : 0.0;
}

// Separating-axis test of boxes i and j, with a lower bound on their distance: positive when an
// axis separates them (the gap along the first one found), 0 when they overlap.
// separating_axis is in/out: on input the axis that separated the pair last time (or -1),
// tested first; on output the axis that separates them now, or -1 when the boxes overlap.
KOKKOS_INLINE_FUNCTION double oriented_boxes_gap(const OrientedBox& i, const OrientedBox& j,
                                                 int& separating_axis) {
  const ObbPair pair = make_obb_pair(i, j);
  const int previous = separating_axis;
  if (previous >= 0 && previous < obb_axis_count) {
    const double gap = obb_gap_along(pair, previous);
    if (gap > 0)
      return gap;
  }
  for (int axis = 0; axis < obb_axis_count; ++axis) {
    const double gap = axis != previous ? obb_gap_along(pair, axis) : 0.0;
    if (gap > 0) {
      separating_axis = axis;
      return gap;
    }
  }
  separating_axis = -1;
  return 0;
}

// Separating-axis test of boxes i and j (oriented_boxes_gap without the gap).
KOKKOS_INLINE_FUNCTION bool oriented_boxes_overlap(const OrientedBox& i, const OrientedBox& j,
                                                   int& separating_axis) {
  return !(oriented_boxes_gap(i, j, separating_axis) > 0);
}

// Whether the body boxes of two posed surfaces overlap (oriented_boxes_overlap).
template <class S, class T>
KOKKOS_INLINE_FUNCTION bool bounding_boxes_overlap(const S& i, const T& j, int& separating_axis) {
  return oriented_boxes_overlap(oriented_box_of(i), oriented_box_of(j), separating_axis);
}

} // namespace kdem
