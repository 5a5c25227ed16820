#pragma once
// The clump family's scene keys (clump_scene.cpp): a shape entry
// `clump: {elements, equivalent_diameter, union_precision}` (book Sect. 3.1: a rigid body of
// sphere and superquadric elements) and the `clump_contact` settings.
#include <array>
#include <vector>

#include "family_scene.hpp"
#include "snapshot.hpp"
#include "superquadric_scene.hpp"

namespace kdem {

// One element in the clump's frame as the scene writes it (before any scaling): a sphere of
// radius half_axes[0] (all three equal), or a superquadric.
struct ClumpElementParameters {
  bool sphere = false;
  Vec3d half_axes{0, 0, 0}; // m
  double n1 = 2, n2 = 2;
  Vec3d position{0, 0, 0};                       // m, the element's centre
  std::array<double, 4> orientation{1, 0, 0, 0}; // unit quaternion [w, x, y, z], element to clump
};

struct ClumpShapeParameters : FamilyShapeParameters {
  std::vector<ClumpElementParameters> elements;
  double equivalent_diameter = 0; // m; > 0: the clump is scaled to this volume-equivalent size
  double union_precision = 1e-4;  // relative precision of the union's mass properties
  // The smallest element semi-axis; with equivalent_diameter, scaled by an estimate of the factor
  // (from the elements' volumes summed as ellipsoids: only the default skin reads it).
  double smallest_size() const override;
};

// The clump contacts' settings: the superquadric elements' Newton and how seam duplicates count.
struct ClumpContactConfig : SuperquadricContactConfig {
  bool seam_weighted = true;  // false: every element contact counts in full
  double seam_distance = 0.5; // of the smaller element's equivalent radius
  double seam_angle = 30;     // degrees
};

// Its entry in the registry of scene readers.
FamilyScene clump_scene();

// The parameters of a clump shape entry; throws std::logic_error for another family's.
const ClumpShapeParameters& clump_parameters(const ShapeConfig& shape);
// A clump shape entry made in code.
ShapeConfig clump_shape_config(const std::string& name,
                               const std::vector<ClumpElementParameters>& elements,
                               double equivalent_diameter = 0);

} // namespace kdem
