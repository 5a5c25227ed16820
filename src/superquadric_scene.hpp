#pragma once
// Readers of the superquadric family's scene keys (superquadric_scene.cpp).
#include <vector>

#include "scene.hpp"
#include "scene_yaml.hpp"

namespace kdem::scene_yaml {

// `shapes`: a sequence of named templates.
std::vector<ShapeConfig> read_shapes(const Value& list);
// The shape a source names; refuses unknown names with the list of defined ones.
const ShapeConfig& shape_named(const Value& value, const std::vector<ShapeConfig>& shapes);
// `superquadric_contact`: Newton tolerance and cap, curvature limit, kernel layout switches.
SuperquadricContactConfig read_superquadric_contact(const Value& value);
// A shaped source places one template; its `sizes` say the smallest semi-axis (for the default
// skin) while the engine sizes the bounding spheres.
SizeDistributionConfig sizes_of_shape(const ShapeConfig& shape);

} // namespace kdem::scene_yaml
