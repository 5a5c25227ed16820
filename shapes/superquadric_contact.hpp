#pragma once
// Particle-particle narrow phase for superquadrics: the midway-point method (book Eqs. 2.9-2.10;
// Podlozhnyuk et al., Comput. Part. Mech. 4 (2017) 101) and an exact sphere-superquadric path.
// Host and device code: no recursion, no dynamic memory, no exceptions; every result is finite.
//
// Midway point: X and lambda with grad F_i(X) + lambda^2 grad F_j(X) = 0 and F_i(X) = F_j(X), where
// the level sets F_i = F_j = t touch with opposite normals. Solved by Newton on the 4 x 4 system
// of Eq. 2.10 in the length unit L (smallest semi-axis of the pair), with a backtracking line
// search on |residual|^2 that only accepts steps that decrease it. If that fails, a homotopy
// morphs both bodies from spheres (where the solution is exact) to the real shapes in stages.
// The overlap is the chord of the intersection along the normal line through X0.
#include "ellipsoid_midway.hpp"
#include "implicit_surface.hpp"
#include "small_solve.hpp"
#include "sphere.hpp"
#include "superquadric.hpp"

namespace kdem {

struct MidwayState {     // carried per pair from step to step
  Vec3 point;            // midway point X0 of the last evaluation, world frame, m
  double multiplier = 0; // lambda of Eq. 2.9 (not squared); <= 0 means no warm start
};

struct NarrowPhaseControls {
  // Converged when both (1) the angle in rad between grad F_i and -grad F_j and (2) the distance
  // between the level sets of F_i and F_j through X, |F_i - F_j| / (|grad F_i| + |grad F_j|), in
  // units of the smallest semi-axis of the pair, are at most this.
  double tolerance = 1e-10;
  int max_iterations = 40; // Newton iterations of one solve: the direct one, each homotopy stage
  bool use_fallback = true;
  int homotopy_stages = 4;      // fallback: equal stages from spheres; a failed stage is halved
  int max_homotopy_solves = 24; // Newton solves the fallback may spend in all
  // Two ellipsoids: the midway point from the scalar root of ellipsoid_midway.hpp, checked by
  // the general convergence test (and refined by the general Newton where it fails).
  bool ellipsoid_scalar_root = true;
  // m, the solves' unit of length (Newton's largest step is half of it, and the gap tolerance is
  // in its units); 0: the pair's smallest semi-axis. The pieces of a body (a poly-superquadric's
  // octants) are solved in the whole body's unit: a piece much thinner than the body would
  // otherwise crawl towards a contact a body size away in steps of its own thickness.
  double length = 0;
};

struct NarrowPhaseResult {
  ContactGeometry geometry; // normal from j towards i; point midway between the surface points
  double curvature_i = 0, curvature_j = 0; // mean curvature at each surface point, 1/m
  MidwayState state;                       // for the next step, also when not touching
  // Not touching: a lower bound on the gap between the bodies, m (0 when none is known).
  double separation = 0;
  int iterations = 0; // Newton iterations used, fallback included
  int status = 0;     // 0 converged, 1 converged only through the fallback, 2 failed
};

namespace narrow_phase {

constexpr double armijo_fraction = 1e-4;  // sufficient decrease (Nocedal & Wright, Eq. 3.4)
constexpr int max_backtracks = 40;        // step halvings before a line search gives up
constexpr double max_position_step = 0.5; // in units of L, so a step stays in the local region
constexpr int max_surface_iterations = 80;

struct Unknowns {
  Vec3 x;       // m, world frame
  double w = 0; // lambda (midway point) or nu (closest point)
};

KOKKOS_INLINE_FUNCTION double smallest_semi_axis(const SuperquadricShape& s) {
  return math::min(s.a, math::min(s.b, s.c));
}

KOKKOS_INLINE_FUNCTION double equivalent_radius(const SuperquadricShape& s) {
  return math::cbrt(s.a * s.b * s.c);
}

KOKKOS_INLINE_FUNCTION double squared_norm(const Vector4& r) {
  return r.v[0] * r.v[0] + r.v[1] * r.v[1] + r.v[2] * r.v[2] + r.v[3] * r.v[3];
}

KOKKOS_INLINE_FUNCTION bool is_finite(Vec3 v) {
  return kdem::is_finite(v.x) && kdem::is_finite(v.y) && kdem::is_finite(v.z);
}

KOKKOS_INLINE_FUNCTION Vec3 unit_or_zero(Vec3 v) {
  const double length = norm(v);
  return length > 0 ? (1.0 / length) * v : Vec3{0, 0, 0};
}

KOKKOS_INLINE_FUNCTION Vector4 times(const Matrix4& a, const Vector4& x) {
  Vector4 y;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      y.v[r] += a.m[r][c] * x.v[c];
  return y;
}

// Newton direction J p = -r; where J is singular (flat faces leave whole rows at zero), the
// Levenberg-Marquardt direction (J^T J + mu I) p = -J^T r, which is zero along the null space.
KOKKOS_INLINE_FUNCTION bool descent_direction(const Matrix4& jacobian, const Vector4& residual,
                                              Vector4& step) {
  Vector4 minus_residual;
  for (int r = 0; r < 4; ++r)
    minus_residual.v[r] = -residual.v[r];
  if (solve_4x4(jacobian, minus_residual, step))
    return true;
  Matrix4 normal;
  Vector4 rhs;
  double trace_normal = 0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 4; ++k)
        normal.m[r][c] += jacobian.m[k][r] * jacobian.m[k][c];
    for (int k = 0; k < 4; ++k)
      rhs.v[r] -= jacobian.m[k][r] * residual.v[k];
    trace_normal += normal.m[r][r];
  }
  const double damping = 1e-10 * trace_normal; // well above the singular threshold of solve_4x4
  for (int r = 0; r < 4; ++r)
    normal.m[r][r] += damping;
  return trace_normal > 0 && solve_4x4(normal, rhs, step);
}

KOKKOS_INLINE_FUNCTION void limit_position_step(Vector4& step) {
  const double length =
      math::sqrt(step.v[0] * step.v[0] + step.v[1] * step.v[1] + step.v[2] * step.v[2]);
  if (length > max_position_step) {
    const double shrink = max_position_step / length;
    for (int r = 0; r < 4; ++r)
      step.v[r] *= shrink;
  }
}

// Damped Newton: each accepted step satisfies the Armijo condition on the merit |r|^2, so the
// residual never increases. Returns true once problem.converged holds; counts iterations.
template <class Problem>
KOKKOS_INLINE_FUNCTION bool newton_solve(const Problem& problem, Unknowns& u,
                                         typename Problem::Evaluation& e, int max_iterations,
                                         int& iterations) {
  for (int iteration = 0;; ++iteration) {
    if (!e.finite)
      return false;
    if (problem.converged(e))
      return true;
    if (iteration >= max_iterations)
      return false;
    ++iterations;
    const Matrix4 jacobian = problem.jacobian(e, u);
    Vector4 step;
    if (!descent_direction(jacobian, e.residual, step))
      return false;
    limit_position_step(step);
    const Vector4 predicted = times(jacobian, step);
    double slope = 0; // d|r|^2/dt at t = 0
    for (int r = 0; r < 4; ++r)
      slope += 2.0 * e.residual.v[r] * predicted.v[r];
    if (!(slope < 0))
      return false;
    bool accepted = false;
    double t = 1;
    for (int k = 0; k < max_backtracks && !accepted; ++k, t *= 0.5) {
      const Vec3 dx = (t * problem.length) * Vec3{step.v[0], step.v[1], step.v[2]};
      const Unknowns trial{u.x + dx, u.w + t * step.v[3]};
      const typename Problem::Evaluation te = problem.evaluate(trial);
      if (te.finite && te.merit <= e.merit + armijo_fraction * t * slope) {
        u = trial;
        e = te;
        accepted = true;
      }
    }
    if (!accepted)
      return false;
  }
}

// The midway-point system of Eq. 2.9 in the length unit L: r = [L (g_i + lambda^2 g_j); F_i - F_j],
// unknowns (X / L, lambda), for any two surfaces of the concept of implicit_surface.hpp.
template <class SurfaceI, class SurfaceJ> struct MidwayProblemOf {
  SurfaceI i;
  SurfaceJ j;
  double length = 1;
  double tolerance = 1e-10;

  struct Evaluation {
    ShapeFunction fi, fj; // world gradients, body-frame Hessians (turned only in jacobian)
    Vector4 residual;
    double merit = 0;
    bool finite = false;
  };

  KOKKOS_INLINE_FUNCTION Evaluation evaluate(const Unknowns& u) const {
    return evaluation_of(u, i.evaluate_with_body_hessian(u.x), j.evaluate_with_body_hessian(u.x));
  }

  // The evaluation at u of shape functions known there (world gradients, body-frame Hessians).
  KOKKOS_INLINE_FUNCTION Evaluation evaluation_of(const Unknowns& u, const ShapeFunction& fi,
                                                  const ShapeFunction& fj) const {
    Evaluation e;
    e.fi = fi;
    e.fj = fj;
    const Vec3 g = length * (e.fi.gradient + (u.w * u.w) * e.fj.gradient);
    e.residual = Vector4{{g.x, g.y, g.z, e.fi.value - e.fj.value}};
    e.merit = squared_norm(e.residual);
    e.finite = kdem::is_finite(e.merit) && narrow_phase::is_finite(u.x) && kdem::is_finite(u.w) &&
               kdem::is_finite(e.fi.hessian.m[0][0] + e.fj.hessian.m[0][0]);
    return e;
  }

  KOKKOS_INLINE_FUNCTION Matrix4 jacobian(const Evaluation& e, const Unknowns& u) const {
    Matrix4 a;
    const Mat3 h = (length * length) *
                   (i.world_hessian(e.fi.hessian) + (u.w * u.w) * j.world_hessian(e.fj.hessian));
    const Vec3 lambda_column = (2.0 * u.w * length) * e.fj.gradient;
    const Vec3 gap_row = length * (e.fi.gradient - e.fj.gradient);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        a.m[r][c] = h.m[r][c];
      a.m[r][3] = lambda_column[r];
      a.m[3][r] = gap_row[r];
    }
    return a;
  }

  KOKKOS_INLINE_FUNCTION bool converged(const Evaluation& e) const {
    const double gi = norm(e.fi.gradient), gj = norm(e.fj.gradient);
    if (!(gi > 0 && gj > 0))
      return false;
    const double angle = norm((1.0 / gi) * e.fi.gradient + (1.0 / gj) * e.fj.gradient);
    const double gap = math::fabs(e.fi.value - e.fj.value) / ((gi + gj) * length);
    return angle <= tolerance && gap <= tolerance;
  }
};

static_assert(is_implicit_surface<PosedSuperquadric>::value,
              "a posed superquadric is a surface of the concept of implicit_surface.hpp");
using MidwayProblem = MidwayProblemOf<PosedSuperquadric, PosedSuperquadric>;

// Start value of lambda (digest Sect. 5): lambda^2 = -(g_i . g_j) / |g_j|^2, or |g_i| / |g_j|
// where the gradients are far from antiparallel and that projection says little.
KOKKOS_INLINE_FUNCTION double initial_multiplier(const ShapeFunction& fi, const ShapeFunction& fj) {
  const double gj2 = norm2(fj.gradient);
  if (!(gj2 > 0))
    return 1.0;
  const double ratio = norm(fi.gradient) / math::sqrt(gj2);
  const double projected = math::fabs(dot(fi.gradient, fj.gradient)) / gj2;
  const double lambda2 = projected > 1e-3 * ratio ? projected : ratio;
  return lambda2 > 0 ? math::sqrt(lambda2) : 1.0;
}

// Midway point of two spheres of the equivalent radii (abc)^(1/3) at the two centres.
template <class SurfaceI, class SurfaceJ>
KOKKOS_INLINE_FUNCTION Vec3 sphere_midway_point(const SurfaceI& i, const SurfaceJ& j) {
  const double ri = i.equivalent_radius(), rj = j.equivalent_radius();
  const double r = ri / (ri + rj);
  return (1.0 - r) * i.centre + r * j.centre;
}

template <class SurfaceI, class SurfaceJ>
KOKKOS_INLINE_FUNCTION MidwayProblemOf<SurfaceI, SurfaceJ>
make_midway_problem(const SurfaceI& i, const SurfaceJ& j, double tolerance) {
  const double length = math::min(i.smallest_length(), j.smallest_length());
  return MidwayProblemOf<SurfaceI, SurfaceJ>{i, j, length, tolerance};
}

template <class Problem>
KOKKOS_INLINE_FUNCTION Unknowns start_with_initial_multiplier(const Problem& problem, Vec3 x) {
  const typename Problem::Evaluation e = problem.evaluate(Unknowns{x, 1.0});
  return Unknowns{x, initial_multiplier(e.fi, e.fj)};
}

// Shape at homotopy parameter t: a sphere of the equivalent radius at t = 0, the real one at 1.
KOKKOS_INLINE_FUNCTION SuperquadricShape morphed_shape(const SuperquadricShape& s, double t) {
  const double r = equivalent_radius(s);
  return make_superquadric(r + t * (s.a - r), r + t * (s.b - r), r + t * (s.c - r),
                           2.0 + t * (s.n1 - 2.0), 2.0 + t * (s.n2 - 2.0));
}

KOKKOS_INLINE_FUNCTION PosedSuperquadric morphed(const PosedSuperquadric& p, double t) {
  return PosedSuperquadric{morphed_shape(p.shape, t), p.centre, p.rotation};
}

// Fallback: continuation from the exact sphere solution through shapes morphed in stages; a
// stage that fails is retried at half the increment. On success u and e belong to the real pair.
// Compiled apart from the direct solve, which it would otherwise double in size.
KDEM_WHOLE_FUNCTION bool homotopy_solve(const MidwayProblem& real, Unknowns& u,
                                        MidwayProblem::Evaluation& e,
                                        const NarrowPhaseControls& controls, int& iterations) {
  const int stages = controls.homotopy_stages > 0 ? controls.homotopy_stages : 1;
  double reached = 0, increment = 1.0 / stages;
  Unknowns current{sphere_midway_point(real.i, real.j), 1.0};
  for (int solve = 0; solve < controls.max_homotopy_solves; ++solve) {
    const double target = math::min(1.0, reached + increment);
    const MidwayProblem stage =
        target >= 1.0 ? real
                      : MidwayProblem{morphed(real.i, target), morphed(real.j, target), real.length,
                                      real.tolerance};
    Unknowns trial = start_with_initial_multiplier(stage, current.x);
    MidwayProblem::Evaluation te = stage.evaluate(trial);
    if (newton_solve(stage, trial, te, controls.max_iterations, iterations)) {
      current = trial;
      reached = target;
      if (reached >= 1.0) {
        u = current;
        e = te;
        return true;
      }
    } else {
      increment *= 0.5;
    }
  }
  return false;
}

// The positive root of the quadratic model f0 + slope s + curvature s^2 / 2 of f(s) =
// F(origin + s direction) at s = 0, given f0 < 0 and curvature >= 0 (F is convex), in the form
// that does not cancel; 0 where the model has no positive root.
KOKKOS_INLINE_FUNCTION double quadratic_model_root(double f0, double slope, double curvature) {
  const double denominator =
      slope + math::sqrt(math::max(0.0, slope * slope - 2.0 * curvature * f0));
  const double root = -2.0 * f0 / denominator;
  return denominator > 0 && kdem::is_finite(root) ? root : 0.0;
}

// Where the line from a point inside a body leaves it: the root s > 0 of f(s) = F(origin +
// s direction), given f(0) < 0 (F is convex along lines, so there is one), with F, its gradient
// and Hessian at the last point evaluated, in the body frame (for the curvature there).
struct SurfaceCrossing {
  double distance = 0;
  ShapeFunction at_crossing;
};

// Whether F is quadratic along every line (an ellipsoid), so that the quadratic model of
// surface_crossing is F itself and its root is the crossing.
template <class Surface> KOKKOS_INLINE_FUNCTION bool is_quadric(const Surface&) {
  return false;
}
KOKKOS_INLINE_FUNCTION bool is_quadric(const PosedSuperquadric& body) {
  return is_ellipsoid(body.shape);
}

// Newton from the root of the quadratic model of f at s = 0 (at_origin: F, world gradient and
// body-frame Hessian at the origin, as the midway solve leaves them), which is within
// O(s^3 / L^2) of the root, so that one Newton step usually ends the search. Steps are clamped
// to half the smallest semi-axis and kept inside a bracket that starts at [0, a bound beyond the
// body's bounding sphere of radius |(a, b, c)|]. Converged when the last correction c is below
// the rounding of the bracket (`resolution`) or when Newton's error estimate after it,
// f'' c^2 / (2 f'), is (f'' from the Hessian at the point, so the crossing costs one evaluation
// with Hessian per step and none after). Searched in the body frame, where a point costs no
// rotation. For a quadric the model's root is the crossing, and no evaluation is needed.
template <class Surface>
KOKKOS_INLINE_FUNCTION bool surface_crossing(const Surface& body, Vec3 origin, Vec3 direction,
                                             const ShapeFunction& at_origin,
                                             SurfaceCrossing& crossing) {
  const Vec3 local_origin = body.to_local(origin);
  const Vec3 local_direction = transpose_times(body.rotation, direction);
  double lo = 0;
  double hi = norm(local_origin) + body.reach();
  const double max_step = 0.5 * body.smallest_length();
  const double resolution = 4.0 * double_epsilon * (hi + body.smallest_length());
  const Vec3 hessian_direction = at_origin.hessian * local_direction;
  double x = math::min(quadratic_model_root(at_origin.value, dot(at_origin.gradient, direction),
                                            dot(local_direction, hessian_direction)),
                       hi);
  if (is_quadric(body) && x > 0 && x < hi) {
    // Exact to rounding: on the surface, gradient g(0) + x H d and the constant Hessian.
    crossing.distance = x;
    crossing.at_crossing.value = 0;
    crossing.at_crossing.gradient =
        transpose_times(body.rotation, at_origin.gradient) + x * hessian_direction;
    crossing.at_crossing.hessian = at_origin.hessian;
    return true;
  }
  for (int iteration = 0; iteration < max_surface_iterations; ++iteration) {
    const ShapeFunction f = body.template local<true>(local_origin + x * local_direction);
    crossing.at_crossing = f;
    if (!kdem::is_finite(f.value))
      return false;
    if (f.value < 0)
      lo = x;
    else
      hi = x;
    if (f.value == 0)
      break;
    const double slope = dot(f.gradient, local_direction);
    double next = 0.5 * (lo + hi);
    if (slope > 0 && kdem::is_finite(slope)) {
      const double correction = math::clamp(f.value / slope, -max_step, max_step);
      const double error_after =
          0.5 * dot(local_direction, f.hessian * local_direction) * correction * correction / slope;
      if (math::fabs(correction) <= resolution ||
          (math::fabs(correction) < max_step && error_after <= resolution)) {
        x -= correction;
        break;
      }
      if (x - correction > lo && x - correction < hi)
        next = x - correction;
    }
    x = next;
    if (hi - lo <= resolution)
      break;
  }
  crossing.distance = x;
  return kdem::is_finite(x);
}

// Surface points, overlap and curvatures on the line through x0 along the unit normal (from j
// towards i): X_i = x0 - alpha n on i's side facing j, X_j = x0 + beta n, overlap alpha + beta.
// This is the digest's alpha0 - beta0 with its normal grad F_i / |grad F_i| = -n. fi, fj: F of
// each body at x0 with world gradient and body-frame Hessian (the midway solve's last
// evaluation). The curvatures are those of the level sets through the last points evaluated,
// within the last Newton correction of the surface points (see surface_crossing).
template <class SurfaceI, class SurfaceJ>
KOKKOS_INLINE_FUNCTION bool chord_geometry(const SurfaceI& i, const SurfaceJ& j, Vec3 x0,
                                           Vec3 normal, const ShapeFunction& fi,
                                           const ShapeFunction& fj, NarrowPhaseResult& result) {
  SurfaceCrossing along_i, along_j;
  if (!surface_crossing(i, x0, -normal, fi, along_i) ||
      !surface_crossing(j, x0, normal, fj, along_j))
    return false;
  const Vec3 surface_i = x0 - along_i.distance * normal, surface_j = x0 + along_j.distance * normal;
  result.geometry.touching = true;
  result.geometry.overlap = along_i.distance + along_j.distance;
  result.geometry.normal = normal;
  result.geometry.point = 0.5 * (surface_i + surface_j);
  result.curvature_i = mean_curvature(along_i.at_crossing);
  result.curvature_j = mean_curvature(along_j.at_crossing);
  return kdem::is_finite(result.geometry.overlap) && is_finite(result.geometry.point) &&
         kdem::is_finite(result.curvature_i + result.curvature_j);
}

// A lower bound on the gap from any point x outside both bodies. F is convex, so F(y) >= F(x) +
// g . (y - x): body i lies behind the plane through x with normal n_i = g_i / |g_i| by
// m_i = F_i(x) / |g_i|, and body j behind its plane with normal n_j by m_j. Along n_i, body j
// reaches at most |n_i + n_j| (|x - c_j| + r_j) closer than m_j (r_j >= j's bounding radius), so
// the bodies' projections on n_i are apart by at least m_i + m_j - that. Rounding of F (a few
// 1e-16 of its unit-scale terms) is covered by 1e-9 L. Returns 0 where x is not outside both.
template <class SurfaceI, class SurfaceJ>
KOKKOS_INLINE_FUNCTION double separation_bound(const SurfaceI& i, const SurfaceJ& j, Vec3 x,
                                               const ShapeFunction& fi, const ShapeFunction& fj) {
  const double gi = norm(fi.gradient), gj = norm(fj.gradient);
  if (!(fi.value > 0 && fj.value > 0 && gi > 0 && gj > 0))
    return 0;
  const double reach_j = norm(x - j.centre) + j.reach();
  const double tilt = norm((1.0 / gi) * fi.gradient + (1.0 / gj) * fj.gradient);
  const double length = math::min(i.smallest_length(), j.smallest_length());
  const double bound = fi.value / gi + fj.value / gj - tilt * reach_j - 1e-9 * length;
  return kdem::is_finite(bound) && bound > 0 ? bound : 0.0;
}

KOKKOS_INLINE_FUNCTION NarrowPhaseResult failed_result(int iterations) {
  NarrowPhaseResult result;
  result.iterations = iterations;
  result.status = 2;
  return result;
}

// Closest point p of body j's surface to a point c: c - p = nu L g~ with g~ = L grad F_j(p) and
// F_j(p) = 0, in the length unit L; r = [(c - p) / L - nu g~; F_j], unknowns (p / L, nu).
// nu > 0 for c outside, < 0 inside.
template <class Surface> struct ClosestPointProblemOf {
  Surface body;
  Vec3 target;
  double length = 1;
  double tolerance = 1e-10;

  struct Evaluation {
    ShapeFunction f;
    Vector4 residual;
    double merit = 0;
    bool finite = false;
  };

  KOKKOS_INLINE_FUNCTION Evaluation evaluate(const Unknowns& u) const {
    Evaluation e;
    e.f = body.template evaluate<true>(u.x);
    const Vec3 r = (1.0 / length) * (target - u.x) - (u.w * length) * e.f.gradient;
    e.residual = Vector4{{r.x, r.y, r.z, e.f.value}};
    e.merit = squared_norm(e.residual);
    e.finite = kdem::is_finite(e.merit) && narrow_phase::is_finite(u.x) && kdem::is_finite(u.w) &&
               kdem::is_finite(e.f.hessian.m[0][0]);
    return e;
  }

  KOKKOS_INLINE_FUNCTION Matrix4 jacobian(const Evaluation& e, const Unknowns& u) const {
    Matrix4 a;
    const Mat3 h = (u.w * length * length) * e.f.hessian;
    const Vec3 g = length * e.f.gradient;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        a.m[r][c] = (r == c ? -1.0 : 0.0) - h.m[r][c];
      a.m[r][3] = -g[r];
      a.m[3][r] = g[r];
    }
    return a;
  }

  KOKKOS_INLINE_FUNCTION bool converged(const Evaluation& e) const {
    const double g = length * norm(e.f.gradient);
    if (!(g > 0))
      return false;
    const double normal_error =
        math::sqrt(e.residual.v[0] * e.residual.v[0] + e.residual.v[1] * e.residual.v[1] +
                   e.residual.v[2] * e.residual.v[2]);
    return normal_error <= tolerance && math::fabs(e.f.value) / g <= tolerance;
  }
};

using ClosestPointProblem = ClosestPointProblemOf<PosedSuperquadric>;

template <class Problem>
KOKKOS_INLINE_FUNCTION Unknowns closest_point_start(const Problem& problem, Vec3 p) {
  const ShapeFunction f = problem.body.template evaluate<false>(p);
  const Vec3 g = problem.length * f.gradient;
  const double g2 = norm2(g);
  const double nu = g2 > 0 ? dot((1.0 / problem.length) * (problem.target - p), g) / g2 : 0.0;
  return Unknowns{p, nu};
}

// Radial projection of the target onto the surface: F + k = k G with G homogeneous of degree n1
// in the body frame, so the surface point on the ray from the centre is centre + G^(-1/n1) d.
KOKKOS_INLINE_FUNCTION Vec3 radial_projection(const PosedSuperquadric& body, Vec3 target) {
  const SuperquadricShape& s = body.shape;
  const Vec3 local = body.to_local(target);
  const double g = body.value(target) / s.conditioning + 1.0;
  if (!(g > 1e-200))
    return body.to_world(Vec3{0, 0, s.c});
  return body.to_world(math::pow(g, -1.0 / s.n1) * local);
}

// Two ellipsoids: the scalar root of ellipsoid_midway.hpp, then the general convergence test on
// the F and gradients the root found (its gap test is at least as strict; the normals are
// opposite to rounding). False where the root is not found or the test fails.
KOKKOS_INLINE_FUNCTION bool ellipsoid_pair_solve(const MidwayProblem& problem,
                                                 const MidwayState& previous,
                                                 const NarrowPhaseControls& controls, Unknowns& u,
                                                 MidwayProblem::Evaluation& e, int& iterations) {
  EllipsoidMidway root;
  if (!ellipsoid_midway(problem.i, problem.j, previous.point, previous.multiplier,
                        controls.tolerance * problem.length, controls.max_iterations, root,
                        iterations))
    return false;
  u = Unknowns{root.point, root.multiplier};
  e = problem.evaluation_of(u, root.fi, root.fj); // F as the root found it, not evaluated anew
  return newton_solve(problem, u, e, controls.max_iterations, iterations);
}

} // namespace narrow_phase

KDEM_WHOLE_FUNCTION NarrowPhaseResult
superquadric_pair_contact(const PosedSuperquadric& i, const PosedSuperquadric& j,
                          const MidwayState& previous, const NarrowPhaseControls& controls) {
  using namespace narrow_phase;
  MidwayProblem problem = make_midway_problem(i, j, controls.tolerance);
  if (controls.length > 0)
    problem.length = controls.length;
  // The midway point minimises the strictly convex max(F_i, F_j), so every start that converges
  // finds the same point: a warm start is solved alone, and the sphere start is tried only
  // without one or when Newton from it fails.
  Unknowns u;
  MidwayProblem::Evaluation e;
  int iterations = 0;
  bool solved = controls.ellipsoid_scalar_root && is_ellipsoid(i.shape) && is_ellipsoid(j.shape) &&
                ellipsoid_pair_solve(problem, previous, controls, u, e, iterations);
  if (!solved && previous.multiplier > 0) {
    u = Unknowns{previous.point, previous.multiplier};
    e = problem.evaluate(u);
    solved = newton_solve(problem, u, e, controls.max_iterations, iterations);
  }
  if (!solved) {
    u = start_with_initial_multiplier(problem, sphere_midway_point(i, j));
    e = problem.evaluate(u);
    solved = newton_solve(problem, u, e, controls.max_iterations, iterations);
  }
  int status = 0;
  if (!solved) {
    status = 1;
    if (!controls.use_fallback || !homotopy_solve(problem, u, e, controls, iterations))
      return failed_result(iterations);
  }
  NarrowPhaseResult result;
  result.iterations = iterations;
  result.status = status;
  result.state = MidwayState{u.x, math::fabs(u.w)};
  const Vec3 normal =
      unit_or_zero(unit_or_zero(e.fj.gradient) - unit_or_zero(e.fi.gradient)); // j towards i
  if (e.fi.value < 0 && e.fj.value < 0 && !chord_geometry(i, j, u.x, normal, e.fi, e.fj, result))
    return failed_result(iterations);
  result.separation = separation_bound(i, j, u.x, e.fi, e.fj);
  return result;
}

// Sphere (body i) against superquadric j: the exact closest point p of j's surface to the centre,
// overlap = radius - signed distance of the centre from j along the outward normal at p. The
// state stores p with multiplier 1 (a flag: nu is recomputed from p). Falls back to the midway
// method with the sphere as an n = 2 superquadric.
KDEM_WHOLE_FUNCTION NarrowPhaseResult
sphere_superquadric_contact(Vec3 sphere_centre, double sphere_radius, const PosedSuperquadric& j,
                            const MidwayState& previous, const NarrowPhaseControls& controls) {
  using namespace narrow_phase;
  const double length =
      controls.length > 0 ? controls.length : math::min(smallest_semi_axis(j.shape), sphere_radius);
  const ClosestPointProblem problem{j, sphere_centre, length, controls.tolerance};
  Unknowns u = closest_point_start(problem, radial_projection(j, sphere_centre));
  ClosestPointProblem::Evaluation e = problem.evaluate(u);
  if (previous.multiplier > 0) {
    const Unknowns warm = closest_point_start(problem, previous.point);
    const ClosestPointProblem::Evaluation we = problem.evaluate(warm);
    if (we.finite && (!e.finite || we.merit < e.merit)) {
      u = warm;
      e = we;
    }
  }
  int iterations = 0;
  const bool centre_outside = j.value(sphere_centre) > 0;
  const bool solved = newton_solve(problem, u, e, controls.max_iterations, iterations) &&
                      (centre_outside ? u.w > 0 : u.w <= 0); // else not the nearest point
  if (!solved) {
    if (!controls.use_fallback)
      return failed_result(iterations);
    const PosedSuperquadric sphere{
        make_superquadric(sphere_radius, sphere_radius, sphere_radius, 2, 2), sphere_centre,
        Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}};
    NarrowPhaseResult fallback = superquadric_pair_contact(sphere, j, MidwayState{}, controls);
    fallback.iterations += iterations;
    fallback.state.multiplier = 0; // a midway point is no start for the closest point
    if (fallback.status == 0)
      fallback.status = 1;
    return fallback;
  }
  NarrowPhaseResult result;
  result.iterations = iterations;
  result.state = MidwayState{u.x, 1.0};
  const Vec3 normal = unit_or_zero(e.f.gradient); // outward from j at p: from j towards i
  const double signed_distance = dot(sphere_centre - u.x, normal);
  const double overlap = sphere_radius - signed_distance;
  // Not touching: the body lies behind the plane through p with normal n by F(p) / |grad F(p)|
  // (convexity), the sphere in front of it by its signed distance minus its radius.
  const double plane_offset = e.f.value / norm(e.f.gradient);
  if (overlap <= 0 && kdem::is_finite(plane_offset))
    result.separation = math::max(0.0, plane_offset - overlap - 1e-9 * length);
  if (overlap > 0) {
    const Vec3 sphere_surface = sphere_centre - sphere_radius * normal;
    result.geometry.touching = true;
    result.geometry.overlap = overlap;
    result.geometry.normal = normal;
    result.geometry.point = 0.5 * (sphere_surface + u.x);
    result.curvature_i = sphere_radius > 0 ? 1.0 / sphere_radius : 0.0; // radius 0: a point probe
    result.curvature_j = mean_curvature(e.f);
  }
  if (!kdem::is_finite(overlap) || !narrow_phase::is_finite(result.geometry.point) ||
      !kdem::is_finite(result.curvature_j))
    return failed_result(iterations);
  return result;
}

} // namespace kdem
