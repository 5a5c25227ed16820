#pragma once
// Time and launch count of every kernel by its label, and the bytes allocated in the engine's
// memory space (now and at the peak), through Kokkos Tools callbacks: what
// `kdem run --kernel-times` writes, and what the benchmarks split into stages. With `fence`
// each kernel is waited for before its time is taken (needed on a GPU, where launches return
// at once; it also removes the overlap of consecutive kernels, so totals are an upper bound).
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

namespace kdem {

struct KernelTally {
  std::int64_t launches = 0;
  double seconds = 0;
};

class KernelTimer {
public:
  // Installs the callbacks (chained after any already set, such as the memory-space check's);
  // one timer at a time.
  explicit KernelTimer(bool fence = true);
  ~KernelTimer(); // restores the callbacks found at construction
  KernelTimer(const KernelTimer&) = delete;
  KernelTimer& operator=(const KernelTimer&) = delete;

  void reset(); // clears the kernel tallies; the memory counts go on
  const std::map<std::string, KernelTally>& tallies() const;
  std::int64_t bytes_allocated() const; // in the engine's memory space, now
  std::int64_t peak_bytes() const;      // the most at any time since construction
  std::map<std::string, std::int64_t> bytes_by_label() const; // now, summed by View label
  std::string bytes_by_label_json() const;                    // {label: bytes, ...}
  // {"kernels": {label: {"launches": n, "seconds": s}, ...}, "steps": steps, "memory": ...}
  std::string to_json(std::int64_t steps, std::int64_t particle_steps, int particles) const;
  std::string kernels_json() const; // {label: {"launches": n, "seconds": s}, ...}
  void write_json(const std::filesystem::path& path, std::int64_t steps,
                  std::int64_t particle_steps, int particles) const;
};

} // namespace kdem
