#pragma once
// Copies between device Views and flat host vectors (row-major), for output and checkpoints.
#include <string>
#include <vector>

#include "../kernels/types.hpp"

namespace kdem {

template <class View> constexpr int columns_of(const View& view) {
  if constexpr (View::rank == 1)
    return 1;
  else
    return int(view.extent(1));
}

template <class View>
std::vector<typename View::non_const_value_type> flatten_to_host(const View& view, int rows) {
  auto mirror = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  const int columns = columns_of(view);
  std::vector<typename View::non_const_value_type> out(std::size_t(rows) * columns);
  for (int i = 0; i < rows; ++i)
    for (int c = 0; c < columns; ++c) {
      if constexpr (View::rank == 1)
        out[i] = mirror(i);
      else
        out[std::size_t(i) * columns + c] = mirror(i, c);
    }
  return out;
}

// A new View named `label` holding `values` (rows = values.size() / columns).
template <class View>
View view_from_host(const std::string& label,
                    const std::vector<typename View::non_const_value_type>& values, int columns) {
  const int rows = columns > 0 ? int(values.size() / columns) : 0;
  View view(label, rows);
  auto mirror = Kokkos::create_mirror_view(view);
  for (int i = 0; i < rows; ++i)
    for (int c = 0; c < columns; ++c) {
      if constexpr (View::rank == 1)
        mirror(i) = values[i];
      else
        mirror(i, c) = values[std::size_t(i) * columns + c];
    }
  Kokkos::deep_copy(view, mirror);
  return view;
}

} // namespace kdem
