#pragma once
// The poly-superquadric family (book Sect. 3.2): a template per scene shape (eight octant pieces
// of superquadrics about an origin O0, see shapes/poly_superquadric.hpp). A particle's position
// and orientation are those of its centroid and principal axes, as for every rigid body; the
// template keeps where O0 and the octant frame lie in that principal frame (the book's v_lc and,
// where the octants are not symmetric, a rotation: principal axes may lie up to 16 degrees off
// the octant frame). Contacts come from the octant-pair Newton of
// shapes/poly_superquadric_contact.hpp (pairs.hpp) and the support-point wall numerics (walls.hpp).
#include "../../shapes/poly_superquadric.hpp"
#include "../families/family_rows.hpp"
#include "../families/host_hooks.hpp"
#include "../superquadric/family.hpp"
#include "../walls.hpp"

namespace kdem {

// One scene shape of the family on the device.
struct PolySuperquadricTemplate {
  PolySuperquadricShape shape;
  Vec3 origin;      // m, O0 from the centroid, principal frame
  Mat3 octant_axes; // columns: the octant frame's axes in the principal frame
};

template <class F> struct ImplicitWallContactOf;
struct PolySuperquadricFamily;
using PolySuperquadricWallContact = ImplicitWallContactOf<PolySuperquadricFamily>;

struct PolySuperquadricFamily {
  static constexpr const char* name = "poly_superquadric";
  static constexpr const char* wall_label = "kdem::poly_superquadric_wall_contacts";
  static constexpr bool rigid_rotation = true;
  static constexpr bool surface_turns = true;
  static constexpr int contact_points = 1; // convex: one contact per pair
  static constexpr bool iterative_narrow_phase = true;
  static constexpr bool shape_templates = true; // its scene shapes: `poly_superquadric` entries

  // The narrow-phase controls are the superquadrics' (the octant elements are superquadrics),
  // read from the scene's `poly_superquadric_contact`.
  struct Table {
    DeviceView<PolySuperquadricTemplate*> shapes;
    ScalarView equivalent_radius; // m, radius of the sphere of equal volume, per template
    SuperquadricContactSettings settings;
  };

  KOKKOS_INLINE_FUNCTION static double equivalent_radius(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    return t.equivalent_radius(s.template_index(p.shape(i)));
  }

  KOKKOS_INLINE_FUNCTION static PosedPolySuperquadric pose(const Table& t, const ShapeFamilies& s,
                                                           const ParticleViews& p, int i) {
    const PolySuperquadricTemplate& shape = t.shapes(s.template_index(p.shape(i)));
    const Mat3 rotation = rotation_matrix(load_quat(p.orientation, i));
    return PosedPolySuperquadric{shape.shape, load3(p.position, i) + rotation * shape.origin,
                                 rotation * shape.octant_axes};
  }

  KOKKOS_INLINE_FUNCTION static OrientedBox oriented_box(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    return oriented_box_of(pose(t, s, p, i));
  }

  // Host side (src/poly_superquadric_setup.cpp): mass properties, bounding radius, output fields
  // and surface of each scene shape, and this table.
  static std::vector<ShapeTemplate> setup_templates(const FamilyShapes& shapes, Table& table);
  static PolySuperquadricWallContact wall_contact(const Table& t, const ShapeFamilies& s,
                                                  const WallElements& elements,
                                                  const ParticleViews& p);
};

} // namespace kdem
