#pragma once
// Execution and memory space of one engine build, and the View aliases used by every kernel.
// Each library target is compiled for one backend by defining KDEM_EXEC_SPACE (and, for the
// memory-space check, KDEM_MEMORY_SPACE).
#include <Kokkos_Core.hpp>
#include <cstdint>
#include <string>

#include "memory_space_check.hpp"

#ifndef KDEM_EXEC_SPACE
#define KDEM_EXEC_SPACE Kokkos::DefaultExecutionSpace
#endif
// The `memcheck` preset sets kdem::CheckedMemorySpace<KDEM_EXEC_SPACE> (memory_space_check.hpp).
#ifndef KDEM_MEMORY_SPACE
#define KDEM_MEMORY_SPACE KDEM_EXEC_SPACE::memory_space
#endif

namespace kdem {

using ExecSpace = KDEM_EXEC_SPACE;
using MemSpace = KDEM_MEMORY_SPACE;
using RangePolicy = Kokkos::RangePolicy<ExecSpace>;
// For loops whose work gathers in part of the range, such as the wall contacts of particles
// sorted by cell (those near a floor are contiguous): chunks handed out as threads come free.
// The same results as RangePolicy; each index writes only its own outputs.
using BalancedPolicy = Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;

template <class T> using DeviceView = Kokkos::View<T, MemSpace>;

using Vec3View = DeviceView<double* [3]>;
using QuatView = DeviceView<double* [4]>;
using ScalarView = DeviceView<double*>;
using IndexView = DeviceView<int*>;
using IdView = DeviceView<std::int64_t*>;

// A View whose every entry the caller writes before reading: no zero-filling pass.
template <class View> View uninitialized(const std::string& label, std::size_t rows) {
  return View(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), rows);
}

} // namespace kdem
