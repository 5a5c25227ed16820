#pragma once
// Where to look for the wall elements near a point: per wall the range of its elements and, for
// a mesh, a uniform grid over its triangles in the wall's reference frame, so that the triangles
// within reach of a particle are found among those of one cell, not among all of the mesh.
//
// A grid is built for a reach R (the largest particle radius plus the skin). A triangle is listed
// in every cell whose centre lies within R + h sqrt(3) / 2 of it (h: cell size), so a cell lists
// every triangle within R of any point inside it, and a point outside the grid (the triangles'
// box grown by R) is farther than R from all of them. Lists hold element ids in ascending order:
// the candidates come out in the same order as from a loop over all elements.
#include "../shapes/math.hpp"
#include "../shapes/vec3.hpp"
#include "ragged_table.hpp"

namespace kdem {

struct WallLookup {
  int first_element = 0, end_element = 0; // the wall's elements, contiguous
  double origin[3] = {0, 0, 0};           // m, reference frame
  double cell_size = 0;                   // m; 0: no grid, every element is a candidate
  int dims[3] = {0, 0, 0};
  int first_cell = 0; // row of the grid's cell 0 in the table of cell lists
  double reach = 0;   // m, the R the grid was built for

  KOKKOS_INLINE_FUNCTION bool binned() const { return cell_size > 0; }
  // The grid's cell holding reference-frame point p, or -1 outside the grid.
  KOKKOS_INLINE_FUNCTION int cell_of(Vec3 p) const {
    const double x[3] = {p.x, p.y, p.z};
    int c[3];
    for (int a = 0; a < 3; ++a) {
      const double s = math::floor((x[a] - origin[a]) / cell_size);
      if (!(s >= 0 && s < dims[a]))
        return -1;
      c[a] = int(s);
    }
    return c[0] + dims[0] * (c[1] + dims[1] * c[2]);
  }
};

// Where the elements of `wall` that may lie within `reach` of the reference-frame point p are:
// all of the wall's (no grid, or a grid built for a smaller reach), the list of the grid's cell
// row `row`, or none (p outside the grid).
struct CandidateSource {
  bool every_element = false;
  int row = -1;
};

KOKKOS_INLINE_FUNCTION CandidateSource candidate_source(const WallLookup& wall, Vec3 p,
                                                        double reach) {
  CandidateSource source;
  if (!wall.binned() || reach > wall.reach) {
    source.every_element = true;
    return source;
  }
  const int cell = wall.cell_of(p);
  source.row = cell < 0 ? -1 : wall.first_cell + cell;
  return source;
}

// Calls visit(e) for every element of `wall` that may lie within `reach` of p, in ascending
// order (see candidate_source); `cells` is the device table of cell lists.
template <class Visit>
KOKKOS_INLINE_FUNCTION void for_each_candidate_element(const WallLookup& wall,
                                                       const RaggedTable<int>& cells, Vec3 p,
                                                       double reach, Visit&& visit) {
  const CandidateSource source = candidate_source(wall, p, reach);
  if (source.every_element) {
    for (int e = wall.first_element; e < wall.end_element; ++e)
      visit(e);
    return;
  }
  if (source.row < 0)
    return;
  const int listed = cells.size(source.row);
  for (int k = 0; k < listed; ++k)
    visit(cells(source.row, k));
}

} // namespace kdem
