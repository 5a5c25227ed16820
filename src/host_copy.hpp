#pragma once
// Copies between device Views and flat host vectors (row-major), for output and checkpoints.
#include <array>
#include <string>
#include <vector>

#include "../kernels/ragged_table.hpp"
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

// A new device View named `label` holding `values`, converted element by element.
template <class T, class Host>
DeviceView<T*> upload(const std::string& label, const std::vector<Host>& values) {
  DeviceView<T*> view(label, values.size());
  auto mirror = Kokkos::create_mirror_view(view);
  for (std::size_t k = 0; k < values.size(); ++k)
    mirror(k) = values[k];
  Kokkos::deep_copy(view, mirror);
  return view;
}

// The same for rows of N columns.
template <class View, class Host, std::size_t N>
View upload_rows(const std::string& label, const std::vector<std::array<Host, N>>& rows) {
  View view(label, rows.size());
  auto mirror = Kokkos::create_mirror_view(view);
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (std::size_t c = 0; c < N; ++c)
      mirror(k, c) = rows[k][c];
  Kokkos::deep_copy(view, mirror);
  return view;
}

// A ragged device table named `label` holding `rows` in order, each converted element by
// element.
template <class T, class Host>
RaggedTable<T> upload_ragged(const std::string& label, const std::vector<std::vector<Host>>& rows) {
  std::vector<int> offsets{0};
  std::vector<Host> flat;
  for (const auto& row : rows) {
    flat.insert(flat.end(), row.begin(), row.end());
    offsets.push_back(int(flat.size()));
  }
  return RaggedTable<T>{upload<T>(label + "_values", flat),
                        upload<int>(label + "_offsets", offsets)};
}

} // namespace kdem
