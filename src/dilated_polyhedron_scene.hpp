#pragma once
// The dilated-polyhedron family's scene keys (dilated_polyhedron_scene.cpp): a shape entry
// `dilated_polyhedron: {mesh | superquadric | harmonics, nodes, convex_hull, simplify_to, scale,
// dilation_radius, mass_precision}` (book chapter 4: a closed triangle mesh, convex or not, swept
// by a sphere of the dilation radius; the core read from a file or built by src/core_builders.hpp)
// and the `dilated_polyhedron_contact` settings.
#include <array>
#include <string>
#include <vector>

#include "family_scene.hpp"

namespace kdem {

struct DilatedPolyhedronShapeParameters : FamilyShapeParameters {
  std::string mesh_file;                     // absolute path, or "(how the core was built)"
  std::vector<std::array<double, 3>> points; // m, the core's coordinates times `scale`
  std::vector<std::array<int, 3>> triangles; // welded, as in the file or as built
  double dilation_radius = 0;                // m
  double mass_precision = 1e-4;              // relative precision of the mass properties
  // The smallest half-width of the core's box plus the dilation radius.
  double smallest_size() const override;
};

struct DilatedPolyhedronContactConfig : FamilySettings {
  double cone_slack = 1e-6;    // rad, see ConeSlack (shapes/dilated_polyhedron.hpp)
  double cone_fade = 0.002;    // rad, beyond the slack: see ConeSlack
  double merge_distance = 0.5; // of the smaller dilation radius: see DilatedContactSettings
  bool averaging = true;       // false: every contact point counts in full
  double averaging_angle = 30; // degrees: contact points whose normals agree within it average
};

// Its entry in the registry of scene readers.
FamilyScene dilated_polyhedron_scene();

// The parameters of a dilated-polyhedron shape entry; throws std::logic_error for another
// family's.
const DilatedPolyhedronShapeParameters& dilated_polyhedron_parameters(const ShapeConfig& shape);
// A dilated-polyhedron shape entry made in code from a mesh held in memory.
ShapeConfig dilated_polyhedron_shape_config(const std::string& name,
                                            std::vector<std::array<double, 3>> points,
                                            std::vector<std::array<int, 3>> triangles,
                                            double dilation_radius, double mass_precision = 1e-4);

} // namespace kdem
