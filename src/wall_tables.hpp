#pragma once
// The wall tables of the kernels built from the host's element table: the elements on the
// device, and the lookup of kernels/wall_bins.hpp (per wall its element range and, for a mesh,
// the grid of cell lists over its triangles) on the host and the device.
#include <vector>

#include "../kernels/walls.hpp"
#include "wall_builder.hpp"

namespace kdem {

// Rows of ints, as the host side of a RaggedTable<int>.
struct HostRaggedTable {
  std::vector<int> offsets{0};
  std::vector<int> values;

  int rows() const { return int(offsets.size()) - 1; }
  int size(int row) const { return offsets[row + 1] - offsets[row]; }
  const int& operator()(int row, int k) const { return values[offsets[row] + k]; }
};

struct WallBinTable {
  std::vector<WallLookup> walls;
  HostRaggedTable cells;
  double reach = 0; // m, the reach the grids were built for
};

// The lookup of `wall_count` walls whose elements `table` holds (each wall's contiguous), with
// grids over the triangles of mesh walls for `reach` (> 0): cells of the reach, grown while the
// grid would have more than max(4096, 16 x its triangles) cells.
WallBinTable bin_wall_elements(const WallElementTable& table, int wall_count, double reach);

// The host side of for_each_candidate_element: visit(e) for the elements of wall w that may lie
// within `reach` of the reference-frame point p, ascending.
template <class Visit>
void for_each_candidate_on_host(const WallBinTable& bins, int w, Vec3 p, double reach,
                                Visit&& visit) {
  const WallLookup& wall = bins.walls[w];
  const CandidateSource source = candidate_source(wall, p, reach);
  if (source.every_element) {
    for (int e = wall.first_element; e < wall.end_element; ++e)
      visit(e);
  } else if (source.row >= 0) {
    for (int k = 0; k < bins.cells.size(source.row); ++k)
      visit(bins.cells(source.row, k));
  }
}

WallElements upload_wall_elements(const WallElementTable& table);
void upload_wall_lookup(WallSet& walls, const WallBinTable& bins);

} // namespace kdem
