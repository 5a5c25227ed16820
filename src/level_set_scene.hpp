#pragma once
// The level-set family's scene keys (level_set_scene.cpp): a shape entry `level_set: {mesh |
// superquadric | harmonics, nodes, convex_hull, simplify_to, scale, grid_spacing, padding,
// point_spacing | point_count}` (book chapter 5: a closed triangle mesh, convex or not, read from a
// file or built by src/core_builders.hpp, turned into a signed-distance grid and surface points)
// and the `level_set_contact` settings.
#include <array>
#include <string>
#include <vector>

#include "family_scene.hpp"

namespace kdem {

struct LevelSetShapeParameters : FamilyShapeParameters {
  std::string mesh_file;                     // absolute path, or "(how the mesh was built)"
  std::vector<std::array<double, 3>> points; // m, the mesh's coordinates times `scale`
  std::vector<std::array<int, 3>> triangles; // welded, as in the file or as built
  double grid_spacing = 0;                   // m
  int padding = 2;                           // cells beyond the mesh's box
  double point_spacing = 0;                  // m, least distance between surface points
  int point_count = 0; // > 0: about this many surface points instead (point_spacing is chosen)
  // The smallest half-width of the mesh's box.
  double smallest_size() const override;
};

struct LevelSetContactConfig : FamilySettings {
  double merge_distance = 0.5; // of the smaller equivalent radius: see LevelSetContactSettings
  bool averaging = true;       // false: every patch counts in full
  double averaging_angle = 30; // degrees: patches whose normals agree within it average
  bool both_ways = true;       // false: one body's points against the other's grid
};

// Its entry in the registry of scene readers.
FamilyScene level_set_scene();

// The parameters of a level-set shape entry; throws std::logic_error for another family's.
const LevelSetShapeParameters& level_set_parameters(const ShapeConfig& shape);
// A level-set shape entry made in code from a mesh held in memory.
ShapeConfig level_set_shape_config(const std::string& name,
                                   std::vector<std::array<double, 3>> points,
                                   std::vector<std::array<int, 3>> triangles, double grid_spacing,
                                   double point_spacing, int padding = 2);

} // namespace kdem
