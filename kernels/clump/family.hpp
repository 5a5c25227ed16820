#pragma once
// The clump family (multi-superquadric particles, book Sect. 3.1): a template per scene shape, a
// list of sphere and superquadric elements in the clump's principal frame (shapes/clump.hpp).
// A particle's position and orientation are those of the union's centroid and principal axes;
// its radius bounds every element. Contacts are found per element (pairs.hpp, walls.hpp), each
// touching element pair a contact point with its own history, keyed by the elements' indices.
#include "../../shapes/clump.hpp"
#include "../families/family_rows.hpp"
#include "../families/host_hooks.hpp"
#include "../ragged_table.hpp"
#include "../superquadric/family.hpp"
#include "../walls.hpp"

namespace kdem {

struct ClumpContactSettings {
  SuperquadricContactSettings newton; // of the superquadric elements' solves
  SeamSettings seam;
};

struct ClumpWallContact;

struct ClumpFamily {
  static constexpr const char* name = "clump";
  static constexpr const char* wall_label = "kdem::clump_wall_contacts";
  static constexpr bool rigid_rotation = true;
  static constexpr bool surface_turns = true;
  // A pair keeps a slot per pair of elements that may touch, up to this many (the template's
  // element counts decide per pair, ShapeFamilies::features).
  static constexpr int contact_points = clump_max_elements;
  static constexpr bool iterative_narrow_phase = true;
  static constexpr bool shape_templates = true; // its scene shapes: `clump` entries

  struct Table {
    RaggedTable<ClumpElementTemplate> elements; // per template, principal frame
    ScalarView equivalent_radius;               // m, of the union's volume, per template
    ClumpContactSettings settings;
  };

  KOKKOS_INLINE_FUNCTION static double equivalent_radius(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    return t.equivalent_radius(s.template_index(p.shape(i)));
  }

  KOKKOS_INLINE_FUNCTION static int element_count(const Table& t, const ShapeFamilies& s,
                                                  const ParticleViews& p, int i) {
    return t.elements.size(s.template_index(p.shape(i)));
  }

  // Element m of particle i, placed with the particle's pose (`rotation`: its principal axes).
  KOKKOS_INLINE_FUNCTION static PlacedElement element(const Table& t, const ShapeFamilies& s,
                                                      const ParticleViews& p, int i,
                                                      const Mat3& rotation, int m) {
    return place_element(t.elements(s.template_index(p.shape(i)), m), load3(p.position, i),
                         rotation);
  }

  // Host side (src/clump_setup.cpp): union mass properties, principal frame, bounding radii,
  // output fields and surface of each scene shape, and this table.
  static std::vector<ShapeTemplate> setup_templates(const FamilyShapes& shapes, Table& table);
  static ClumpWallContact wall_contact(const Table& t, const ShapeFamilies& s,
                                       const WallElements& elements, const ParticleViews& p);
};

} // namespace kdem
