#pragma once
// The penetrating surface points of one level-set pair (or of a body and a wall element) grouped
// into patches, one contact each: the connected regions of penetration. A point joins a patch
// when it lies within the link distance of the patch's points (of the box, axis-aligned in the
// frame of the computation, that bounds them) and its normal agrees with the patch's deepest
// point's within the averaging angle; a point that reaches two patches joins them into one. (A
// bounding sphere, grown point by point and patch by patch, swelled until the two legs of a U
// landing on a plane, a leg's width apart, became one patch; the union of boxes does not swell.) A
// patch's contact is its deepest point (overlap, normal, point and key), whose Hertz force is the
// gradient of a potential of the bodies' poses, so that elastic impacts keep their energy while the
// patches keep their number.
//
// Why connected regions: with patches cut at a fixed distance from their deepest point, a wide
// flat contact (a blunt body landing on a plane) falls into several patches whose number changes
// as the body turns, and the averaging over them then neither conserves energy nor follows one
// Hertz contact (measured: a blunt superquadric lost or gained up to 7 % of its energy landing on
// a plane; docs/validation.md, "Level-set wall impact").
#include "family.hpp"

namespace kdem {

template <int K> struct LevelSetPatches {
  int count = 0;
  int missed = 0;
  double link = 0; // m: points closer than this to a patch's points may join it
  double merge_cosine = 1;
  FeatureContact contact[K]; // each patch's deepest point
  Vec3 lo[K], hi[K];         // and the box bounding its points

  LevelSetPatches() = default;
  // With the settings' linking, for bodies whose smaller equivalent radius is `size`.
  KOKKOS_INLINE_FUNCTION LevelSetPatches(const LevelSetContactSettings& s, double size)
      : link(s.merge * size), merge_cosine(s.averaging.cos_angle) {}

  KOKKOS_INLINE_FUNCTION bool reaches(int m, const FeatureContact& c) const {
    const Vec3 x = c.point;
    const Vec3 outside{math::max(0.0, math::max(lo[m].x - x.x, x.x - hi[m].x)),
                       math::max(0.0, math::max(lo[m].y - x.y, x.y - hi[m].y)),
                       math::max(0.0, math::max(lo[m].z - x.z, x.z - hi[m].z))};
    return norm2(outside) < link * link && dot(c.normal, contact[m].normal) > merge_cosine;
  }

  KOKKOS_INLINE_FUNCTION void enclose(int m, Vec3 a, Vec3 b) {
    lo[m] = Vec3{math::min(lo[m].x, a.x), math::min(lo[m].y, a.y), math::min(lo[m].z, a.z)};
    hi[m] = Vec3{math::max(hi[m].x, b.x), math::max(hi[m].y, b.y), math::max(hi[m].z, b.z)};
  }

  KOKKOS_INLINE_FUNCTION void open(int m, const FeatureContact& c) {
    contact[m] = c;
    lo[m] = hi[m] = c.point;
  }

  // Patch `from` joined into patch `into`; the last patch moves into `from`'s place.
  KOKKOS_INLINE_FUNCTION void join(int into, int from) {
    enclose(into, lo[from], hi[from]);
    if (contact[from].overlap > contact[into].overlap)
      contact[into] = contact[from];
    --count;
    if (from != count) {
      contact[from] = contact[count];
      lo[from] = lo[count];
      hi[from] = hi[count];
    }
  }

  KOKKOS_INLINE_FUNCTION void add(const FeatureContact& c) {
    int into = -1;
    for (int m = 0; m < count; ++m) {
      if (!reaches(m, c))
        continue;
      if (into < 0) {
        into = m;
        continue;
      }
      join(into, m);
      --m; // the patch moved into m's place is tested next
    }
    if (into >= 0) {
      enclose(into, c.point, c.point);
      if (c.overlap > contact[into].overlap)
        contact[into] = c;
      return;
    }
    if (count < K) {
      open(count++, c);
      return;
    }
    ++missed;
    int shallowest = 0;
    for (int m = 1; m < K; ++m)
      if (contact[m].overlap < contact[shallowest].overlap)
        shallowest = m;
    if (c.overlap > contact[shallowest].overlap)
      open(shallowest, c);
  }

  // weight(m) of each patch: the book's averaging over the patches whose normals agree (Eq.
  // 5.17's 1 / N_p for equal overlaps).
  template <class SetWeight>
  KOKKOS_INLINE_FUNCTION void weights(const SeamSettings& averaging,
                                      const SetWeight& set_weight) const {
    ContactGeometry g[K];
    for (int m = 0; m < count; ++m)
      g[m] = ContactGeometry{true, contact[m].overlap, contact[m].normal, contact[m].point};
    seam_weights(
        count, [&](int m) -> const ContactGeometry& { return g[m]; }, [](int) { return 1.0; },
        averaging, set_weight);
  }
};

} // namespace kdem
