#pragma once
// Four superquadric pairs of one shape pair solved in lock step (host only, see lanes.hpp): the
// common case of superquadric_pair_contact, a warm-started Newton solve of the midway system
// that converges in a few full steps, followed by the two surface crossings along the normal,
// written over lanes with the same formulas in the same order. Where a lane leaves that case
// (a singular Jacobian, a step the line search would shorten, more iterations than the lanes
// run, a crossing that needs bisection, anything not finite) the lane is reported unsolved
// and the caller solves the pair with superquadric_pair_contact, which stays the reference.
//
// Why: the scalar solve is a chain of dependent operations (evaluation, 4 x 4 solve,
// evaluation, crossing), so one pair at a time leaves most of a core idle; four pairs side by
// side fill it and share each instruction (docs/performance.md, sections 20 and 22).
#include "lanes.hpp"
#include "superquadric_contact.hpp"

#if KDEM_HOST_LANES
namespace kdem::lanes {

// Full Newton steps the lanes take before handing a lane that has not converged to the scalar
// solve, and Newton steps of one surface crossing likewise: a warm-started pair of a bed needs
// one or two of each (docs/performance.md, section 17).
constexpr int max_newton_steps = 4;
constexpr int max_crossing_steps = 4;

struct Pose {
  Vec centre;
  Rotation rotation;
};

// F, gradient and the body-frame Hessian of superquadric_local (its (x, z) and (y, z) entries
// are zero).
struct ShapeFunction {
  Real value;
  Vec gradient;
  Real hxx, hyy, hxy, hzz;
};

inline ShapeFunction select(Mask m, const ShapeFunction& a, const ShapeFunction& b) {
  return {select(m, a.value, b.value), select(m, a.gradient, b.gradient), select(m, a.hxx, b.hxx),
          select(m, a.hyy, b.hyy),     select(m, a.hxy, b.hxy),           select(m, a.hzz, b.hzz)};
}

inline Real lane_pow(Real t, double exponent) {
  Real r{};
  for (int l = 0; l < width; ++l)
    r[l] = std::pow(t[l], exponent);
  return r;
}

inline Real power_minus_two(Real t, double n, int n_integer) { // as kdem::power_minus_two
  if (n_integer >= 2)
    return integer_power(t, n_integer - 2);
  return select(t > splat(0.0), lane_pow(t, n - 2.0), splat(0.0));
}

// superquadric_local<true> lane by lane.
inline ShapeFunction local(const SuperquadricShape& s, const Vec& p) {
  const Real xa = p.x * s.inv_a, yb = p.y * s.inv_b, zc = p.z * s.inv_c;
  const Real u = abs(xa), v = abs(yb), w = abs(zc);
  const double n1 = s.n1, n2 = s.n2, k = s.conditioning;
  const Real u_m2 = power_minus_two(u, n2, s.n2_integer),
             v_m2 = power_minus_two(v, n2, s.n2_integer);
  const Real u_m1 = u_m2 * xa, v_m1 = v_m2 * yb;
  const Real w_m2 = power_minus_two(w, n1, s.n1_integer), w_m1 = w_m2 * zc;
  const Real section = u_m1 * xa + v_m1 * yb;
  Real s_p1 = splat(1.0), s_p2 = splat(0.0);
  if (!s.equal_exponents) {
    const Mask off_axis = section > splat(superquadric_axis_threshold);
    const Real power = s.ratio_minus_two_integer >= 0
                           ? integer_power(section, s.ratio_minus_two_integer)
                           : lane_pow(section, s.exponent_ratio - 2.0);
    s_p2 = select(off_axis, power, splat(0.0));
    s_p1 = select(off_axis, power * section, splat(0.0));
  }
  const Real section_term = s.equal_exponents ? section : s_p1 * section;
  ShapeFunction f;
  f.value = k * (section_term + w_m1 * zc - 1.0);
  f.gradient = {k * n1 * s.inv_a * s_p1 * u_m1, k * n1 * s.inv_b * s_p1 * v_m1,
                k * n1 * s.inv_c * w_m1};
  const Real cross = (n1 - n2) * s_p2;
  f.hxx = k * n1 * s.inv_a * s.inv_a * ((n2 - 1) * u_m2 * s_p1 + cross * u_m1 * u_m1);
  f.hyy = k * n1 * s.inv_b * s.inv_b * ((n2 - 1) * v_m2 * s_p1 + cross * v_m1 * v_m1);
  f.hxy = k * n1 * s.inv_a * s.inv_b * cross * u_m1 * v_m1;
  f.hzz = k * n1 * (n1 - 1) * s.inv_c * s.inv_c * w_m2;
  return f;
}

inline Vec body_hessian_times(const ShapeFunction& f, const Vec& v) {
  return {f.hxx * v.x + f.hxy * v.y, f.hxy * v.x + f.hyy * v.y, f.hzz * v.z};
}

// As PosedSuperquadric::evaluate_with_body_hessian: world gradient, body-frame Hessian.
inline ShapeFunction evaluate(const SuperquadricShape& s, const Pose& pose, const Vec& x) {
  ShapeFunction f = local(s, transpose_times(pose.rotation, x - pose.centre));
  f.gradient = times(pose.rotation, f.gradient);
  return f;
}

struct Symmetric3 {
  Real m[3][3];
};

// R H R^T, as PosedSuperquadric::world_hessian.
inline Symmetric3 world_hessian(const Rotation& r, const ShapeFunction& f) {
  Real tx[3], ty[3], tz[3];
  for (int b = 0; b < 3; ++b) {
    tx[b] = f.hxx * r.m[b][0] + f.hxy * r.m[b][1];
    ty[b] = f.hxy * r.m[b][0] + f.hyy * r.m[b][1];
    tz[b] = f.hzz * r.m[b][2];
  }
  Symmetric3 world;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b)
      world.m[a][b] = world.m[b][a] = r.m[a][0] * tx[b] + r.m[a][1] * ty[b] + r.m[a][2] * tz[b];
  return world;
}

// The midway system of MidwayProblemOf in lanes.
struct MidwayPair {
  const SuperquadricShape& shape_i;
  const SuperquadricShape& shape_j;
  const Pose& i;
  const Pose& j;
  double length;
  double tolerance;
};

struct Unknowns {
  Vec x;
  Real w;
};

struct Evaluation {
  ShapeFunction fi, fj;
  Real residual[4];
  Real merit;
  Mask finite;
};

inline Evaluation evaluate(const MidwayPair& pair, const Unknowns& u) {
  Evaluation e;
  e.fi = evaluate(pair.shape_i, pair.i, u.x);
  e.fj = evaluate(pair.shape_j, pair.j, u.x);
  const Vec g = splat(pair.length) * (e.fi.gradient + (u.w * u.w) * e.fj.gradient);
  e.residual[0] = g.x, e.residual[1] = g.y, e.residual[2] = g.z;
  e.residual[3] = e.fi.value - e.fj.value;
  e.merit = e.residual[0] * e.residual[0] + e.residual[1] * e.residual[1] +
            e.residual[2] * e.residual[2] + e.residual[3] * e.residual[3];
  e.finite = is_finite(e.merit) & is_finite(u.x) & is_finite(u.w) & is_finite(e.fi.hxx + e.fj.hxx);
  return e;
}

inline Evaluation select(Mask m, const Evaluation& a, const Evaluation& b) {
  Evaluation e;
  e.fi = select(m, a.fi, b.fi);
  e.fj = select(m, a.fj, b.fj);
  for (int r = 0; r < 4; ++r)
    e.residual[r] = select(m, a.residual[r], b.residual[r]);
  e.merit = select(m, a.merit, b.merit);
  e.finite = (m & a.finite) | (~m & b.finite);
  return e;
}

inline Mask converged(const MidwayPair& pair, const Evaluation& e) {
  const Real gi = norm(e.fi.gradient), gj = norm(e.fj.gradient);
  const Mask nonzero = (gi > splat(0.0)) & (gj > splat(0.0));
  const Real angle = norm((1.0 / gi) * e.fi.gradient + (1.0 / gj) * e.fj.gradient);
  const Real gap = abs(e.fi.value - e.fj.value) / ((gi + gj) * pair.length);
  return nonzero & (angle <= splat(pair.tolerance)) & (gap <= splat(pair.tolerance));
}

struct System4 {
  Real a[4][4];
  Real b[4];
};

inline System4 newton_system(const MidwayPair& pair, const Evaluation& e, const Unknowns& u) {
  const double length = pair.length;
  const Symmetric3 hi = world_hessian(pair.i.rotation, e.fi);
  const Symmetric3 hj = world_hessian(pair.j.rotation, e.fj);
  const Real w2 = u.w * u.w;
  const Vec lambda_column = (2.0 * u.w * length) * e.fj.gradient;
  const Vec gap_row = splat(length) * (e.fi.gradient - e.fj.gradient);
  const Real lambda[3] = {lambda_column.x, lambda_column.y, lambda_column.z};
  const Real gap[3] = {gap_row.x, gap_row.y, gap_row.z};
  System4 s;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      s.a[r][c] = (length * length) * (hi.m[r][c] + w2 * hj.m[r][c]);
    s.a[r][3] = lambda[r];
    s.a[3][r] = gap[r];
  }
  s.a[3][3] = splat(0.0);
  for (int r = 0; r < 4; ++r)
    s.b[r] = -e.residual[r];
  return s;
}

// solve_4x4 lane by lane: LU with partial pivoting, the pivot row of each lane chosen and
// swapped by masks. Lanes where solve_4x4 returns false come back false (the scalar solve then
// tries its Levenberg-Marquardt direction).
inline Mask solve(System4 s, Real x[4]) {
  Real largest = splat(0.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      largest = max(largest, abs(s.a[r][c]));
  Mask ok = is_finite(largest) & (largest > splat(0.0));
  const Real smallest_pivot = singular_pivot_factor * largest;
  for (int k = 0; k < 4; ++k) {
    Real best = abs(s.a[k][k]);
    Mask pivot_is[4] = {no_lane(), no_lane(), no_lane(), no_lane()};
    for (int r = k + 1; r < 4; ++r) {
      const Mask larger = abs(s.a[r][k]) > best;
      best = select(larger, abs(s.a[r][k]), best);
      for (int q = k + 1; q < r; ++q)
        pivot_is[q] &= ~larger;
      pivot_is[r] = larger;
    }
    ok &= best > smallest_pivot;
    for (int r = k + 1; r < 4; ++r) {
      const Mask swap = pivot_is[r];
      for (int c = 0; c < 4; ++c) {
        const Real t = s.a[k][c];
        s.a[k][c] = select(swap, s.a[r][c], t);
        s.a[r][c] = select(swap, t, s.a[r][c]);
      }
      const Real t = s.b[k];
      s.b[k] = select(swap, s.b[r], t);
      s.b[r] = select(swap, t, s.b[r]);
    }
    for (int r = k + 1; r < 4; ++r) {
      const Real factor = s.a[r][k] / s.a[k][k];
      for (int c = k + 1; c < 4; ++c)
        s.a[r][c] -= factor * s.a[k][c];
      s.b[r] -= factor * s.b[k];
    }
  }
  for (int r = 3; r >= 0; --r) {
    Real sum = s.b[r];
    for (int c = r + 1; c < 4; ++c)
      sum -= s.a[r][c] * x[c];
    x[r] = sum / s.a[r][r];
    ok &= is_finite(x[r]);
  }
  return ok;
}

// One full Newton step of narrow_phase::newton_solve for the lanes in `active`: the lanes whose
// step is accepted at t = 1 move to it; the others are returned as failed (the scalar solve
// would take the Levenberg-Marquardt direction or shorten the step).
inline Mask newton_step(const MidwayPair& pair, Mask active, Unknowns& u, Evaluation& e) {
  const System4 system = newton_system(pair, e, u);
  Real step[4];
  Mask ok = solve(system, step);
  const Real length = sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2]);
  const Mask too_long = length > splat(narrow_phase::max_position_step);
  const Real shrink = select(too_long, narrow_phase::max_position_step / length, splat(1.0));
  for (int r = 0; r < 4; ++r)
    step[r] = select(too_long, step[r] * shrink, step[r]);
  Real slope = splat(0.0);
  for (int r = 0; r < 4; ++r) {
    Real predicted = splat(0.0);
    for (int c = 0; c < 4; ++c)
      predicted += system.a[r][c] * step[c];
    slope += 2.0 * e.residual[r] * predicted;
  }
  ok &= slope < splat(0.0);
  const Unknowns trial{u.x + splat(pair.length) * Vec{step[0], step[1], step[2]}, u.w + step[3]};
  const Evaluation te = evaluate(pair, trial);
  ok &= te.finite & (te.merit <= e.merit + narrow_phase::armijo_fraction * slope);
  const Mask moved = active & ok;
  u = {select(moved, trial.x, u.x), select(moved, trial.w, u.w)};
  e = select(moved, te, e);
  return active & ~ok;
}

// narrow_phase::surface_crossing lane by lane for a body that is not a quadric, for the lanes in
// `wanted`; returns the lanes it could not settle within max_crossing_steps.
struct Crossing {
  Real distance;
  ShapeFunction at_crossing; // body frame
};

inline Mask surface_crossing(const SuperquadricShape& s, const Pose& body, const Vec& origin,
                             const Vec& direction, const ShapeFunction& at_origin, Mask wanted,
                             Crossing& crossing) {
  const Vec local_origin = transpose_times(body.rotation, origin - body.centre);
  const Vec local_direction = transpose_times(body.rotation, direction);
  const double smallest = math::min(s.a, math::min(s.b, s.c));
  const double reach = math::sqrt(s.a * s.a + s.b * s.b + s.c * s.c);
  Real lo = splat(0.0);
  Real hi = norm(local_origin) + reach;
  const double max_step = 0.5 * smallest;
  const Real resolution = 4.0 * double_epsilon * (hi + smallest);
  const Vec hessian_direction = body_hessian_times(at_origin, local_direction);
  const Real f0 = at_origin.value, slope0 = dot(at_origin.gradient, direction),
             curvature0 = dot(local_direction, hessian_direction);
  const Real denominator = slope0 + sqrt(max(splat(0.0), slope0 * slope0 - 2.0 * curvature0 * f0));
  const Real root = -2.0 * f0 / denominator;
  Real x = min(select((denominator > splat(0.0)) & is_finite(root), root, splat(0.0)), hi);
  if (narrow_phase::is_ellipsoid(s)) { // the model's root is the crossing (surface_crossing)
    crossing.distance = x;
    crossing.at_crossing = at_origin;
    crossing.at_crossing.value = splat(0.0);
    crossing.at_crossing.gradient =
        transpose_times(body.rotation, at_origin.gradient) + x * hessian_direction;
    return wanted & ~((x > splat(0.0)) & (x < hi));
  }
  Mask open = wanted;
  Mask failed = no_lane();
  ShapeFunction at = at_origin;
  for (int iteration = 0; iteration < max_crossing_steps && any(open); ++iteration) {
    const ShapeFunction f = local(s, local_origin + x * local_direction);
    at = select(open, f, at);
    const Mask bad = open & ~is_finite(f.value);
    failed |= bad;
    open &= ~bad;
    const Mask inside = f.value < splat(0.0);
    lo = select(open & inside, x, lo);
    hi = select(open & ~inside, x, hi);
    open &= ~(f.value == splat(0.0));
    const Real slope = dot(f.gradient, local_direction);
    const Mask has_slope = (slope > splat(0.0)) & is_finite(slope);
    const Real correction = clamp(f.value / slope, splat(-max_step), splat(max_step));
    const Real error_after = 0.5 * dot(local_direction, body_hessian_times(f, local_direction)) *
                             correction * correction / slope;
    const Real size = abs(correction);
    const Mask settled = open & has_slope &
                         ((size <= resolution) | ((size < max_step) & (error_after <= resolution)));
    const Real corrected = x - correction;
    x = select(settled, corrected, x);
    open &= ~settled;
    const Mask in_bracket = has_slope & (corrected > lo) & (corrected < hi);
    x = select(open, select(in_bracket, corrected, 0.5 * (lo + hi)), x);
    open &= ~(hi - lo <= resolution);
  }
  crossing.distance = x;
  crossing.at_crossing = at;
  return failed | open | (wanted & ~is_finite(x));
}

inline Real mean_curvature(const ShapeFunction& f) { // as kdem::mean_curvature
  const Real g2 = dot(f.gradient, f.gradient);
  const Real gHg = dot(f.gradient, body_hessian_times(f, f.gradient));
  const Real curvature = abs(gHg - g2 * (f.hxx + f.hyy + f.hzz)) / (2.0 * g2 * sqrt(g2));
  return select(g2 > splat(0.0), curvature, splat(0.0));
}

// narrow_phase::separation_bound lane by lane.
inline Real separation_bound(const MidwayPair& pair, const SuperquadricShape& shape_j, const Vec& x,
                             const Evaluation& e) {
  const Real gi = norm(e.fi.gradient), gj = norm(e.fj.gradient);
  const Mask outside =
      (e.fi.value > splat(0.0)) & (e.fj.value > splat(0.0)) & (gi > splat(0.0)) & (gj > splat(0.0));
  const double reach =
      math::sqrt(shape_j.a * shape_j.a + shape_j.b * shape_j.b + shape_j.c * shape_j.c);
  const Real reach_j = norm(x - pair.j.centre) + reach;
  const Real tilt = norm((1.0 / gi) * e.fi.gradient + (1.0 / gj) * e.fj.gradient);
  const Real bound = e.fi.value / gi + e.fj.value / gj - tilt * reach_j - 1e-9 * pair.length;
  return select(outside & is_finite(bound) & (bound > splat(0.0)), bound, splat(0.0));
}

// Inputs of four pairs of the shapes (shape_i, shape_j): poses and warm starts (start
// multiplier > 0 in every lane that is to be solved here).
struct PairInputs {
  Pose i, j;
  Vec start_point;
  Real start_multiplier;
};

inline void set_lane(Vec& v, int l, Vec3 x) {
  v.x[l] = x.x, v.y[l] = x.y, v.z[l] = x.z;
}

inline void set_lane(Rotation& r, int l, const Mat3& rotation) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      r.m[a][b][l] = rotation.m[a][b];
}

// Lane l of the inputs but the rotations: the two centres and the start.
inline void set_lane(PairInputs& in, int l, Vec3 centre_i, Vec3 centre_j,
                     const MidwayState& start) {
  set_lane(in.i.centre, l, centre_i);
  set_lane(in.j.centre, l, centre_j);
  set_lane(in.start_point, l, start.point);
  in.start_multiplier[l] = start.multiplier;
}

// Lane l of the inputs: the two posed bodies and the start.
inline void set_lane(PairInputs& in, int l, const PosedSuperquadric& i, const PosedSuperquadric& j,
                     const MidwayState& start) {
  set_lane(in, l, i.centre, j.centre, start);
  set_lane(in.i.rotation, l, i.rotation);
  set_lane(in.j.rotation, l, j.rotation);
}

// Solves the lanes of `in` as superquadric_pair_contact would from the warm start; returns the
// lanes solved here (bit l for lane l), whose results are in `out`. The other lanes are for the
// scalar solve.
// Compiled whole (KDEM_WHOLE_FUNCTION), as the scalar narrow phases: the same instructions in the
// Serial and OpenMP engines.
KDEM_WHOLE_FUNCTION int superquadric_pair_contact(const SuperquadricShape& shape_i,
                                                  const SuperquadricShape& shape_j,
                                                  const PairInputs& in,
                                                  const NarrowPhaseControls& controls,
                                                  NarrowPhaseResult (&out)[width]) {
  const double length = math::min(math::min(shape_i.a, math::min(shape_i.b, shape_i.c)),
                                  math::min(shape_j.a, math::min(shape_j.b, shape_j.c)));
  const MidwayPair pair{shape_i, shape_j, in.i, in.j, length, controls.tolerance};
  Unknowns u{in.start_point, in.start_multiplier};
  Evaluation e = evaluate(pair, u);
  Mask failed = ~(in.start_multiplier > splat(0.0));
  Mask active = ~failed;
  Real iterations = splat(0.0);
  for (int step = 0; step < max_newton_steps && any(active); ++step) {
    failed |= active & ~e.finite;
    active &= e.finite & ~converged(pair, e);
    if (!any(active))
      break;
    iterations += select(active, splat(1.0), splat(0.0));
    const Mask rejected = newton_step(pair, active, u, e);
    failed |= rejected;
    active &= ~rejected;
  }
  failed |= active & ~(e.finite & converged(pair, e));
  if (controls.max_iterations < max_newton_steps)
    failed |= iterations > splat(double(controls.max_iterations));

  const Vec normal = unit_or_zero(unit_or_zero(e.fj.gradient) - unit_or_zero(e.fi.gradient));
  const Mask touching = ~failed & (e.fi.value < splat(0.0)) & (e.fj.value < splat(0.0));
  Crossing along_i{}, along_j{};
  if (any(touching)) {
    failed |= surface_crossing(shape_i, in.i, u.x, -normal, e.fi, touching, along_i);
    failed |= surface_crossing(shape_j, in.j, u.x, normal, e.fj, touching, along_j);
  }
  const Vec surface_i = u.x - along_i.distance * normal,
            surface_j = u.x + along_j.distance * normal;
  const Real overlap = along_i.distance + along_j.distance;
  const Vec point = splat(0.5) * (surface_i + surface_j);
  const Real curvature_i = mean_curvature(along_i.at_crossing),
             curvature_j = mean_curvature(along_j.at_crossing);
  failed |=
      touching & ~(is_finite(overlap) & is_finite(point) & is_finite(curvature_i + curvature_j));
  const Real separation = separation_bound(pair, shape_j, u.x, e);
  const Real multiplier = abs(u.w);

  for (int l = 0; l < width; ++l) {
    if (lane(failed, l))
      continue;
    NarrowPhaseResult& r = out[l];
    r = NarrowPhaseResult{};
    r.iterations = int(iterations[l]);
    r.status = 0;
    r.state = MidwayState{Vec3{u.x.x[l], u.x.y[l], u.x.z[l]}, multiplier[l]};
    if (lane(touching, l)) {
      r.geometry.touching = true;
      r.geometry.overlap = overlap[l];
      r.geometry.normal = Vec3{normal.x[l], normal.y[l], normal.z[l]};
      r.geometry.point = Vec3{point.x[l], point.y[l], point.z[l]};
      r.curvature_i = curvature_i[l];
      r.curvature_j = curvature_j[l];
    }
    r.separation = separation[l];
  }
  return bits(~failed);
}

} // namespace kdem::lanes
#endif
