#pragma once
// The sphere family: radius per particle (shape id 0), no template data, closed-form contacts.
#include "../walls.hpp"
#include "family_rows.hpp"

namespace kdem {

// The shape id of spheres; a sphere's size is its particle's radius.
constexpr int sphere_shape = 0;

struct SphereFamily {
  static constexpr const char* name = "sphere";
  static constexpr const char* wall_label = "kdem::sphere_wall_contacts";
  // Integrated with isotropic rotation; turning a sphere moves none of its surface; no pair
  // type of spheres alone keeps a Newton warm start.
  static constexpr bool rigid_rotation = false;
  static constexpr bool surface_turns = false;
  static constexpr int contact_points = 1; // features it may touch another body with
  static constexpr bool iterative_narrow_phase = false;
  static constexpr bool shape_templates = false; // shape id 0, sized by the particle's radius

  struct Table {};

  KOKKOS_INLINE_FUNCTION static double equivalent_radius(const Table&, const ShapeFamilies&,
                                                         const ParticleViews& p, int i) {
    return p.radius(i);
  }

  static SphereWallContact wall_contact(const Table&, const ShapeFamilies&,
                                        const WallElements& elements, const ParticleViews& p) {
    return SphereWallContact{elements, p.position, p.radius};
  }
};

} // namespace kdem
