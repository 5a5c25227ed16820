#pragma once
// run.json: what a run did and how fast, for people and for scripts that compare runs.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace kdem {

struct RunSummary {
  std::string version;
  std::string git_hash;
  std::string backend; // Kokkos execution space, e.g. "OpenMP", "Cuda"
  int threads = 0;
  std::int64_t particles = 0;
  std::int64_t steps = 0;
  std::int64_t contacts = 0; // active contacts at the end of the run
  std::int64_t narrow_phase_failures = 0;
  double wall_seconds = 0;
  double particle_steps_per_second = 0;
  double largest_overlap_ratio = 0;                  // largest overlap / radius seen
  double simulated_time = 0;                         // s
  double discharged_mass = 0;                        // kg
  double energy_drift = 0;                           // relative
  std::vector<std::pair<std::string, double>> extra; // further named numbers, in this order
};

// A JSON object with the fields above in declaration order and "extra" as a nested object.
// Strings are escaped per RFC 8259; finite numbers are written in the shortest form that reads
// back as the same double; NaN and infinities, which JSON cannot hold, are written as null.
std::string to_json(const RunSummary& summary);

// Writes to_json(summary) atomically to path.
void write_run_json(const std::filesystem::path& path, const RunSummary& summary);

// Helpers, exposed for tests and other JSON writers.
std::string json_string(const std::string& text); // quoted and escaped
std::string json_number(double value);            // or "null"

} // namespace kdem
