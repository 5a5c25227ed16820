#pragma once
// A family's template data of varying size per template (element lists, triangle meshes,
// grids, octant axes) in two flat device Views: row t holds values(offsets(t)) up to, not
// including, values(offsets(t + 1)). Built on the host by upload_ragged (src/host_copy.hpp).
#include "types.hpp"

namespace kdem {

template <class T> struct RaggedTable {
  DeviceView<T*> values;
  IndexView offsets; // rows() + 1 entries, offsets(0) = 0, ascending

  KOKKOS_INLINE_FUNCTION int rows() const {
    return offsets.extent(0) > 0 ? int(offsets.extent(0)) - 1 : 0;
  }
  KOKKOS_INLINE_FUNCTION int size(int t) const { return offsets(t + 1) - offsets(t); }
  KOKKOS_INLINE_FUNCTION const T& operator()(int t, int m) const { return values(offsets(t) + m); }
};

} // namespace kdem
