#pragma once
// Case sets for the superquadric narrow-phase benchmark: named hard cases, random pairs and
// moving pairs (sequences of poses evaluated in order with the warm start carried along).
//
// Pairs are placed with the exact support function of a superquadric, h(d) = max x.d over the
// body. In the body frame, with q = n / (n - 1) the Hoelder conjugate of an exponent n,
//   h(d) = || ( ||(a dx, b dy)||_q2 , c dz ) ||_q1,
// because the surface is the unit q1-"sphere" in (rho, |z/c|) with rho = || (x/a, y/b) ||_n2
// (Hoelder's inequality, and its equality case gives the support point). Placing j so that
// h_j(n) + h_i(-n) = overlap makes the projections on the normal n overlap by exactly that.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "shapes/superquadric_contact.hpp"

namespace kdem::narrow_phase_bench {

struct PosePair {
  PosedSuperquadric i, j;
};

// sequences x poses pairs, sequence-major; with warm_start each pose of a sequence starts from
// the previous pose's MidwayState, as a simulation carries it from step to step.
struct CaseSet {
  std::string name;
  int sequences = 0;
  int poses = 1;
  bool warm_start = false;
  std::vector<PosePair> pairs;
};

class Random {
public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  Vec3 direction() {
    const Vec3 v{gauss(), gauss(), gauss()};
    return (1.0 / norm(v)) * v;
  }
  Quat rotation() { return normalized(Quat{gauss(), gauss(), gauss(), gauss()}); }

private:
  double gauss() { return normal_(engine_); }
  std::mt19937_64 engine_;
  std::normal_distribution<double> normal_;
};

inline double conjugate_exponent(double n) {
  return n / (n - 1.0);
}

inline double two_norm_of_order(double x, double y, double q) {
  const double largest = std::max(x, y);
  if (!(largest > 0))
    return 0;
  return largest * std::pow(std::pow(x / largest, q) + std::pow(y / largest, q), 1.0 / q);
}

// Hoelder equality: the maximiser of alpha . u over ||u||_n = 1, one component.
inline double equality_component(double alpha, double dual_norm, double q) {
  return dual_norm > 0 ? std::pow(alpha / dual_norm, q - 1.0) : 0.0;
}

inline Vec3 support_point_local(const SuperquadricShape& s, Vec3 d) {
  const double q1 = conjugate_exponent(s.n1), q2 = conjugate_exponent(s.n2);
  const double ax = std::fabs(s.a * d.x), by = std::fabs(s.b * d.y), cz = std::fabs(s.c * d.z);
  const double section = two_norm_of_order(ax, by, q2);
  const double height = two_norm_of_order(section, cz, q1);
  const double rho = equality_component(section, height, q1);
  const double w = equality_component(cz, height, q1);
  return Vec3{std::copysign(s.a * rho * equality_component(ax, section, q2), d.x),
              std::copysign(s.b * rho * equality_component(by, section, q2), d.y),
              std::copysign(s.c * w, d.z)};
}

inline Vec3 support_point(const PosedSuperquadric& body, Vec3 d) {
  return body.to_world(support_point_local(body.shape, transpose(body.rotation) * d));
}

inline double support_value(const PosedSuperquadric& body, Vec3 d) {
  return dot(support_point(body, d), d);
}

// Upper bound on any chord of the intersection along the unit n (from j towards i).
inline double projected_overlap(const PosedSuperquadric& i, const PosedSuperquadric& j, Vec3 n) {
  return support_value(j, n) + support_value(i, -n);
}

inline double pair_size(const PosedSuperquadric& i, const PosedSuperquadric& j) {
  return std::min(std::cbrt(i.shape.a * i.shape.b * i.shape.c),
                  std::cbrt(j.shape.a * j.shape.b * j.shape.c));
}

// Moves j so that its projection on n overlaps i's by `overlap` (negative: a gap).
inline PosedSuperquadric placed_against(const PosedSuperquadric& i, PosedSuperquadric j, Vec3 n,
                                        double overlap) {
  j.centre = Vec3{0, 0, 0};
  j.centre = support_point(i, -n) - support_point(j, n) + overlap * n;
  return j;
}

inline PosedSuperquadric body(double a, double b, double c, double n1, double n2, Quat q,
                              Vec3 centre = {0, 0, 0}) {
  return pose_superquadric(make_superquadric(a, b, c, n1, n2), centre, q);
}

inline Quat turn(Vec3 axis, double angle) {
  return quat_from_rotation_vector((angle / norm(axis)) * axis);
}

// The rotation taking the unit vector from onto the unit vector to.
inline Quat turn_onto(Vec3 from, Vec3 to) {
  const Vec3 axis = cross(from, to);
  return turn(axis, std::atan2(norm(axis), dot(from, to)));
}

inline PosePair in_contact(const PosedSuperquadric& i, const PosedSuperquadric& j, Vec3 n,
                           double relative_overlap) {
  return {i, placed_against(i, j, n, relative_overlap * pair_size(i, j))};
}

inline CaseSet independent_set(const std::string& name, std::vector<PosePair> pairs) {
  CaseSet set;
  set.name = name;
  set.sequences = int(pairs.size());
  set.pairs = std::move(pairs);
  return set;
}

// ------------------------------------------------------------------ hard cases

constexpr int variants = 64; // random orientations (and shapes) per hard-case set

inline std::string with_blockiness(const std::string& name, double n) {
  return name + " n=" + std::to_string(int(n));
}

inline std::vector<CaseSet> blockiness_sets(Random& random) {
  std::vector<CaseSet> sets;
  for (double n : {2.0, 4.0, 6.0, 8.0, 10.0, 16.0}) {
    std::vector<PosePair> pairs;
    for (int k = 0; k < variants; ++k)
      pairs.push_back(in_contact(body(1, 0.8, 0.6, n, n, random.rotation()),
                                 body(0.7, 1, 0.9, n, n, random.rotation()), random.direction(),
                                 0.01));
    sets.push_back(independent_set(with_blockiness("blockiness", n), pairs));
  }
  return sets;
}

inline std::vector<CaseSet> aspect_sets(Random& random) {
  std::vector<CaseSet> sets;
  for (double aspect : {0.2, 0.5, 2.0, 5.0}) {
    std::vector<PosePair> pairs;
    for (int k = 0; k < variants; ++k) {
      const double n = k % 2 ? 4.0 : 2.0;
      pairs.push_back(in_contact(body(1, 1, aspect, n, 2, random.rotation()),
                                 body(1, aspect, 1, 2, n, random.rotation()), random.direction(),
                                 0.01));
    }
    char name[32];
    std::snprintf(name, sizeof name, "aspect %g", aspect);
    sets.push_back(independent_set(name, pairs));
  }
  return sets;
}

inline CaseSet size_ratio_set(Random& random) {
  std::vector<PosePair> pairs;
  for (double n : {2.0, 4.0, 8.0, 10.0})
    for (int k = 0; k < variants / 4; ++k) {
      const PosedSuperquadric large = body(1, 1, 1, n, n, random.rotation());
      const PosedSuperquadric small = body(0.1, 0.08, 0.12, n, n, random.rotation());
      const bool small_first = k % 2;
      pairs.push_back(in_contact(small_first ? small : large, small_first ? large : small,
                                 random.direction(), 0.01));
    }
  return independent_set("size ratio 10", pairs);
}

// Cubes (a = b = c = 1) meeting in a symmetric configuration along the world z axis.
inline CaseSet cube_set(const std::string& name, Quat qi, Quat qj, double relative_overlap) {
  std::vector<PosePair> pairs;
  const Vec3 up{0, 0, 1};
  for (double n : {4.0, 8.0, 10.0, 16.0})
    pairs.push_back(
        in_contact(body(1, 1, 1, n, n, qi), body(1, 1, 1, n, n, qj), up, relative_overlap));
  return independent_set(name, pairs);
}

inline CaseSet offset_faces_set() {
  std::vector<PosePair> pairs;
  for (double n : {4.0, 8.0, 10.0, 16.0})
    pairs.push_back({body(1, 1, 1, n, n, Quat{}), body(1, 1, 1, n, n, Quat{}, {0.3, -0.2, -1.99})});
  return independent_set("cubes face on face, offset", pairs);
}

inline std::vector<CaseSet> cube_sets() {
  const Quat identity{};
  const Vec3 diagonal = (1.0 / std::sqrt(3.0)) * Vec3{1, 1, 1};
  return {
      cube_set("cubes face on face", identity, identity, 0.01),
      offset_faces_set(),
      cube_set("cubes edge on edge", turn({1, 0, 0}, 0.25 * pi), turn({0, 1, 0}, 0.25 * pi), 0.01),
      cube_set("cube corner on face", turn_onto(diagonal, {0, 0, 1}), identity, 0.01),
      cube_set("cubes nearly parallel faces", identity, turn({1, 0.3, 0}, 0.01), 0.01),
      cube_set("cubes nearly parallel faces 1e-4", identity, turn({1, 0.3, 0}, 1e-4), 0.01)};
}

// Random blocky pairs at one relative overlap.
inline CaseSet blocky_depth_set(Random& random, const std::string& name, double relative_overlap) {
  std::vector<PosePair> pairs;
  for (int k = 0; k < variants; ++k) {
    const double n = random.uniform(4, 10);
    pairs.push_back(
        in_contact(body(1, 1, 1, n, n, random.rotation()),
                   body(1, random.uniform(0.5, 1), 1, n, random.uniform(2, 10), random.rotation()),
                   random.direction(), relative_overlap));
  }
  return independent_set(name, pairs);
}

// Two cubes, i fixed, j turning about the contact normal and tilting, kept at 1 % overlap: the
// contact moves across faces, edges and corners.
inline CaseSet rotating_cubes_set(double n, int poses) {
  CaseSet set;
  set.name = with_blockiness("rotating cubes", n);
  set.sequences = 1;
  set.poses = poses;
  set.warm_start = true;
  const Vec3 up{0, 0, 1};
  for (int p = 0; p < poses; ++p) {
    const double t = double(p) / (poses - 1);
    const Quat qj = turn({0, 0, 1}, 0.5 * pi * t) * turn({1, 0.4, 0}, 0.8 * t);
    set.pairs.push_back(in_contact(body(1, 1, 1, n, n, Quat{}), body(1, 1, 1, n, n, qj), up, 0.01));
  }
  return set;
}

inline std::vector<CaseSet> hard_case_sets(std::uint64_t seed) {
  Random random(seed);
  std::vector<CaseSet> sets = blockiness_sets(random);
  for (CaseSet& s : aspect_sets(random))
    sets.push_back(s);
  sets.push_back(size_ratio_set(random));
  for (CaseSet& s : cube_sets())
    sets.push_back(s);
  sets.push_back(blocky_depth_set(random, "grazing 1e-6", 1e-6));
  sets.push_back(blocky_depth_set(random, "deep 10 %", 0.1));
  sets.push_back(rotating_cubes_set(8, 64));
  sets.push_back(rotating_cubes_set(16, 64));
  return sets;
}

// ------------------------------------------------------------------ random and moving pairs

// Semi-axes (1, r^t, r) with the aspect r log-uniform in [1/max_aspect, max_aspect], t uniform
// in [0, 1]: the longest over the shortest is at most max_aspect.
inline SuperquadricShape random_shape(Random& random, double max_aspect, double scale) {
  const double aspect = random.log_uniform(1.0 / max_aspect, max_aspect);
  const double middle = std::pow(aspect, random.uniform(0, 1));
  return make_superquadric(scale, scale * middle, scale * aspect, random.uniform(2, 10),
                           random.uniform(2, 10));
}

// n1, n2 in [2, 10], aspect ratios up to 5, a size ratio up to 10 in a third of the pairs,
// projected overlap log-uniform in [1e-6, 0.1] of the smaller equivalent radius.
inline PosePair random_pair(Random& random) {
  const double scale_j = random.uniform(0, 1) < 1.0 / 3 ? random.uniform(0.1, 1) : 1.0;
  const PosedSuperquadric i = pose_superquadric(random_shape(random, 5, 1), {}, random.rotation());
  const PosedSuperquadric j =
      pose_superquadric(random_shape(random, 5, scale_j), {}, random.rotation());
  return in_contact(i, j, random.direction(), random.log_uniform(1e-6, 0.1));
}

inline CaseSet random_set(int count, std::uint64_t seed) {
  Random random(seed);
  std::vector<PosePair> pairs;
  for (int k = 0; k < count; ++k)
    pairs.push_back(random_pair(random));
  return independent_set("random", pairs);
}

// One collision: both bodies spin, the line of centres turns slowly, and the projected overlap
// along it follows peak (1.25 sin(pi t) - 0.25) for t in [0, 1]: the pair approaches, overlaps
// by up to peak and separates again, as in a simulation with `poses` steps per collision.
inline std::vector<PosePair> collision_poses(Random& random, int poses) {
  const SuperquadricShape si = random_shape(random, 5, 1), sj = random_shape(random, 5, 1);
  const Quat qi = random.rotation(), qj = random.rotation();
  const Vec3 spin_i = random.uniform(0, 1) * random.direction();
  const Vec3 spin_j = random.uniform(0, 1) * random.direction();
  const Vec3 normal = random.direction(), swing = 0.3 * random.direction();
  const double peak = random.log_uniform(1e-3, 0.05);
  std::vector<PosePair> sequence;
  for (int p = 0; p < poses; ++p) {
    const double t = double(p) / (poses - 1);
    const PosedSuperquadric i =
        pose_superquadric(si, {}, normalized(quat_from_rotation_vector(t * spin_i) * qi));
    const PosedSuperquadric j =
        pose_superquadric(sj, {}, normalized(quat_from_rotation_vector(t * spin_j) * qj));
    const Vec3 n = rotate(quat_from_rotation_vector(t * swing), normal);
    sequence.push_back(in_contact(i, j, n, peak * (1.25 * std::sin(pi * t) - 0.25)));
  }
  return sequence;
}

inline CaseSet moving_set(int sequences, int poses, std::uint64_t seed, bool warm_start) {
  Random random(seed);
  CaseSet set;
  set.name = warm_start ? "moving" : "moving, cold start";
  set.sequences = sequences;
  set.poses = poses;
  set.warm_start = warm_start;
  for (int s = 0; s < sequences; ++s)
    for (const PosePair& pair : collision_poses(random, poses))
      set.pairs.push_back(pair);
  return set;
}

} // namespace kdem::narrow_phase_bench
