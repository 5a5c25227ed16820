// The union-volume integration of clumps (shapes/clump_properties.hpp): its cost against the
// precision asked for, and the error it reaches. For each requested precision from 1e-2 to 1e-6:
// the wall time (median of --repeat runs), the grid levels evaluated, the estimated precision,
// and the true errors where a reference exists: two unit spheres 1.2 apart against the lens
// closed form (volume: `volume_error`), and for the book's spherocylinder and a clump of eight
// non-integer-exponent superquadrics the change from the result at 1e-7
// (`volume_change_from_finest`; the refinement stops at its cost cap before that precision, so
// the finest result is the capped one, whose own error the tests measure); for all three the
// largest inertia entry's change from the finest result relative to its trace.
//
//   kdem_bench_union_precision [--repeat R] [--out FILE.json]
//
// Host code, one thread.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "shapes/clump_properties.hpp"
#include "shapes/sphere.hpp"
#include "src/build_info.hpp"

namespace {

using namespace kdem;

struct Clump {
  std::string name;
  std::vector<ClumpElement> elements;
  double exact_volume = 0; // 0: none known, the finest result is the reference
};

ClumpElement element(double a, double b, double c, double n1, double n2, Vec3 centre,
                     Quat orientation = Quat{1, 0, 0, 0}) {
  return ClumpElement{make_superquadric(a, b, c, n1, n2), centre, normalized(orientation)};
}

std::vector<Clump> clumps() {
  const double d = 1.2; // the lens: V = 2 (4/3 pi) - pi (4 + d) (2 - d)^2 / 12
  Clump lens{"two_spheres_lens",
             {element(1, 1, 1, 2, 2, {0.31, -0.17, 0.23 - d / 2}),
              element(1, 1, 1, 2, 2, {0.31, -0.17, 0.23 + d / 2})},
             2 * sphere_volume(1) - pi * (4 + d) * (2 - d) * (2 - d) / 12};
  const double r0 = 6e-3;
  Clump spherocylinder{"book_spherocylinder",
                       {element(r0, r0, r0, 10, 2, {0, 0, 0}),
                        element(r0, r0, r0, 2, 2, {0, 0, r0}),
                        element(r0, r0, r0, 2, 2, {0, 0, -r0})}};
  Clump eight{"eight_superquadrics", {}};
  for (int k = 0; k < 8; ++k) {
    const double t = 0.7 * k;
    eight.elements.push_back(element(
        0.6 + 0.05 * k, 0.5, 0.4 + 0.03 * k, 2.5 + 0.4 * k, 3.1 - 0.1 * k,
        0.45 * Vec3{std::cos(t), std::sin(t), 0.3 * k - 1}, Quat{1, 0.1 * k, -0.2, 0.05 * k}));
  }
  return {lens, spherocylinder, eight};
}

double inertia_error(const ClumpMassProperties& a, const ClumpMassProperties& reference) {
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      worst = std::max(
          worst, std::fabs(a.inertia_per_density.m[i][j] - reference.inertia_per_density.m[i][j]));
  return worst / trace(reference.inertia_per_density);
}

} // namespace

int main(int argc, char** argv) {
  int repeat = 3;
  std::string out = "perf/results/union_precision.json";
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--repeat") == 0 && k + 1 < argc)
      repeat = std::stoi(argv[++k]);
    else if (std::strcmp(argv[k], "--out") == 0 && k + 1 < argc)
      out = argv[++k];
    else {
      std::fprintf(stderr, "usage: kdem_bench_union_precision [--repeat R] [--out FILE.json]\n");
      return 2;
    }
  }
  const std::vector<double> requested = {1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6};
  std::string json = "{\n  \"benchmark\": \"union_precision\",\n  \"git_hash\": \"" +
                     std::string(kdem::git_hash()) +
                     "\",\n  \"repeat\": " + std::to_string(repeat) + ",\n  \"clumps\": [\n";
  const std::vector<Clump> all = clumps();
  for (std::size_t c = 0; c < all.size(); ++c) {
    const Clump& clump = all[c];
    const ClumpMassProperties reference = clump_mass_properties(clump.elements, 1e-7);
    json += "    {\"name\": \"" + clump.name +
            "\", \"finest_estimated_precision\": " + std::to_string(reference.relative_precision) +
            ", \"finest_grid_levels\": " + std::to_string(reference.grid_levels) +
            ", \"runs\": [\n";
    for (std::size_t r = 0; r < requested.size(); ++r) {
      std::vector<double> seconds;
      ClumpMassProperties props;
      for (int k = 0; k < repeat; ++k) {
        const auto start = std::chrono::steady_clock::now();
        props = clump_mass_properties(clump.elements, requested[r]);
        seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      std::sort(seconds.begin(), seconds.end());
      const double volume_reference =
          clump.exact_volume > 0 ? clump.exact_volume : reference.volume;
      char row[512];
      std::snprintf(row, sizeof row,
                    "      {\"requested\": %.1e, \"seconds\": %.4g, \"grid_levels\": %d, "
                    "\"estimated_precision\": %.3e, \"%s\": %.3e, "
                    "\"inertia_change_from_finest\": %.3e}%s\n",
                    requested[r], seconds[seconds.size() / 2], props.grid_levels,
                    props.relative_precision,
                    clump.exact_volume > 0 ? "volume_error" : "volume_change_from_finest",
                    props.volume / volume_reference - 1, inertia_error(props, reference),
                    r + 1 < requested.size() ? "," : "");
      json += row;
      std::printf("%-22s %.0e  %8.4f s  levels %2d  estimate %.2e  volume %+.2e\n",
                  clump.name.c_str(), requested[r], seconds[seconds.size() / 2], props.grid_levels,
                  props.relative_precision, props.volume / volume_reference - 1);
    }
    json += std::string("    ]}") + (c + 1 < all.size() ? "," : "") + "\n";
  }
  json += "  ]\n}\n";
  const std::string tmp = out + ".tmp";
  std::ofstream(tmp) << json;
  std::rename(tmp.c_str(), out.c_str());
  return 0;
}
