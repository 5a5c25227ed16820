// Experiment behind the choice of the superquadric narrow phase's next structure (performance
// report, section 20): the shape function with gradient and body-frame Hessian at a world point,
// as the engine evaluates it (PosedSuperquadric::evaluate_with_body_hessian, one point at a
// time), against four points in lock step: the same formulas over arrays of four lanes, with
// the blockiness a compile-time constant of the loop (one shape in every lane), so that the
// compiler turns each line into one instruction on four doubles (AVX2).
//
//   kdem_bench_lockstep_eval [--blockiness N] [--points P] [--repeat R]
//
// Prints one JSON object: ns per point evaluated by the engine's function (`scalar_ns`), by the
// lanes from points already laid out lane by lane (`lockstep_ns`), and by the lanes including
// the gather of each pose and point into lanes (`lockstep_with_gather_ns`, what a kernel over
// pairs would pay once per pair), medians over R passes over P random poses and points; and the
// largest relative difference between the two results (the same operations in the same order:
// 0 expected). Host code only: an experiment, not a kernel of the engine.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "shapes/superquadric.hpp"

namespace {

using namespace kdem;

constexpr int lanes = 4;

struct LaneInput {
  double cx[lanes], cy[lanes], cz[lanes]; // centre
  double r[9][lanes];                     // rotation, row-major entries
  double px[lanes], py[lanes], pz[lanes]; // world point
};

struct LaneOutput {
  double value[lanes];
  double gx[lanes], gy[lanes], gz[lanes];                // world gradient
  double hxx[lanes], hyy[lanes], hxy[lanes], hzz[lanes]; // body-frame Hessian
};

template <int M> double power(double t) {
  if constexpr (M == 0)
    return 1.0;
  else if constexpr (M == 2)
    return t * t;
  else if constexpr (M == 6) {
    const double t2 = t * t;
    return t2 * t2 * t2;
  }
}

// superquadric_local<true> for n1 = n2 = M + 2, then the gradient turned to the world, as
// evaluate_with_body_hessian does: the same operations in the same order, lanes in step.
// The output does not overlap the input (__restrict__): without that promise the compiler keeps
// the loop scalar.
template <int M>
void evaluate_lanes(const SuperquadricShape& s, const LaneInput& __restrict__ in,
                    LaneOutput& __restrict__ out) {
  const double k = s.conditioning, n = s.n1;
  const double ia = s.inv_a, ib = s.inv_b, ic = s.inv_c;
  for (int l = 0; l < lanes; ++l) {
    const double dx = in.px[l] - in.cx[l], dy = in.py[l] - in.cy[l], dz = in.pz[l] - in.cz[l];
    const double lx = in.r[0][l] * dx + in.r[3][l] * dy + in.r[6][l] * dz;
    const double ly = in.r[1][l] * dx + in.r[4][l] * dy + in.r[7][l] * dz;
    const double lz = in.r[2][l] * dx + in.r[5][l] * dy + in.r[8][l] * dz;
    const double xa = lx * ia, yb = ly * ib, zc = lz * ic;
    const double u = std::fabs(xa), v = std::fabs(yb), w = std::fabs(zc);
    const double u_m2 = power<M>(u), v_m2 = power<M>(v), w_m2 = power<M>(w);
    const double u_m1 = u_m2 * xa, v_m1 = v_m2 * yb, w_m1 = w_m2 * zc;
    out.value[l] = k * (u_m1 * xa + v_m1 * yb + w_m1 * zc - 1.0);
    const double bx = k * n * ia * u_m1, by = k * n * ib * v_m1, bz = k * n * ic * w_m1;
    out.gx[l] = in.r[0][l] * bx + in.r[1][l] * by + in.r[2][l] * bz;
    out.gy[l] = in.r[3][l] * bx + in.r[4][l] * by + in.r[5][l] * bz;
    out.gz[l] = in.r[6][l] * bx + in.r[7][l] * by + in.r[8][l] * bz;
    out.hxx[l] = k * n * ia * ia * ((n - 1) * u_m2);
    out.hyy[l] = k * n * ib * ib * ((n - 1) * v_m2);
    out.hxy[l] = 0;
    out.hzz[l] = k * n * (n - 1) * ic * ic * w_m2;
  }
}

void evaluate_lanes(const SuperquadricShape& s, const LaneInput& in, LaneOutput& out) {
  switch (s.n1_integer) {
  case 2:
    return evaluate_lanes<0>(s, in, out);
  case 4:
    return evaluate_lanes<2>(s, in, out);
  default:
    return evaluate_lanes<6>(s, in, out);
  }
}

void gather(const std::vector<PosedSuperquadric>& poses, const std::vector<Vec3>& points, int first,
            LaneInput& in) {
  for (int l = 0; l < lanes; ++l) {
    const PosedSuperquadric& pose = poses[first + l];
    const Vec3 point = points[first + l];
    in.cx[l] = pose.centre.x, in.cy[l] = pose.centre.y, in.cz[l] = pose.centre.z;
    for (int e = 0; e < 9; ++e)
      in.r[e][l] = pose.rotation.m[e / 3][e % 3];
    in.px[l] = point.x, in.py[l] = point.y, in.pz[l] = point.z;
  }
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

double relative_difference(double a, double b) {
  return std::fabs(a - b) / std::max(1.0, std::fabs(b));
}

int option(int argc, char** argv, const std::string& name, int fallback) {
  for (int a = 1; a + 1 < argc; ++a)
    if (argv[a] == name)
      return std::atoi(argv[a + 1]);
  return fallback;
}

} // namespace

int main(int argc, char** argv) {
  const int blockiness = option(argc, argv, "--blockiness", 8);
  const int points_count = option(argc, argv, "--points", 1 << 14) / lanes * lanes;
  const int repeat = option(argc, argv, "--repeat", 400);
  if (blockiness != 2 && blockiness != 4 && blockiness != 8) {
    std::fprintf(stderr, "bench_lockstep_eval: --blockiness must be 2, 4 or 8\n");
    return 2;
  }
  if (points_count < lanes || repeat < 1) {
    std::fprintf(stderr, "bench_lockstep_eval: --points must be at least 4, --repeat at least 1\n");
    return 2;
  }
  const double a = 8.2e-4; // m, the semi-axis of the benchmark bed's cubes
  const SuperquadricShape shape = make_superquadric(a, a, a, blockiness, blockiness);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal(0, 1);
  std::uniform_real_distribution<double> offset(-2 * a, 2 * a);
  std::vector<PosedSuperquadric> poses(points_count);
  std::vector<Vec3> points(points_count);
  for (int p = 0; p < points_count; ++p) {
    const Quat q = normalized(Quat{normal(rng), normal(rng), normal(rng), normal(rng)});
    poses[p] = pose_superquadric(shape, Vec3{offset(rng), offset(rng), offset(rng)}, q);
    points[p] = Vec3{offset(rng), offset(rng), offset(rng)};
  }
  const int groups = points_count / lanes;
  std::vector<LaneInput> laid_out(groups);
  for (int g = 0; g < groups; ++g)
    gather(poses, points, g * lanes, laid_out[g]);

  std::vector<ShapeFunction> scalar(points_count);
  std::vector<LaneOutput> in_lanes(groups), gathered(groups);
  std::vector<double> scalar_s, lockstep_s, gather_s;
  for (int r = 0; r < repeat; ++r) {
    auto start = std::chrono::steady_clock::now();
    for (int p = 0; p < points_count; ++p)
      scalar[p] = poses[p].evaluate_with_body_hessian<true>(points[p]);
    scalar_s.push_back(seconds_since(start) / points_count);
    start = std::chrono::steady_clock::now();
    for (int g = 0; g < groups; ++g)
      evaluate_lanes(shape, laid_out[g], in_lanes[g]);
    lockstep_s.push_back(seconds_since(start) / points_count);
    start = std::chrono::steady_clock::now();
    for (int g = 0; g < groups; ++g) {
      LaneInput in;
      gather(poses, points, g * lanes, in);
      evaluate_lanes(shape, in, gathered[g]);
    }
    gather_s.push_back(seconds_since(start) / points_count);
  }
  double largest = 0;
  for (int p = 0; p < points_count; ++p) {
    const LaneOutput& o = gathered[p / lanes];
    const int l = p % lanes;
    const ShapeFunction& f = scalar[p];
    for (const double d :
         {relative_difference(o.value[l], f.value), relative_difference(o.gx[l], f.gradient.x),
          relative_difference(o.gy[l], f.gradient.y), relative_difference(o.gz[l], f.gradient.z),
          relative_difference(o.hxx[l], f.hessian.m[0][0]),
          relative_difference(o.hyy[l], f.hessian.m[1][1]),
          relative_difference(o.hxy[l], f.hessian.m[0][1]),
          relative_difference(o.hzz[l], f.hessian.m[2][2]),
          relative_difference(in_lanes[p / lanes].value[l], f.value)})
      largest = std::max(largest, d);
  }
  const double scalar_ns = 1e9 * median(scalar_s), lockstep_ns = 1e9 * median(lockstep_s),
               gather_ns = 1e9 * median(gather_s);
  std::printf("{\"blockiness\": %d, \"lanes\": %d, \"points\": %d, \"repeat\": %d, "
              "\"scalar_ns\": %.3f, \"lockstep_ns\": %.3f, \"lockstep_with_gather_ns\": %.3f, "
              "\"scalar_over_lockstep\": %.2f, \"scalar_over_lockstep_with_gather\": %.2f, "
              "\"largest_relative_difference\": %.3g}\n",
              blockiness, lanes, points_count, repeat, scalar_ns, lockstep_ns, gather_ns,
              scalar_ns / lockstep_ns, scalar_ns / gather_ns, largest);
  return 0;
}
