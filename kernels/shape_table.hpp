#pragma once
// Device table of particle shape templates, and per-family index lists of particles and pairs,
// so that each pair type (sphere-sphere, sphere-superquadric, superquadric-superquadric) and
// each particle family gets its own statically typed kernel, launched only when present.
//
// Particle shape ids: shape(i) == sphere_shape is a sphere of radius(i); shape(i) = k > 0 is
// superquadric template k - 1, and radius(i) is then its bounding-sphere radius.
#include "../shapes/superquadric.hpp"
#include "diagnostics.hpp"

namespace kdem {

constexpr int sphere_shape = 0;

struct ShapeTable {
  int superquadric_count = 0;
  DeviceView<SuperquadricShape*> superquadric;
  ScalarView equivalent_radius; // m, radius of the sphere of equal volume, per template
};

KOKKOS_INLINE_FUNCTION bool is_superquadric(int shape_id) {
  return shape_id != sphere_shape;
}

KOKKOS_INLINE_FUNCTION int superquadric_template(int shape_id) {
  return shape_id - 1;
}

// Index lists of one list build. In a scene of spheres only, `mixed` is false and the lists
// are empty: the sphere kernels then run over all particles and pairs directly.
struct FamilyLists {
  bool mixed = false;
  int sphere_count = 0, superquadric_count = 0;
  IndexView spheres, superquadrics; // particle rows
  int sphere_pair_count = 0, mixed_pair_count = 0, superquadric_pair_count = 0;
  IndexView sphere_pairs;       // both bodies spheres
  IndexView mixed_pairs;        // one sphere, one superquadric (either order)
  IndexView superquadric_pairs; // both bodies superquadrics
  // Work space of each step's superquadric prefilter, sized here so that the step allocates
  // nothing: a pass flag per superquadric pair, and the pairs that passed.
  IndexView superquadric_pair_passes, superquadric_pairs_left;
};

// Rows k of [0, count) for which keep(k) holds, in ascending order (count, scan, fill).
template <class Keep>
IndexView rows_where(int count, int& selected, const std::string& label, Keep keep) {
  IndexView flags(label, count);
  Kokkos::parallel_for(
      "kdem::flag_rows", RangePolicy(0, count),
      KOKKOS_LAMBDA(int k) { flags(k) = keep(k) ? 1 : 0; });
  return kept_indices(flags, selected);
}

inline FamilyLists sort_into_families(const ParticleViews& p, const PairList& pairs,
                                      bool scene_has_superquadrics) {
  FamilyLists f;
  f.mixed = scene_has_superquadrics;
  if (!f.mixed)
    return f;
  auto shape = p.shape;
  auto pair_i = pairs.pair_i, pair_j = pairs.pair_j;
  f.spheres = rows_where(
      p.count, f.sphere_count, "sphere_rows",
      KOKKOS_LAMBDA(int i) { return !is_superquadric(shape(i)); });
  f.superquadrics = rows_where(
      p.count, f.superquadric_count, "superquadric_rows",
      KOKKOS_LAMBDA(int i) { return is_superquadric(shape(i)); });
  const int n = pairs.pair_count;
  f.sphere_pairs = rows_where(
      n, f.sphere_pair_count, "sphere_pairs", KOKKOS_LAMBDA(int k) {
        return !is_superquadric(shape(pair_i(k))) && !is_superquadric(shape(pair_j(k)));
      });
  f.mixed_pairs = rows_where(
      n, f.mixed_pair_count, "mixed_pairs", KOKKOS_LAMBDA(int k) {
        return is_superquadric(shape(pair_i(k))) != is_superquadric(shape(pair_j(k)));
      });
  f.superquadric_pairs = rows_where(
      n, f.superquadric_pair_count, "superquadric_pairs", KOKKOS_LAMBDA(int k) {
        return is_superquadric(shape(pair_i(k))) && is_superquadric(shape(pair_j(k)));
      });
  f.superquadric_pair_passes =
      uninitialized<IndexView>("superquadric_pair_passes", f.superquadric_pair_count);
  f.superquadric_pairs_left =
      uninitialized<IndexView>("superquadric_pairs_left", f.superquadric_pair_count);
  return f;
}

KOKKOS_INLINE_FUNCTION PosedSuperquadric posed_particle(const ShapeTable& shapes,
                                                        const ParticleViews& p, int i) {
  return pose_superquadric(shapes.superquadric(superquadric_template(p.shape(i))),
                           load3(p.position, i), load_quat(p.orientation, i));
}

} // namespace kdem
