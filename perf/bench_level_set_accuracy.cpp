// Speed against error of level-set bodies standing in for a superquadric (issue: level sets,
// item 5). The superquadric S is meshed at M Fibonacci nodes (the builders' lattice) and made a
// level-set body (a signed-distance grid of spacing h, surface points at least l apart). Pairs
// of S at random orientations and directions are placed so that the superquadric family's exact
// narrow phase (the midway point) finds them overlapping by a / 100 (bisection on the distance);
// each pair is then computed as two level-set bodies, as the engine does (both bodies' points in
// the other's grid, merged into patches, averaged). Per (M, h, l): the median and largest
// relative overlap error (against a / 100; a pair the level sets do not find, `missed`, counts
// its whole overlap), the median and largest normal error (rad; the force-weighted normal of the
// patches), the time per pair of each method (median of --repeat sweeps, one thread): the
// engine's (the points in the cells under the other body's box) and with every point tested;
// and the memory per template (grid, points and cells).
//
//   kdem_bench_level_set_accuracy [--repeat R] [--pairs N] [--out FILE.json]
//   kdem_bench_level_set_accuracy --pairs-in POSES.txt --pairs-eval-out FILE.csv
//
// The second form evaluates given poses (a peer's or a run's; one pair per line: a's shape
// index and b's, a's rotation and b's row by row, b's centre from a's, in units of a) at the
// defaults (8000 nodes, h = 2c / 40, points 2 h apart): the exact overlap and normal and the
// level sets'.
//
// Host code, one thread.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "kernels/level_set/patches.hpp"
#include "shapes/level_set_build.hpp"
#include "shapes/superquadric_contact.hpp"
#include "src/build_info.hpp"
#include "src/core_builders.hpp"

namespace {

using namespace kdem;

struct Shape {
  std::string name;
  SuperquadricShape s;
};

struct Pair {
  Mat3 rotation_a, rotation_b;
  Vec3 offset; // b's centre from a's
  NarrowPhaseResult exact;
};

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Quat q{g(rng), g(rng), g(rng), g(rng)};
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return rotation_matrix(Quat{q.w / n, q.x / n, q.y / n, q.z / n});
}

// Pairs overlapping by `overlap` in the exact narrow phase: b moved along a random direction
// until the midway overlap is met (bisection on the distance, 60 halvings).
std::vector<Pair> pairs(const SuperquadricShape& s, int count, double overlap, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  const NarrowPhaseControls controls;
  std::vector<Pair> out;
  while (int(out.size()) < count) {
    Pair p;
    p.rotation_a = random_rotation(rng);
    p.rotation_b = random_rotation(rng);
    Vec3 u{g(rng), g(rng), g(rng)};
    u = (1.0 / norm(u)) * u;
    const PosedSuperquadric a{s, Vec3{}, p.rotation_a};
    const auto at = [&](double d) {
      return superquadric_pair_contact(a, PosedSuperquadric{s, d * u, p.rotation_b}, MidwayState{},
                                       controls);
    };
    // Touching deeply at 0, apart beyond the bounding spheres; a failed solve (deep overlaps)
    // counts as too close.
    double near = 0, far = 2.5 * s.a;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (near + far);
      const NarrowPhaseResult r = at(mid);
      const bool too_close = r.status == 2 || (r.geometry.touching && r.geometry.overlap > overlap);
      (too_close ? near : far) = mid;
    }
    p.offset = far * u;
    p.exact = at(far);
    if (p.exact.status == 0 && p.exact.geometry.touching &&
        std::fabs(p.exact.geometry.overlap - overlap) < 1e-3 * overlap)
      out.push_back(p);
  }
  return out;
}

// The pairs of each shape as JSON, for a peer to evaluate the same poses: the shape, its
// rotations (row-major), b's offset, and the exact overlap and normal (from b towards a).
std::string pairs_json(const Shape& shape, const std::vector<Pair>& all) {
  const SuperquadricShape& s = shape.s;
  std::string json = "    {\"name\": \"" + shape.name + "\", \"half_axes\": [" +
                     std::to_string(s.a) + ", " + std::to_string(s.b) + ", " + std::to_string(s.c) +
                     "], \"n1\": " + std::to_string(s.n1) + ", \"n2\": " + std::to_string(s.n2) +
                     ", \"pairs\": [\n";
  char row[1200];
  for (std::size_t k = 0; k < all.size(); ++k) {
    const Pair& p = all[k];
    const auto& ra = p.rotation_a.m;
    const auto& rb = p.rotation_b.m;
    const Vec3 n = p.exact.geometry.normal;
    std::snprintf(row, sizeof row,
                  "      {\"rotation_a\": [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, "
                  "%.17g], \"rotation_b\": [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, "
                  "%.17g, %.17g], \"offset\": [%.17g, %.17g, %.17g], \"exact_overlap\": %.17g, "
                  "\"exact_normal\": [%.17g, %.17g, %.17g]}%s\n",
                  ra[0][0], ra[0][1], ra[0][2], ra[1][0], ra[1][1], ra[1][2], ra[2][0], ra[2][1],
                  ra[2][2], rb[0][0], rb[0][1], rb[0][2], rb[1][0], rb[1][1], rb[1][2], rb[2][0],
                  rb[2][1], rb[2][2], p.offset.x, p.offset.y, p.offset.z, p.exact.geometry.overlap,
                  n.x, n.y, n.z, k + 1 < all.size() ? "," : "");
    json += row;
  }
  return json + "    ]}";
}

constexpr int pair_points = max_pair_contact_points;
using Collected = LevelSetPatches<pair_points>;

// The engine's settings (docs/scene.md, level_set_contact).
LevelSetContactSettings engine_settings() {
  return LevelSetContactSettings{};
}

// Turns contacts found with the roles swapped (in b's frame) into a's frame and order.
struct Swapped {
  Collected& found;
  RelativePose b_in_a;
  void add(FeatureContact c) const {
    c.normal = -(b_in_a.rotation * c.normal);
    c.point = b_in_a.point(c.point);
    std::swap(c.feature_a, c.feature_b);
    found.add(c);
  }
};

// Both bodies' points in the other's grid, in a's frame (the engine's level-set pair: the
// points of the cells under the other body's box); one way: b's points in a's grid only (the
// engine's `points: one_way`, b standing for the body of the higher index).
Collected level_set_pair(const LevelSetBodyView& a, const LevelSetBodyView& b, const Pair& p,
                         double equivalent, bool one_way) {
  const LevelSetContactSettings settings = engine_settings();
  const RelativePose b_in_a{transpose(p.rotation_a) * p.rotation_b,
                            transpose_times(p.rotation_a, p.offset)};
  const RelativePose a_in_b{transpose(p.rotation_b) * p.rotation_a,
                            transpose_times(p.rotation_b, -p.offset)};
  Collected found(settings, equivalent);
  points_inside(a, b, b_in_a, found);
  if (one_way)
    return found;
  Swapped swapped{found, b_in_a};
  points_inside(b, a, a_in_b, swapped);
  return found;
}

// The body with all its points in one cell spanning all space, so that a query visits every
// point, as before the points were sorted into cells: the reference the cells are timed against.
struct OneCell {
  LevelSetBodyView view;
  int first[2];
  explicit OneCell(const LevelSetBodyView& body) : view(body), first{0, body.point_count} {
    // Centred on the body's origin, which lies inside it, so that no test skips the cell.
    view.cells.lo = Vec3{-1e6, -1e6, -1e6};
    view.cells.hi = Vec3{1e6, 1e6, 1e6};
    view.cells.size = 2e6;
    view.cells.nx = view.cells.ny = view.cells.nz = 1;
    view.cell_first = first;
  }
  OneCell(const OneCell&) = delete;
};

struct Averaged {
  double overlap = 0;
  Vec3 normal;
  bool touching = false;
};

// The force-weighted overlap sum_c w_c o_c and the normal of the forces (a's frame, from b
// towards a).
Averaged averaged(const Collected& found) {
  Averaged a;
  if (found.count == 0)
    return a;
  Vec3 force;
  found.weights(engine_settings().averaging, [&](int c, double w) {
    a.overlap += w * found.contact[c].overlap;
    force += (w * found.contact[c].overlap) * found.contact[c].normal;
  });
  a.touching = a.overlap > 0;
  if (a.touching)
    a.normal = (1.0 / norm(force)) * force;
  return a;
}

double angle_between(Vec3 a, Vec3 b) {
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double largest(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

template <class F> double seconds_per_call(int repeat, int calls, F&& sweep) {
  std::vector<double> times;
  for (int r = 0; r < repeat; ++r) {
    const auto start = std::chrono::steady_clock::now();
    sweep();
    times.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / calls);
  }
  return median(times);
}

std::vector<Vec3> points_of(const TriangleMesh& mesh) {
  std::vector<Vec3> points;
  for (const auto& q : mesh.points)
    points.push_back(Vec3{q[0], q[1], q[2]});
  return points;
}

// A grid of `cells` across the smallest extent 2c, points `ratio` grid spacings apart.
LevelSetOptions options_for(const SuperquadricShape& s, double cells, double ratio,
                            double cell_size) {
  LevelSetOptions options;
  options.spacing = 2 * s.c / cells;
  options.point_spacing = ratio * options.spacing;
  options.cell_size_in_point_spacings = cell_size;
  return options;
}

double equivalent_radius(const LevelSetBody& body) {
  return std::cbrt(3 * body.mass.volume / (4 * pi));
}

LevelSetBody default_level_set(const SuperquadricShape& s) {
  const TriangleMesh mesh = superquadric_core(s.a, s.b, s.c, s.n1, s.n2, 8000);
  return build_level_set(points_of(mesh), mesh.triangles,
                         options_for(s, 40, 2, LevelSetOptions{}.cell_size_in_point_spacings));
}

// One CSV row per pose of `in_path`: the exact overlap and normal (world, from b towards a;
// status 0 = solved) and the level sets' (force-weighted, as the accuracy sweep).
int evaluate_given_pairs(const std::vector<Shape>& shapes, const std::string& in_path,
                         const std::string& out_path) {
  std::ifstream in(in_path);
  if (!in) {
    std::fprintf(stderr, "%s: cannot be read\n", in_path.c_str());
    return 1;
  }
  std::vector<LevelSetBody> bodies;
  for (const Shape& shape : shapes)
    bodies.push_back(default_level_set(shape.s));
  const NarrowPhaseControls controls;
  std::string csv = "shape_a,shape_b,exact_status,exact_touching,exact_overlap,exact_nx,exact_ny,"
                    "exact_nz,level_set_touching,level_set_overlap,level_set_nx,level_set_ny,"
                    "level_set_nz\n";
  int ka = 0, kb = 0, line = 0;
  while (in >> ka) {
    ++line;
    in >> kb;
    Pair p;
    for (auto* r : {&p.rotation_a, &p.rotation_b})
      for (auto& row : r->m)
        for (double& x : row)
          in >> x;
    in >> p.offset.x >> p.offset.y >> p.offset.z;
    const int count = int(shapes.size());
    if (!in || ka < 0 || ka >= count || kb < 0 || kb >= count) {
      std::fprintf(stderr, "%s: line %d: expected two shape indices below %d and 21 numbers\n",
                   in_path.c_str(), line, count);
      return 1;
    }
    const NarrowPhaseResult exact = superquadric_pair_contact(
        PosedSuperquadric{shapes[ka].s, Vec3{}, p.rotation_a},
        PosedSuperquadric{shapes[kb].s, p.offset, p.rotation_b}, MidwayState{}, controls);
    const Averaged a = averaged(level_set_pair(
        view_of(bodies[ka]), view_of(bodies[kb]), p,
        std::min(equivalent_radius(bodies[ka]), equivalent_radius(bodies[kb])), false));
    const Vec3 n = p.rotation_a * a.normal;
    char row[600];
    std::snprintf(row, sizeof row,
                  "%d,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g\n", ka, kb,
                  exact.status, int(exact.geometry.touching), exact.geometry.overlap,
                  exact.geometry.normal.x, exact.geometry.normal.y, exact.geometry.normal.z,
                  int(a.touching), a.overlap, n.x, n.y, n.z);
    csv += row;
  }
  const std::string tmp = out_path + ".tmp";
  std::ofstream(tmp) << csv;
  std::rename(tmp.c_str(), out_path.c_str());
  std::printf("wrote %s (%d pairs)\n", out_path.c_str(), line);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  int repeat = 5, pair_count = 300;
  double cell_size = LevelSetOptions{}.cell_size_in_point_spacings;
  bool quick = false, one_way = false;
  std::string pairs_out, pairs_in, pairs_eval_out;
  std::string out = "perf/results/level_set_accuracy.json";
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--repeat") == 0 && k + 1 < argc)
      repeat = std::stoi(argv[++k]);
    else if (std::strcmp(argv[k], "--pairs") == 0 && k + 1 < argc)
      pair_count = std::stoi(argv[++k]);
    else if (std::strcmp(argv[k], "--out") == 0 && k + 1 < argc)
      out = argv[++k];
    else if (std::strcmp(argv[k], "--cell-size") == 0 && k + 1 < argc)
      cell_size = std::stod(argv[++k]);
    else if (std::strcmp(argv[k], "--quick") == 0)
      quick = true;
    else if (std::strcmp(argv[k], "--one-way") == 0)
      one_way = true;
    else if (std::strcmp(argv[k], "--pairs-out") == 0 && k + 1 < argc)
      pairs_out = argv[++k];
    else if (std::strcmp(argv[k], "--pairs-in") == 0 && k + 1 < argc)
      pairs_in = argv[++k];
    else if (std::strcmp(argv[k], "--pairs-eval-out") == 0 && k + 1 < argc)
      pairs_eval_out = argv[++k];
    else {
      std::fprintf(stderr, "usage: kdem_bench_level_set_accuracy [--repeat R] [--pairs N] "
                           "[--out FILE.json] [--cell-size POINT_SPACINGS] [--quick] [--one-way] "
                           "[--pairs-out PAIRS.json] | --pairs-in POSES.txt --pairs-eval-out "
                           "FILE.csv\n");
      return 2;
    }
  }
  const std::vector<Shape> shapes = {{"ellipsoid_1_0.7_0.5", make_superquadric(1, 0.7, 0.5, 2, 2)},
                                     {"blocky_1_0.8_0.6_n4", make_superquadric(1, 0.8, 0.6, 4, 4)}};
  if (!pairs_in.empty() || !pairs_eval_out.empty()) {
    if (pairs_in.empty() || pairs_eval_out.empty()) {
      std::fprintf(stderr, "--pairs-in and --pairs-eval-out go together\n");
      return 2;
    }
    return evaluate_given_pairs(shapes, pairs_in, pairs_eval_out);
  }
  // --quick: the default resolution and one finer point spacing only.
  const std::vector<int> node_counts =
      quick ? std::vector<int>{8000} : std::vector<int>{2000, 8000};
  // Grid spacings as fractions of the smallest extent 2c; point spacings as multiples of h.
  const std::vector<double> cells_across =
      quick ? std::vector<double>{40} : std::vector<double>{10, 20, 40, 80};
  const std::vector<double> point_over_grid =
      quick ? std::vector<double>{2, 1} : std::vector<double>{2, 1, 0.5};
  const NarrowPhaseControls controls;
  std::string json = "{\n  \"benchmark\": \"level_set_accuracy\",\n  \"git_hash\": \"" +
                     std::string(git_hash()) + "\",\n  \"repeat\": " + std::to_string(repeat) +
                     ",\n  \"pairs\": " + std::to_string(pair_count) +
                     ",\n  \"cell_size_in_point_spacings\": " + std::to_string(cell_size) +
                     ",\n  \"points\": \"" + (one_way ? "one_way" : "both_ways") + "\"" +
                     ",\n  \"shapes\": [\n";
  std::string pair_sets;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const SuperquadricShape& s = shapes[k].s;
    const double overlap = s.a / 100;
    const std::vector<Pair> all = pairs(s, pair_count, overlap, 29 + unsigned(k));
    pair_sets += (k ? ",\n" : "") + pairs_json(shapes[k], all);
    const double exact_seconds = seconds_per_call(repeat, pair_count, [&] {
      double sink = 0;
      for (const Pair& p : all)
        sink += superquadric_pair_contact(PosedSuperquadric{s, Vec3{}, p.rotation_a},
                                          PosedSuperquadric{s, p.offset, p.rotation_b},
                                          MidwayState{}, controls)
                    .geometry.overlap;
      if (sink == 12345.0)
        std::puts("");
    });
    json += "    {\"name\": \"" + shapes[k].name +
            "\", \"exact_ns_per_pair\": " + std::to_string(1e9 * exact_seconds) + ", \"runs\": [\n";
    bool first = true;
    for (int nodes : node_counts) {
      const TriangleMesh mesh = superquadric_core(s.a, s.b, s.c, s.n1, s.n2, nodes);
      const std::vector<Vec3> points = points_of(mesh);
      for (double cells : cells_across)
        for (double ratio : point_over_grid) {
          const LevelSetOptions options = options_for(s, cells, ratio, cell_size);
          const auto build_start = std::chrono::steady_clock::now();
          const LevelSetBody body = build_level_set(points, mesh.triangles, options);
          const double build_seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
          const LevelSetBodyView view = view_of(body);
          const double equivalent = equivalent_radius(body);
          std::vector<double> overlap_errors, normal_errors;
          int missed = 0;
          for (const Pair& p : all) {
            const Averaged a = averaged(level_set_pair(view, view, p, equivalent, one_way));
            if (!a.touching) {
              ++missed;
              overlap_errors.push_back(1.0);
              continue;
            }
            overlap_errors.push_back(std::fabs(a.overlap - p.exact.geometry.overlap) / overlap);
            // Level sets: in a's frame, from b towards a; exact: world, from j (b) towards i (a).
            normal_errors.push_back(
                angle_between(p.rotation_a * a.normal, p.exact.geometry.normal));
          }
          const double seconds = seconds_per_call(repeat, pair_count, [&] {
            int sink = 0;
            for (const Pair& p : all)
              sink += level_set_pair(view, view, p, equivalent, one_way).count;
            if (sink == -1)
              std::puts("");
          });
          const OneCell every_point(view);
          const double every_point_seconds = seconds_per_call(repeat, pair_count, [&] {
            int sink = 0;
            for (const Pair& p : all)
              sink +=
                  level_set_pair(every_point.view, every_point.view, p, equivalent, one_way).count;
            if (sink == -1)
              std::puts("");
          });
          char row[1000];
          std::snprintf(
              row, sizeof row,
              "%s      {\"nodes\": %d, \"cells_across\": %g, \"grid_spacing_over_a\": %.4g, "
              "\"point_spacing_over_a\": %.4g, \"grid_nodes\": %zu, \"surface_points\": %zu, "
              "\"grid_bytes\": %zu, \"point_bytes\": %zu, \"build_seconds\": %.3f, "
              "\"overlap_error_median\": %.4g, \"overlap_error_max\": %.4g, "
              "\"normal_error_median_rad\": %.4g, \"normal_error_max_rad\": %.4g, "
              "\"missed\": %d, \"ns_per_pair\": %.1f, \"ns_per_pair_every_point\": %.1f}",
              first ? "" : ",\n", nodes, cells, options.spacing / s.a, options.point_spacing / s.a,
              body.values.size(), body.surface_points.size(), body.grid_bytes(), body.point_bytes(),
              build_seconds, median(overlap_errors), largest(overlap_errors), median(normal_errors),
              largest(normal_errors), missed, 1e9 * seconds, 1e9 * every_point_seconds);
          json += row;
          first = false;
          std::fprintf(stderr,
                       "%s nodes %d cells %g points %g: overlap error median %.3g, %d "
                       "missed, %.0f ns (every point: %.0f ns)\n",
                       shapes[k].name.c_str(), nodes, cells, ratio, median(overlap_errors), missed,
                       1e9 * seconds, 1e9 * every_point_seconds);
        }
    }
    json += std::string("\n    ]}") + (k + 1 < shapes.size() ? "," : "") + "\n";
  }
  json += "  ]\n}\n";
  const std::string tmp = out + ".tmp";
  std::ofstream(tmp) << json;
  std::rename(tmp.c_str(), out.c_str());
  if (!pairs_out.empty()) {
    const std::string pairs_tmp = pairs_out + ".tmp";
    std::ofstream(pairs_tmp) << "{\n  \"git_hash\": \"" << git_hash() << "\",\n  \"shapes\": [\n"
                             << pair_sets << "\n  ]\n}\n";
    std::rename(pairs_tmp.c_str(), pairs_out.c_str());
    std::printf("wrote %s\n", pairs_out.c_str());
  }
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
