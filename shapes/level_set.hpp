#pragma once
// Level-set bodies (book chapter 5; digest ch4_5 part B): a signed-distance grid in the body
// frame (negative inside) and points on its zero level set. Host and device.
//
// A contact is a surface point of one body found inside the other body's grid with a negative
// interpolated value; the value is the overlap and its gradient the normal (digest B5). Contacts
// are FeatureContacts (shapes/dilated_polyhedron.hpp): normal from body B towards body A, the
// point midway between the surfaces, a surface point's key 1 + its index (0: no point of that
// body).
#include "dilated_polyhedron.hpp"
#include "math.hpp"
#include "vec3.hpp"

namespace kdem {

// A uniform grid of nodes: node (i, j, k) at origin + spacing (i, j, k), 0 <= i < nx etc., its
// value at flat index i + nx (j + ny k).
struct LevelSetGrid {
  Vec3 origin;
  double spacing = 0;
  int nx = 0, ny = 0, nz = 0;

  KOKKOS_INLINE_FUNCTION int index(int i, int j, int k) const { return i + nx * (j + ny * k); }
  KOKKOS_INLINE_FUNCTION int nodes() const { return nx * ny * nz; }
  KOKKOS_INLINE_FUNCTION Vec3 node(int i, int j, int k) const {
    return origin + spacing * Vec3{double(i), double(j), double(k)};
  }
  KOKKOS_INLINE_FUNCTION Vec3 far_corner() const { return node(nx - 1, ny - 1, nz - 1); }
};

// The interpolated signed distance and its gradient (per metre; not normalised).
struct LevelSetSample {
  double value = 0;
  Vec3 gradient;
};

namespace level_set {

// The cell holding coordinate t (in cells from the origin) along an axis of n nodes, and t's
// fraction in it: the last cell takes its far face, so every t in [0, n - 1] has a cell.
KOKKOS_INLINE_FUNCTION int cell_of(double t, int n, double& fraction) {
  int c = int(math::floor(t));
  if (c > n - 2)
    c = n - 2;
  fraction = t - double(c);
  return c;
}

} // namespace level_set

// Book Eqs. 5.12 to 5.16: trilinear interpolation of the node values of the cell holding p
// (body frame) and its gradient, the derivative of the same trilinear form divided by the
// spacing. Returns false, and leaves `sample` alone, when p lies outside the grid's box (or is
// NaN): such a point is outside the body, since the grid holds the body with a margin.
// Exact for a field affine in x, y and z.
KOKKOS_INLINE_FUNCTION bool interpolate_level_set(const LevelSetGrid& grid, const double* values,
                                                  Vec3 p, LevelSetSample& sample) {
  const Vec3 t = (1.0 / grid.spacing) * (p - grid.origin);
  if (!(t.x >= 0 && t.y >= 0 && t.z >= 0 && t.x <= grid.nx - 1 && t.y <= grid.ny - 1 &&
        t.z <= grid.nz - 1))
    return false;
  double x, y, z;
  const int i = level_set::cell_of(t.x, grid.nx, x);
  const int j = level_set::cell_of(t.y, grid.ny, y);
  const int k = level_set::cell_of(t.z, grid.nz, z);
  double v[2][2][2];
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a)
        v[a][b][c] = values[grid.index(i + a, j + b, k + c)];
  // Linear in x first, then y, then z: the value and the three partial derivatives.
  double vx[2][2], dx[2][2];
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b) {
      vx[b][c] = v[0][b][c] + x * (v[1][b][c] - v[0][b][c]);
      dx[b][c] = v[1][b][c] - v[0][b][c];
    }
  double vy[2], dy[2], dxy[2];
  for (int c = 0; c < 2; ++c) {
    vy[c] = vx[0][c] + y * (vx[1][c] - vx[0][c]);
    dy[c] = vx[1][c] - vx[0][c];
    dxy[c] = dx[0][c] + y * (dx[1][c] - dx[0][c]);
  }
  const double per_metre = 1.0 / grid.spacing;
  sample.value = vy[0] + z * (vy[1] - vy[0]);
  sample.gradient =
      per_metre * Vec3{dxy[0] + z * (dxy[1] - dxy[0]), dy[0] + z * (dy[1] - dy[0]), vy[1] - vy[0]};
  return true;
}

// The body's box (body frame) and a uniform grid of cells over it into which the surface points
// are sorted, each cell's points contiguous: points first[c] to first[c + 1] - 1 lie in cell c.
// A query over a box visits only the cells it overlaps; a row of cells along x is one run.
// No point outside the box is inside the body: the trilinear value there is at least the box's
// signed distance (positive), since that distance is convex, at most the body's, and trilinear
// weights reproduce the point they interpolate at.
struct LevelSetPointCells {
  Vec3 lo, hi;     // m, the body's box: that of its mesh
  double size = 1; // m, a cell's edge; cell (0, 0, 0) has its low corner at lo
  int nx = 1, ny = 1, nz = 1;

  KOKKOS_INLINE_FUNCTION int index(int i, int j, int k) const { return i + nx * (j + ny * k); }
  KOKKOS_INLINE_FUNCTION int count() const { return nx * ny * nz; }
  KOKKOS_INLINE_FUNCTION Vec3 centre() const { return 0.5 * (lo + hi); }
  KOKKOS_INLINE_FUNCTION Vec3 half_extent() const { return 0.5 * (hi - lo); }
  // The cell holding coordinate x along an axis (from lo_axis, n cells), clamped to the grid.
  KOKKOS_INLINE_FUNCTION int cell_along(double x, double lo_axis, int n) const {
    const double t = math::floor((x - lo_axis) / size);
    return t < 0 ? 0 : (t > n - 1 ? n - 1 : int(t));
  }
  KOKKOS_INLINE_FUNCTION int cell_of(Vec3 x) const {
    return index(cell_along(x.x, lo.x, nx), cell_along(x.y, lo.y, ny), cell_along(x.z, lo.z, nz));
  }
};

// A level-set body as the contact code reads it: its grid, surface points (body frame) and the
// cells they are sorted into.
struct LevelSetBodyView {
  LevelSetGrid grid;
  const double* values = nullptr;
  const Vec3* points = nullptr;
  int point_count = 0;
  double reach = 0; // m, bounding radius about the body origin: no point beyond is inside
  LevelSetPointCells cells;
  const int* cell_first = nullptr; // cells.count() + 1 offsets into points

  KOKKOS_INLINE_FUNCTION bool sample(Vec3 p, LevelSetSample& s) const {
    return norm2(p) < reach * reach && interpolate_level_set(grid, values, p, s);
  }

  // Calls visit(q) for the index q of every point in the cells that the box [lo, hi] (body frame)
  // overlaps, in index order; none where the box misses the body's box (or is NaN). A point in
  // the box is always visited, others may be.
  template <class Visit>
  KOKKOS_INLINE_FUNCTION void for_points_in_box(Vec3 lo, Vec3 hi, const Visit& visit) const {
    const LevelSetPointCells& c = cells;
    if (!(lo.x <= c.hi.x && lo.y <= c.hi.y && lo.z <= c.hi.z && hi.x >= c.lo.x && hi.y >= c.lo.y &&
          hi.z >= c.lo.z))
      return;
    const int i0 = c.cell_along(lo.x, c.lo.x, c.nx), i1 = c.cell_along(hi.x, c.lo.x, c.nx);
    const int j0 = c.cell_along(lo.y, c.lo.y, c.ny), j1 = c.cell_along(hi.y, c.lo.y, c.ny);
    const int k0 = c.cell_along(lo.z, c.lo.z, c.nz), k1 = c.cell_along(hi.z, c.lo.z, c.nz);
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j) {
        const int last = cell_first[c.index(i1, j, k) + 1];
        for (int q = cell_first[c.index(i0, j, k)]; q < last; ++q)
          visit(q);
      }
  }

  // Calls visit(q) for the index q of every point in the cells that reach below the plane through
  // `origin` with unit normal n (the side n points away from), in index order; a point below is
  // always visited. Each row of cells along x holds its points in one run, and the cells of a row
  // that reach below the plane are a run of it: one range per row, found from the height of the
  // row's first cell's lowest corner.
  template <class Visit>
  KOKKOS_INLINE_FUNCTION void for_points_below_plane(Vec3 origin, Vec3 n,
                                                     const Visit& visit) const {
    const LevelSetPointCells& c = cells;
    const double s = c.size;
    // From a cell's low corner to its lowest corner along n, less a margin for rounding.
    const double drop =
        s * (math::min(n.x, 0.0) + math::min(n.y, 0.0) + math::min(n.z, 0.0)) - 1e-9 * reach;
    const double box_drop = (c.hi.x - c.lo.x) * math::min(n.x, 0.0) +
                            (c.hi.y - c.lo.y) * math::min(n.y, 0.0) +
                            (c.hi.z - c.lo.z) * math::min(n.z, 0.0) - 1e-9 * reach;
    if (!(dot(c.lo - origin, n) + box_drop < 0))
      return;
    const double step = n.x * s; // the lowest corner's rise from one cell of a row to the next
    for (int k = 0; k < c.nz; ++k)
      for (int j = 0; j < c.ny; ++j) {
        const Vec3 row_lo{c.lo.x, c.lo.y + j * s, c.lo.z + k * s};
        const double first = dot(row_lo - origin, n) + drop; // cell i reaches first + step i
        int i0 = 0, i1 = c.nx - 1;
        if (step > 0) // cells i < -first / step: i <= ceil(-first / step) - 1
          i1 = int(math::max(math::min(-math::floor(first / step), double(c.nx)), 0.0)) - 1;
        else if (step < 0) // cells i > -first / step: i >= floor(-first / step) + 1
          i0 = int(math::min(math::max(math::floor(-first / step), -1.0), double(c.nx))) + 1;
        else if (!(first < 0))
          continue;
        if (i0 > i1)
          continue;
        const int last = cell_first[c.index(i1, j, k) + 1];
        for (int q = cell_first[c.index(i0, j, k)]; q < last; ++q)
          visit(q);
      }
  }

  // for_points_in_box over the box of the ball (centre, radius).
  template <class Visit>
  KOKKOS_INLINE_FUNCTION void for_points_in_ball_box(Vec3 centre, double radius,
                                                     const Visit& visit) const {
    const Vec3 r{radius, radius, radius};
    for_points_in_box(centre - r, centre + r, visit);
  }
};

namespace level_set {

// The unit outward normal at x from a sample: the gradient, or (where it vanishes, on a
// symmetry plane deep inside) the direction from the body's origin.
KOKKOS_INLINE_FUNCTION Vec3 outward(const LevelSetSample& s, Vec3 x) {
  const double length = norm(s.gradient);
  if (length > 0)
    return (1.0 / length) * s.gradient;
  const double from_origin = norm(x);
  return from_origin > 0 ? (1.0 / from_origin) * x : Vec3{0, 0, 1};
}

} // namespace level_set

// The surface points of body B (pose: B's frame in A's) inside body A's grid, as contacts in A's
// frame: overlap minus the interpolated value, normal minus A's outward normal there (from B
// towards A), point half the overlap out of A along it; keys (0, 1 + point index).
// Only b's points in A's box (its box in B's frame, widened by rounding's margin) are tested.
template <class Sink>
KOKKOS_INLINE_FUNCTION void points_inside(const LevelSetBodyView& a, const LevelSetBodyView& b,
                                          const RelativePose& pose, Sink& sink) {
  const Vec3 centre = transpose_times(pose.rotation, a.cells.centre() - pose.translation);
  const Vec3 half = a.cells.half_extent();
  const double margin = 1e-9 * (a.reach + b.reach);
  const auto& r = pose.rotation.m;
  const auto seen_along = [&](int k) { // |R^T| half: A's box along B's axis k
    return math::fabs(r[0][k]) * half.x + math::fabs(r[1][k]) * half.y +
           math::fabs(r[2][k]) * half.z + margin;
  };
  const Vec3 reach{seen_along(0), seen_along(1), seen_along(2)};
  b.for_points_in_box(centre - reach, centre + reach, [&](int q) {
    const Vec3 x = pose.point(b.points[q]);
    LevelSetSample s;
    if (!a.sample(x, s) || !(s.value < 0))
      return;
    const Vec3 out = level_set::outward(s, x);
    FeatureContact c;
    c.overlap = -s.value;
    c.normal = -out;
    c.point = x + (0.5 * c.overlap) * out;
    c.feature_a = 0;
    c.feature_b = 1 + q;
    sink.add(c);
  });
}

// The surface points of a body (its frame) beyond the plane through `origin` with unit normal n
// (pointing out of the wall, into the body's side): overlap the depth, normal n, point half the
// depth back towards the wall; keys (1 + point index, 0).
template <class Sink>
KOKKOS_INLINE_FUNCTION void points_beyond_plane(const LevelSetBodyView& body, Vec3 origin, Vec3 n,
                                                Sink& sink) {
  body.for_points_below_plane(origin, n, [&](int q) {
    const Vec3 x = body.points[q];
    const double height = dot(x - origin, n);
    if (!(height < 0))
      return;
    FeatureContact c;
    c.overlap = -height;
    c.normal = n;
    c.point = x + (0.5 * c.overlap) * n;
    c.feature_a = 1 + q;
    c.feature_b = 0;
    sink.add(c);
  });
}

// The surface points of a body (its frame) beyond the curved wall of a cylinder seen from inside
// (axis through `base` along the unit `axis`, radius, length from the base): overlap the depth,
// normal towards the axis; keys (1 + point index, 0).
template <class Sink>
KOKKOS_INLINE_FUNCTION void points_beyond_cylinder(const LevelSetBodyView& body, Vec3 base,
                                                   Vec3 axis, double radius, double length,
                                                   Sink& sink) {
  for (int q = 0; q < body.point_count; ++q) {
    const Vec3 x = body.points[q];
    const Vec3 from_base = x - base;
    const double along = dot(from_base, axis);
    const Vec3 out = from_base - along * axis;
    const double rho = norm(out);
    if (!(rho > radius) || !(along >= 0 && along <= length))
      continue;
    const Vec3 outward = (1.0 / rho) * out;
    FeatureContact c;
    c.overlap = rho - radius;
    c.normal = -outward;
    c.point = x - (0.5 * c.overlap) * outward;
    c.feature_a = 1 + q;
    c.feature_b = 0;
    sink.add(c);
  }
}

} // namespace kdem
