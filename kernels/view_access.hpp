#pragma once
// Reading and writing Vec3 / Quat rows of SoA Views.
#include "../shapes/vec3.hpp"
#include "types.hpp"

namespace kdem {

template <class View> KOKKOS_INLINE_FUNCTION Vec3 load3(const View& v, int i) {
  return {v(i, 0), v(i, 1), v(i, 2)};
}

template <class View> KOKKOS_INLINE_FUNCTION void store3(const View& v, int i, Vec3 a) {
  v(i, 0) = a.x;
  v(i, 1) = a.y;
  v(i, 2) = a.z;
}

template <class View> KOKKOS_INLINE_FUNCTION Quat load_quat(const View& v, int i) {
  return {v(i, 0), v(i, 1), v(i, 2), v(i, 3)};
}

template <class View> KOKKOS_INLINE_FUNCTION void store_quat(const View& v, int i, Quat q) {
  v(i, 0) = q.w;
  v(i, 1) = q.x;
  v(i, 2) = q.y;
  v(i, 3) = q.z;
}

// Row maps for kernels that run over all rows of a store or over the rows of an index list
// (one particle family or pair type of a mixed scene).
struct AllRows {
  KOKKOS_INLINE_FUNCTION int operator()(int k) const { return k; }
};

struct ListedRows {
  IndexView rows;
  KOKKOS_INLINE_FUNCTION int operator()(int m) const { return rows(m); }
};

} // namespace kdem
