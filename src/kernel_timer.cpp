#include "kernel_timer.hpp"

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "../kernels/types.hpp"
#include "atomic_file.hpp"
#include "run_summary.hpp"

namespace kdem {
namespace {

using Clock = std::chrono::steady_clock;

struct OpenKernel {
  std::string label;
  Clock::time_point start;
};

// One timer at a time (Kokkos Tools has one set of callbacks per process).
struct TimerState {
  bool installed = false;
  bool fence = true;
  Kokkos::Tools::Experimental::EventSet previous{};
  std::map<std::string, KernelTally> tallies;
  std::vector<OpenKernel> open; // kernels do not nest on the launching thread; a stack for safety
  std::int64_t bytes = 0, peak = 0;
  struct Allocation {
    std::int64_t size;
    std::string label;
  };
  std::unordered_map<const void*, Allocation> live; // allocations made while installed
};
TimerState state;

void begin_kernel(Kokkos::Tools::beginFunction chained, const char* label, std::uint32_t device,
                  std::uint64_t* id) {
  if (chained)
    chained(label, device, id);
  state.open.push_back({label, Clock::now()});
}

void end_kernel(Kokkos::Tools::endFunction chained, std::uint64_t id) {
  if (state.fence)
    Kokkos::fence();
  if (!state.open.empty()) {
    const OpenKernel& k = state.open.back();
    KernelTally& tally = state.tallies[k.label];
    ++tally.launches;
    tally.seconds += std::chrono::duration<double>(Clock::now() - k.start).count();
    state.open.pop_back();
  }
  if (chained)
    chained(id);
}

void begin_for(const char* l, std::uint32_t d, std::uint64_t* id) {
  begin_kernel(state.previous.begin_parallel_for, l, d, id);
}
void end_for(std::uint64_t id) {
  end_kernel(state.previous.end_parallel_for, id);
}
void begin_reduce(const char* l, std::uint32_t d, std::uint64_t* id) {
  begin_kernel(state.previous.begin_parallel_reduce, l, d, id);
}
void end_reduce(std::uint64_t id) {
  end_kernel(state.previous.end_parallel_reduce, id);
}
void begin_scan(const char* l, std::uint32_t d, std::uint64_t* id) {
  begin_kernel(state.previous.begin_parallel_scan, l, d, id);
}
void end_scan(std::uint64_t id) {
  end_kernel(state.previous.end_parallel_scan, id);
}

bool in_engine_space(const Kokkos_Profiling_SpaceHandle& space) {
  return std::string(space.name) == MemSpace::name();
}

void allocated(Kokkos_Profiling_SpaceHandle space, const char* label, const void* data,
               std::uint64_t size) {
  if (state.previous.allocate_data)
    state.previous.allocate_data(space, label, data, size);
  if (in_engine_space(space)) {
    state.live[data] = {std::int64_t(size), label};
    state.bytes += std::int64_t(size);
    state.peak = std::max(state.peak, state.bytes);
  }
}

void deallocated(Kokkos_Profiling_SpaceHandle space, const char* label, const void* data,
                 std::uint64_t size) {
  if (state.previous.deallocate_data)
    state.previous.deallocate_data(space, label, data, size);
  const auto found = state.live.find(data);
  if (in_engine_space(space) && found != state.live.end()) {
    state.bytes -= found->second.size;
    state.live.erase(found);
  }
}

} // namespace

KernelTimer::KernelTimer(bool fence) {
  if (state.installed)
    throw std::logic_error("KernelTimer: a timer is already installed");
  namespace tools = Kokkos::Tools::Experimental;
  state.previous = tools::get_callbacks();
  state.installed = true;
  state.fence = fence;
  reset();
  state.bytes = state.peak = 0;
  state.live.clear();
  tools::set_allocate_data_callback(&allocated);
  tools::set_deallocate_data_callback(&deallocated);
  tools::set_begin_parallel_for_callback(&begin_for);
  tools::set_end_parallel_for_callback(&end_for);
  tools::set_begin_parallel_reduce_callback(&begin_reduce);
  tools::set_end_parallel_reduce_callback(&end_reduce);
  tools::set_begin_parallel_scan_callback(&begin_scan);
  tools::set_end_parallel_scan_callback(&end_scan);
}

KernelTimer::~KernelTimer() {
  Kokkos::Tools::Experimental::set_callbacks(state.previous);
  state.installed = false;
}

void KernelTimer::reset() {
  state.tallies.clear();
  state.open.clear();
}

const std::map<std::string, KernelTally>& KernelTimer::tallies() const {
  return state.tallies;
}

std::int64_t KernelTimer::bytes_allocated() const {
  return state.bytes;
}

std::int64_t KernelTimer::peak_bytes() const {
  return state.peak;
}

std::map<std::string, std::int64_t> KernelTimer::bytes_by_label() const {
  std::map<std::string, std::int64_t> bytes;
  for (const auto& entry : state.live)
    bytes[entry.second.label] += entry.second.size;
  return bytes;
}

std::string KernelTimer::bytes_by_label_json() const {
  std::ostringstream out;
  out << "{";
  const char* separator = "";
  for (const auto& [label, bytes] : bytes_by_label()) {
    out << separator << json_string(label) << ": " << bytes;
    separator = ", ";
  }
  out << "}";
  return out.str();
}

std::string KernelTimer::to_json(std::int64_t steps, std::int64_t particle_steps,
                                 int particles) const {
  std::ostringstream out;
  out << "{\n  \"backend\": " << json_string(ExecSpace::name())
      << ",\n  \"fenced\": " << (state.fence ? "true" : "false") << ",\n  \"steps\": " << steps
      << ",\n  \"particle_steps\": " << particle_steps << ",\n  \"particles\": " << particles
      << ",\n  \"memory\": {\"space\": " << json_string(MemSpace::name())
      << ", \"bytes\": " << state.bytes << ", \"peak_bytes\": " << state.peak
      << ", \"bytes_per_particle\": "
      << json_number(particles > 0 ? double(state.bytes) / particles : 0.0)
      << ", \"by_label\": " << bytes_by_label_json() << "},\n  \"kernels\": " << kernels_json()
      << "\n}\n";
  return out.str();
}

std::string KernelTimer::kernels_json() const {
  std::ostringstream out;
  out << "{";
  const char* separator = "\n";
  for (const auto& [label, tally] : state.tallies) {
    out << separator << "    " << json_string(label) << ": {\"launches\": " << tally.launches
        << ", \"seconds\": " << json_number(tally.seconds) << "}";
    separator = ",\n";
  }
  out << "\n  }";
  return out.str();
}

void KernelTimer::write_json(const std::filesystem::path& path, std::int64_t steps,
                             std::int64_t particle_steps, int particles) const {
  write_text_atomically(path, to_json(steps, particle_steps, particles));
}

} // namespace kdem
