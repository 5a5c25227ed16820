#pragma once
// The host types that a family's setup hook takes (defined in src/engine_state.hpp). A family
// with shape templates declares, in its trait,
//   static constexpr bool shape_templates = true;
//   static std::vector<ShapeTemplate> setup_templates(const FamilyShapes& shapes, Table& table);
// and defines it in src/<family>_setup.cpp; a family without (spheres) sets shape_templates to
// false and declares nothing more.
#include <vector>

namespace kdem {

struct ShapeTemplate;
struct FamilyShapes;

} // namespace kdem
