#pragma once
// Clumps against walls: each element against the wall element (a sphere element by its closest
// point, a superquadric element by the convex wall numerics of kernels/surface_walls.hpp), each
// touching element a contact point keyed by its index, seam duplicates weighted as for pairs
// (a spherocylinder lying flat on a plane touches it with three elements at once).
#include "../superquadric/walls.hpp"
#include "family.hpp"

namespace kdem {

struct ClumpWallContact {
  static constexpr int max_contacts = clump_max_elements;
  WallElements el;
  ClumpFamily::Table table;
  ShapeFamilies shapes;
  ParticleViews p;
  double limit = 2;
  SeamSettings seam;

  KOKKOS_INLINE_FUNCTION WallContactGeometry element_contact(int e, const WallPose& wall,
                                                             const PlacedElement& element) const {
    if (element.sphere)
      return sphere_wall_contact(el, e, wall, element.body.centre, element.body.shape.a);
    return implicit_wall_contact(el, e, wall, element.body, element.equivalent_radius, limit);
  }

  KOKKOS_INLINE_FUNCTION void operator()(int i, int e, const WallPose& wall,
                                         WallContacts<max_contacts>& found) const {
    const Mat3 rotation = rotation_matrix(load_quat(p.orientation, i));
    const int elements = ClumpFamily::element_count(table, shapes, p, i);
    double size[max_contacts];
    for (int m = 0; m < elements; ++m) {
      const PlacedElement element = ClumpFamily::element(table, shapes, p, i, rotation, m);
      WallContactGeometry contact = element_contact(e, wall, element);
      if (!contact.geometry.touching)
        continue;
      contact.feature = m;
      size[found.count] = element.equivalent_radius;
      found.add() = contact;
    }
    seam_weights(
        found.count, [&](int c) -> const ContactGeometry& { return found.contact[c].geometry; },
        [&](int c) { return size[c]; }, seam,
        [&](int c, double w) { found.contact[c].weight = w; });
  }
};

inline ClumpWallContact ClumpFamily::wall_contact(const Table& t, const ShapeFamilies& s,
                                                  const WallElements& elements,
                                                  const ParticleViews& p) {
  return ClumpWallContact{elements, t, s, p, t.settings.newton.curvature_limit, t.settings.seam};
}

} // namespace kdem
