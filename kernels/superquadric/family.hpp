#pragma once
// The superquadric family (book Eq. 2.1): a template per scene shape (shape id k + 1 for entry
// k of the scene's `shapes`), the particle's radius is its template's bounding radius, and
// contacts come from the midway-point Newton narrow phase (pairs.hpp) and the deepest-point
// wall contacts (walls.hpp).
#include "../../shapes/superquadric.hpp"
#include "../../shapes/superquadric_contact.hpp"
#include "../../shapes/superquadric_properties.hpp"
#include "../families/family_rows.hpp"
#include "../families/host_hooks.hpp"
#include "../walls.hpp"

namespace kdem {

// Newton controls, contact-radius rule and kernel layout of the superquadric contacts.
struct SuperquadricContactSettings {
  NarrowPhaseControls newton;
  double curvature_limit = 2;
  bool separation_certificates = true; // see SeparationCertificates
  bool box_certificates = true;        // the box test's gap certifies too (needs the above)
  bool compact_candidates = true;      // see superquadric_pairs_in_reach
  bool extrapolate_start = true;       // see NarrowPhase<SuperquadricFamily, SuperquadricFamily>
  bool lanes = true; // host: see NarrowPhase<SuperquadricFamily, SuperquadricFamily>
  int team_size = 0; // of the narrow-phase kernel, see reduce_over_items
};

template <class F> struct ImplicitWallContactOf;
struct SuperquadricFamily;
using SuperquadricWallContactOf = ImplicitWallContactOf<SuperquadricFamily>;

struct SuperquadricFamily {
  static constexpr const char* name = "superquadric";
  static constexpr const char* wall_label = "kdem::superquadric_wall_contacts";
  static constexpr bool rigid_rotation = true;
  static constexpr bool surface_turns = true;
  static constexpr int contact_points = 1; // features it may touch another body with
  static constexpr bool iterative_narrow_phase = true;
  static constexpr bool shape_templates = true; // its scene shapes: `superquadric` entries

  struct Table {
    DeviceView<SuperquadricShape*> shapes;
    ScalarView equivalent_radius; // m, radius of the sphere of equal volume, per template
    SuperquadricContactSettings settings;
  };

  KOKKOS_INLINE_FUNCTION static double equivalent_radius(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    return t.equivalent_radius(s.template_index(p.shape(i)));
  }

  KOKKOS_INLINE_FUNCTION static PosedSuperquadric pose(const Table& t, const ShapeFamilies& s,
                                                       const ParticleViews& p, int i) {
    return pose_superquadric(t.shapes(s.template_index(p.shape(i))), load3(p.position, i),
                             load_quat(p.orientation, i));
  }

  KOKKOS_INLINE_FUNCTION static OrientedBox oriented_box(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    return oriented_box_of(pose(t, s, p, i));
  }

  // Host side (src/superquadric_setup.cpp): volume, inertia, bounding radius, output fields and
  // surface of each scene shape, and this table.
  static std::vector<ShapeTemplate> setup_templates(const FamilyShapes& shapes, Table& table);
  static SuperquadricWallContactOf wall_contact(const Table& t, const ShapeFamilies& s,
                                                const WallElements& elements,
                                                const ParticleViews& p);
};

} // namespace kdem
