#pragma once
// The level-set family (book chapter 5): a template per scene shape, a signed-distance grid over
// the body in its principal frame (centroid at the origin) and points on its surface
// (shapes/level_set.hpp), one grid per template in flat device Views, never one per particle.
// A contact is a surface point of one body inside the other's grid (pairs.hpp) or beyond a wall
// (walls.hpp); the penetrating points of one pair are grouped into patches, the connected regions
// of penetration (patches.hpp), each a contact at its deepest point with that point's key, their
// forces weighted by the book's averaging (Eq. 5.17's 1 / N_p over the patches that share a
// direction). Against the other families, the level-set body's points meet the other body's
// exact surface, and the other body's features its grid (mixed_pairs.hpp).
#include "../../shapes/level_set.hpp"
#include "../../shapes/oriented_box.hpp"
#include "../dilated_polyhedron/family.hpp"
#include "../families/family_rows.hpp"
#include "../families/host_hooks.hpp"
#include "../ragged_table.hpp"
#include "../walls.hpp"

namespace kdem {

struct LevelSetContactSettings {
  // Contacts whose normals agree within the averaging angle share the force in proportion to
  // their overlaps; reach: unbounded.
  SeamSettings averaging{true, 1e300, 0.8660254};
  // A penetrating point within `merge` x the smaller equivalent radius of a patch's points (of
  // the box bounding them) whose normal agrees with the patch's within the averaging angle joins
  // that patch; the patch's deepest point is its contact.
  double merge = 0.5;
  // Both bodies' points are tested against the other's grid (a sharp corner of either is found);
  // false: only the points of the body of the higher particle index against the other's grid.
  bool both_ways = true;
};

struct LevelSetWallContact;

struct LevelSetFamily {
  static constexpr const char* name = "level_set";
  static constexpr const char* wall_label = "kdem::level_set_wall_contacts";
  static constexpr bool rigid_rotation = true;
  static constexpr bool surface_turns = true;
  // Patches one body keeps per partner: a pair of two keeps up to 16 (the cap of
  // max_pair_contact_points), against a sphere or a wall element 8; where more are found the
  // deepest are kept.
  static constexpr int contact_points = 8;
  static constexpr bool iterative_narrow_phase = false;
  static constexpr bool shape_templates = true; // its scene shapes: `level_set` entries

  struct Table {
    RaggedTable<double> values;  // per template, node values (m)
    RaggedTable<Vec3> points;    // per template, surface points (principal frame), by cell
    RaggedTable<int> cell_first; // per template, the first point of each cell, and the count
    DeviceView<LevelSetGrid*> grids;
    DeviceView<LevelSetPointCells*> cells; // per template, its box and the cells over it
    ScalarView reach;                      // m, bounding radius per template
    ScalarView equivalent_radius;          // m, of the sphere of the body's volume, per template
    LevelSetContactSettings settings;
  };

  KOKKOS_INLINE_FUNCTION static double equivalent_radius(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    return t.equivalent_radius(s.template_index(p.shape(i)));
  }

  KOKKOS_INLINE_FUNCTION static LevelSetBodyView body(const Table& t, const ShapeFamilies& s,
                                                      const ParticleViews& p, int i) {
    const int k = s.template_index(p.shape(i));
    LevelSetBodyView b;
    b.grid = t.grids(k);
    b.values = t.values.values.data() + t.values.offsets(k);
    b.points = t.points.values.data() + t.points.offsets(k);
    b.point_count = t.points.size(k);
    b.reach = t.reach(k);
    b.cells = t.cells(k);
    b.cell_first = t.cell_first.values.data() + t.cell_first.offsets(k);
    return b;
  }

  // The world box of body i: its template's box, posed.
  KOKKOS_INLINE_FUNCTION static OrientedBox oriented_box(const Table& t, const ShapeFamilies& s,
                                                         const ParticleViews& p, int i) {
    const LevelSetPointCells& cells = t.cells(s.template_index(p.shape(i)));
    const Mat3 rotation = rotation_matrix(load_quat(p.orientation, i));
    return OrientedBox{load3(p.position, i) + rotation * cells.centre(), rotation,
                       cells.half_extent()};
  }

  // Host side (src/level_set_setup.cpp): the mesh's mass properties and principal frame, the
  // grid and surface points there, bounding radius, output fields and surface, and this table.
  static std::vector<ShapeTemplate> setup_templates(const FamilyShapes& shapes, Table& table);
  static LevelSetWallContact wall_contact(const Table& t, const ShapeFamilies& s,
                                          const WallElements& elements, const ParticleViews& p);
};

} // namespace kdem
