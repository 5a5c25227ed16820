#pragma once
// Uniform cell grid, and the deterministic sort of particles by cell (count -> scan -> fill,
// then ids ordered within each cell so that the result does not depend on thread scheduling).
#include "../shapes/math.hpp"
#include "particles.hpp"
#include "view_access.hpp"

namespace kdem {

struct CellGrid {
  double origin[3] = {0, 0, 0};
  double cell_size = 1;
  int dims[3] = {1, 1, 1};

  KOKKOS_INLINE_FUNCTION int cell_count() const { return dims[0] * dims[1] * dims[2]; }
  KOKKOS_INLINE_FUNCTION int coordinate(double x, int axis) const {
    // Clamped before the conversion: a position far outside the grid, or NaN, must not
    // overflow it (NaN goes to cell 0).
    const double c = math::floor((x - origin[axis]) / cell_size);
    return c >= 0 ? (c < dims[axis] ? int(c) : dims[axis] - 1) : 0;
  }
  KOKKOS_INLINE_FUNCTION int flat(int cx, int cy, int cz) const {
    return cx + dims[0] * (cy + dims[1] * cz);
  }
  KOKKOS_INLINE_FUNCTION int cell_of(Vec3 x) const {
    return flat(coordinate(x.x, 0), coordinate(x.y, 1), coordinate(x.z, 2));
  }
};

// Grid covering [lo, hi] with cells no smaller than min_cell_size; cells grow until the grid has
// at most max_cells cells, so that a huge domain cannot exhaust memory.
inline CellGrid make_cell_grid(const double lo[3], const double hi[3], double min_cell_size,
                               long max_cells) {
  CellGrid grid;
  grid.cell_size = min_cell_size;
  for (;;) {
    long total = 1;
    for (int a = 0; a < 3; ++a) {
      grid.origin[a] = lo[a];
      const double extent = hi[a] > lo[a] ? hi[a] - lo[a] : 0.0;
      grid.dims[a] = 1 + static_cast<int>(extent / grid.cell_size);
      total *= grid.dims[a];
    }
    if (total <= max_cells)
      return grid;
    grid.cell_size *= 1.25;
  }
}

// The particles in cell order: slots cell_start(c)..cell_start(c+1) hold the particles of cell
// c. Normally the particle arrays themselves are permuted into that order, so slot = particle
// row; with the sort switched off (for measuring what it gains) they stay where they are and
// particle_in_slot / slot_of_particle map between the two.
struct CellBins {
  CellGrid grid;
  IndexView cell_start; // cell_count + 1
  bool in_cell_order = true;
  IndexView particle_in_slot, slot_of_particle; // only when !in_cell_order

  KOKKOS_INLINE_FUNCTION int particle(int slot) const {
    return in_cell_order ? slot : particle_in_slot(slot);
  }
  KOKKOS_INLINE_FUNCTION int slot(int particle_row) const {
    return in_cell_order ? particle_row : slot_of_particle(particle_row);
  }
};

inline IndexView exclusive_scan_with_total(const IndexView& counts, int& total) {
  const int n = static_cast<int>(counts.extent(0));
  IndexView offsets("offsets", n + 1);
  Kokkos::parallel_scan(
      "kdem::exclusive_scan", RangePolicy(0, n), KOKKOS_LAMBDA(int k, int& running, bool final) {
        const int value = counts(k);
        if (final)
          offsets(k) = running;
        running += value;
        if (final && k == n - 1)
          offsets(n) = running;
      });
  total = 0;
  if (n > 0)
    Kokkos::deep_copy(total, Kokkos::subview(offsets, n));
  return offsets;
}

// Sorts the particle arrays by cell and returns the bins of the sorted order; with
// reorder = false the arrays keep their order and the bins carry the mapping instead.
inline CellBins sort_particles_by_cell(ParticleViews& p, const CellGrid& grid,
                                       bool reorder = true) {
  const int n = p.count;
  const int cells = grid.cell_count();
  auto cell_of_particle = uninitialized<IndexView>("cell_of_particle", n);
  IndexView counts("cell_counts", cells);
  auto position = p.position;
  Kokkos::parallel_for(
      "kdem::bin_count", RangePolicy(0, n), KOKKOS_LAMBDA(int i) {
        const int c = grid.cell_of(load3(position, i));
        cell_of_particle(i) = c;
        Kokkos::atomic_add(&counts(c), 1);
      });
  int total = 0;
  IndexView cell_start = exclusive_scan_with_total(counts, total);
  auto cursor = uninitialized<IndexView>("cell_cursor", cells);
  Kokkos::deep_copy(cursor, Kokkos::subview(cell_start, Kokkos::make_pair(0, cells)));
  auto order = uninitialized<IndexView>("sort_order", n);
  Kokkos::parallel_for(
      "kdem::bin_fill", RangePolicy(0, n), KOKKOS_LAMBDA(int i) {
        const int slot = Kokkos::atomic_fetch_add(&cursor(cell_of_particle(i)), 1);
        order(slot) = i;
      });
  auto id = p.id;
  Kokkos::parallel_for(
      "kdem::bin_order_by_id", RangePolicy(0, cells), KOKKOS_LAMBDA(int c) {
        const int begin = cell_start(c), end = cell_start(c + 1);
        for (int a = begin + 1; a < end; ++a) { // insertion sort: cells hold few particles
          const int moving = order(a);
          int b = a - 1;
          while (b >= begin && id(order(b)) > id(moving)) {
            order(b + 1) = order(b);
            --b;
          }
          order(b + 1) = moving;
        }
      });
  if (reorder) {
    permute_particles(p, order, n);
    return CellBins{grid, cell_start, true, IndexView{}, IndexView{}};
  }
  auto slot_of = uninitialized<IndexView>("slot_of_particle", n);
  Kokkos::parallel_for(
      "kdem::bin_slots", RangePolicy(0, n),
      KOKKOS_LAMBDA(int slot) { slot_of(order(slot)) = slot; });
  return CellBins{grid, cell_start, false, order, slot_of};
}

} // namespace kdem
