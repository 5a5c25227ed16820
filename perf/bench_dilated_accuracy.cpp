// Speed against error of dilated polyhedra standing in for a superquadric (issue: dilated
// polyhedra, item 7). The superquadric S is meshed at M offset-Fibonacci nodes (the builders'
// lattice), each node moved inward by r along S's normal there, and the mesh dilated by r: with
// r below S's smallest radius of curvature, the dilated body is S up to the core's faceting.
// Probe spheres (radius a / 5) touch S at random points, overlapping it by a / 100 along its
// normal there; each contact is computed by the exact sphere-superquadric closest point of the
// superquadric family (the reference) and by the dilated polyhedron's narrow phase, with the
// engine's default contact settings (slack, fade, merging, averaging, normal-cone caps). Per (M,
// r): the median and largest relative overlap error (against a / 100; a probe the polyhedron does
// not touch, `missed`, counts its whole overlap), the median and largest
// normal error (rad; the force-weighted normal of the polyhedron's contact points, averaged as
// the engine does), the time per contact of each method (median of --repeat sweeps, one thread),
// the core's faces and the dilated body's volume against S's; each (M, r) as the lattice
// inscribed in S and scaled to S's volume.
//
//   kdem_bench_dilated_accuracy [--repeat R] [--probes N] [--out FILE.json]
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

#include "kernels/dilated_polyhedron/family.hpp"
#include "shapes/dilated_polyhedron_build.hpp"
#include "shapes/dilated_polyhedron_properties.hpp"
#include "shapes/superquadric_contact.hpp"
#include "shapes/superquadric_properties.hpp"
#include "src/build_info.hpp"
#include "src/core_builders.hpp"

namespace {

using namespace kdem;

struct Shape {
  std::string name;
  SuperquadricShape s;
};

// The engine's contact settings at the scene's defaults (docs/scene.md,
// dilated_polyhedron_contact): cone slack 1e-6 rad, fade 0.002 rad, merging and averaging.
DilatedContactSettings engine_settings() {
  DilatedContactSettings settings;
  settings.slack = ConeSlack::of_angle(1e-6, 0.002);
  return settings;
}

// The lattice of S with each node moved inward by r along S's unit normal there, then scaled
// by `scale` about the centre.
DilatedCore offset_core(const SuperquadricShape& s, int nodes, double r, double scale = 1) {
  const TriangleMesh lattice = superquadric_core(s.a, s.b, s.c, s.n1, s.n2, nodes);
  std::vector<Vec3> points;
  for (const auto& p : lattice.points) {
    const Vec3 x{p[0], p[1], p[2]};
    const ShapeFunction f = superquadric_local<false>(s, x);
    points.push_back(scale * (x - (r / norm(f.gradient)) * f.gradient));
  }
  DilatedCore core = build_dilated_core(points, lattice.triangles, r);
  bound_normal_cones(core, engine_settings().slack);
  return core;
}

struct Probe {
  Vec3 centre;
  double radius = 0;
};

std::vector<Probe> probes(const SuperquadricShape& s, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  const double radius = s.a / 5, overlap = s.a / 100;
  std::vector<Probe> out;
  while (int(out.size()) < count) {
    Vec3 u{g(rng), g(rng), g(rng)};
    u = (1.0 / norm(u)) * u;
    const double gu = std::pow(
        std::pow(std::pow(std::fabs(u.x / s.a), s.n2) + std::pow(std::fabs(u.y / s.b), s.n2),
                 s.n1 / s.n2) +
            std::pow(std::fabs(u.z / s.c), s.n1),
        -1.0 / s.n1);
    const Vec3 surface = gu * u;
    const ShapeFunction f = superquadric_local<false>(s, surface);
    const Vec3 n = (1.0 / norm(f.gradient)) * f.gradient;
    out.push_back(Probe{surface + (radius - overlap) * n, radius});
  }
  return out;
}

using Collected = DeepestContacts<DilatedPolyhedronFamily::contact_points>;

// The contact points of a pair as the engine weighs them (merged, faded and averaged): the
// force-weighted overlap sum_c w_c o_c and normal of their forces.
struct Averaged {
  double overlap = 0;
  Vec3 normal;
  bool touching = false;
};

Averaged averaged(const Collected& found, const DilatedContactSettings& settings) {
  Averaged a;
  if (found.count == 0)
    return a;
  Vec3 force;
  found.weights(settings.averaging, [&](int c, double w) {
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

} // namespace

int main(int argc, char** argv) {
  int repeat = 5, probe_count = 2000;
  std::string out = "perf/results/dilated_accuracy.json";
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--repeat") == 0 && k + 1 < argc)
      repeat = std::stoi(argv[++k]);
    else if (std::strcmp(argv[k], "--probes") == 0 && k + 1 < argc)
      probe_count = std::stoi(argv[++k]);
    else if (std::strcmp(argv[k], "--out") == 0 && k + 1 < argc)
      out = argv[++k];
    else {
      std::fprintf(stderr, "usage: kdem_bench_dilated_accuracy [--repeat R] [--probes N] "
                           "[--out FILE.json]\n");
      return 2;
    }
  }
  // Smallest radii of curvature: the ellipsoid's c^2 / a = 0.25; the blocky superquadric's about
  // 0.2 at its rounded edges, so r stays at or below 0.1.
  const std::vector<Shape> shapes = {{"ellipsoid_1_0.7_0.5", make_superquadric(1, 0.7, 0.5, 2, 2)},
                                     {"blocky_1_0.8_0.6_n4", make_superquadric(1, 0.8, 0.6, 4, 4)}};
  const std::vector<int> node_counts = {50, 100, 200, 500, 1000, 2000, 5000};
  const std::vector<double> radii = {0.01, 0.03, 0.1};
  const NarrowPhaseControls controls;
  std::string json = "{\n  \"benchmark\": \"dilated_accuracy\",\n  \"git_hash\": \"" +
                     std::string(git_hash()) + "\",\n  \"repeat\": " + std::to_string(repeat) +
                     ",\n  \"probes\": " + std::to_string(probe_count) + ",\n  \"shapes\": [\n";
  const DilatedContactSettings settings = engine_settings();
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const SuperquadricShape& s = shapes[k].s;
    const PosedSuperquadric body{s, Vec3{}, identity3()};
    const std::vector<Probe> all = probes(s, probe_count, 17 + unsigned(k));
    std::vector<NarrowPhaseResult> exact;
    for (const Probe& p : all)
      exact.push_back(
          sphere_superquadric_contact(p.centre, p.radius, body, MidwayState{}, controls));
    const double exact_seconds = seconds_per_call(repeat, probe_count, [&] {
      double sink = 0;
      for (const Probe& p : all)
        sink += sphere_superquadric_contact(p.centre, p.radius, body, MidwayState{}, controls)
                    .geometry.overlap;
      if (sink == 12345.0)
        std::puts("");
    });
    const double volume = superquadric_volume(s);
    json += "    {\"name\": \"" + shapes[k].name +
            "\", \"exact_ns_per_contact\": " + std::to_string(1e9 * exact_seconds) +
            ", \"runs\": [\n";
    bool first = true;
    for (int nodes : node_counts)
      for (double r : radii)
        for (bool matched : {false, true}) {
          // Matched: the core scaled so that the dilated body has S's volume (the book's rescaling
          // of the nodes, Sect. 4.3.2), which centres the faceting error on S instead of inside it.
          const DilatedCore inscribed = offset_core(s, nodes, r * s.a);
          const double inscribed_volume =
              dilated_mass_properties(inscribed, DilatedMassOptions{}).volume;
          const DilatedCore core =
              matched ? offset_core(s, nodes, r * s.a, std::cbrt(volume / inscribed_volume))
                      : inscribed;
          std::vector<double> overlap_errors, normal_errors;
          int missed = 0;
          for (std::size_t p = 0; p < all.size(); ++p) {
            Collected found(settings, core.dilation());
            dilated_sphere_contacts(core, all[p].centre, all[p].radius, settings.slack, found);
            const Averaged a = averaged(found, settings);
            if (!exact[p].geometry.touching)
              continue; // not by construction: the exact solve failed (counted none so far)
            if (!a.touching) {
              ++missed; // the polyhedron lies inside S there: its overlap error is the whole
                        // overlap
              overlap_errors.push_back(exact[p].geometry.overlap / (s.a / 100));
              continue;
            }
            overlap_errors.push_back(std::fabs(a.overlap - exact[p].geometry.overlap) /
                                     (s.a / 100));
            // found: from the sphere towards the core; exact: from the superquadric to the sphere.
            normal_errors.push_back(angle_between(-a.normal, exact[p].geometry.normal));
          }
          const double seconds = seconds_per_call(repeat, probe_count, [&] {
            int sink = 0;
            for (const Probe& p : all) {
              Collected found(settings, core.dilation());
              dilated_sphere_contacts(core, p.centre, p.radius, settings.slack, found);
              sink += found.count;
            }
            if (sink == -1)
              std::puts("");
          });
          const double core_volume =
              matched ? dilated_mass_properties(core, DilatedMassOptions{}).volume
                      : inscribed_volume;
          char row[700];
          std::snprintf(row, sizeof row,
                        "%s      {\"nodes\": %d, \"faces\": %zu, \"dilation_over_a\": %g, "
                        "\"volume_matched\": %s, "
                        "\"overlap_error_median\": %.4g, \"overlap_error_max\": %.4g, "
                        "\"normal_error_median_rad\": %.4g, \"normal_error_max_rad\": %.4g, "
                        "\"missed\": %d, \"ns_per_contact\": %.1f, \"volume_error\": %.4g}",
                        first ? "" : ",\n", nodes, core.faces.size(), r, matched ? "true" : "false",
                        median(overlap_errors),
                        overlap_errors.empty()
                            ? 0.0
                            : *std::max_element(overlap_errors.begin(), overlap_errors.end()),
                        median(normal_errors),
                        normal_errors.empty()
                            ? 0.0
                            : *std::max_element(normal_errors.begin(), normal_errors.end()),
                        missed, 1e9 * seconds, core_volume / volume - 1);
          json += row;
          first = false;
          std::fprintf(stderr, "%s nodes %d r %g matched %d done\n", shapes[k].name.c_str(), nodes,
                       r, int(matched));
        }
    json += std::string("\n    ]}") + (k + 1 < shapes.size() ? "," : "") + "\n";
  }
  json += "  ]\n}\n";
  const std::string tmp = out + ".tmp";
  std::ofstream(tmp) << json;
  std::rename(tmp.c_str(), out.c_str());
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
