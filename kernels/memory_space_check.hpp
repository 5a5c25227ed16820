#pragma once
// A host memory space that host code may not touch, for checking on a machine without a GPU
// that the engine keeps the discipline a GPU build needs: engine data is read and written only
// inside kernels, and reaches the host only through explicit mirrors and deep_copy.
//
// CheckedMemorySpace<Exec> allocates host memory but is, for Kokkos, a space distinct from
// HostSpace that HostSpace cannot access (a LogicalMemorySpace without shared access), so
//  - create_mirror_view makes a real host copy and deep_copy really copies, as with CUDA;
//  - every View element access runs Kokkos' space check, which here passes only while a
//    kernel (parallel_for/reduce/scan) or a deep_copy is running, as tracked by Kokkos Tools
//    callbacks; any other host access aborts with the message below (on a GPU it would read
//    device memory from the host).
// The `memcheck` build preset selects it (KDEM_MEMORY_SPACE); other builds never instantiate it.
//
// Kokkos 4.3 removed LogicalMemorySpace and offers nothing in its place short of writing a
// memory space against Kokkos' internal allocation records, so with Kokkos 4.3 or newer the
// checked space does not exist (KDEM_HAS_CHECKED_MEMORY_SPACE is 0), the memcheck preset is
// refused at configure time (CMakeLists.txt), and every other build works as with Kokkos 3.4.
#include <Kokkos_Core.hpp>

#include <atomic>
#include <cstdint>
#include <type_traits>

namespace kdem {

struct CheckedSpaceName {
  static constexpr const char* get_name() { return "KdemChecked"; }
};

#if KOKKOS_VERSION < 40300
#define KDEM_HAS_CHECKED_MEMORY_SPACE 1
template <class Exec>
using CheckedMemorySpace = Kokkos::Experimental::LogicalMemorySpace<
    Kokkos::HostSpace, Exec, CheckedSpaceName,
    Kokkos::Experimental::LogicalSpaceSharesAccess::no_shared_access>;
#else
#define KDEM_HAS_CHECKED_MEMORY_SPACE 0
#endif

namespace memory_check {

// Kernels and deep copies in progress (the host thread that launches them counts; the threads
// of an OpenMP kernel start after the increment and end before the decrement).
inline std::atomic<int> open_scopes{0};

inline void verify_host_access() {
  if (open_scopes.load(std::memory_order_relaxed) > 0)
    return;
  Kokkos::abort("kdem memory-space check: engine data accessed on the host outside a kernel "
                "(use a mirror and deep_copy; see docs/architecture.md, memory spaces)");
}

// Sees every deep_copy: destination and source space names and labels, and bytes (tests use it
// to check what a time step moves between the engine's space and the host).
using CopyObserver = void (*)(const char* destination_space, const char* destination_label,
                              const char* source_space, const char* source_label,
                              std::uint64_t bytes);
inline CopyObserver copy_observer = nullptr;

inline void open_kernel(const char*, std::uint32_t, std::uint64_t*) {
  ++open_scopes;
}
inline void close_kernel(std::uint64_t) {
  --open_scopes;
}
inline void open_copy(Kokkos_Profiling_SpaceHandle destination, const char* destination_label,
                      const void*, Kokkos_Profiling_SpaceHandle source, const char* source_label,
                      const void*, std::uint64_t bytes) {
  ++open_scopes;
  if (copy_observer)
    copy_observer(destination.name, destination_label, source.name, source_label, bytes);
}
inline void close_copy() {
  --open_scopes;
}

} // namespace memory_check

// True when MemSpace is the checked space: then install_memory_space_check() must run right
// after Kokkos is initialised (every main of the project calls it).
template <class MemSpace> constexpr bool is_checked_space() {
#if KDEM_HAS_CHECKED_MEMORY_SPACE
  return std::is_same<MemSpace, CheckedMemorySpace<typename MemSpace::execution_space>>::value;
#else
  return false;
#endif
}

template <class MemSpace> void install_memory_space_check() {
  if constexpr (is_checked_space<MemSpace>()) {
    namespace tools = Kokkos::Tools::Experimental;
    tools::set_begin_parallel_for_callback(&memory_check::open_kernel);
    tools::set_end_parallel_for_callback(&memory_check::close_kernel);
    tools::set_begin_parallel_reduce_callback(&memory_check::open_kernel);
    tools::set_end_parallel_reduce_callback(&memory_check::close_kernel);
    tools::set_begin_parallel_scan_callback(&memory_check::open_kernel);
    tools::set_end_parallel_scan_callback(&memory_check::close_kernel);
    tools::set_begin_deep_copy_callback(&memory_check::open_copy);
    tools::set_end_deep_copy_callback(&memory_check::close_copy);
  }
}

} // namespace kdem

#if KDEM_HAS_CHECKED_MEMORY_SPACE
namespace Kokkos {
namespace Impl {
// View element access from host code to the checked space: allowed only inside kernels and
// copies (the primary template aborts always, since HostSpace cannot access the space).
template <class Exec>
struct verify_space<Kokkos::HostSpace, kdem::CheckedMemorySpace<Exec>, false> {
  static void check() { kdem::memory_check::verify_host_access(); }
};
} // namespace Impl
} // namespace Kokkos
#endif
