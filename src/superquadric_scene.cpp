// The scene keys of superquadric particles: the `shapes` list (book Eq. 2.1: semi-axes and
// blockiness exponents) and `superquadric_contact` (narrow-phase controls).
#include "superquadric_scene.hpp"

namespace kdem::scene_yaml {

// n >= 2 keeps the Hessian of the shape function finite on the surface; beyond 20 the corners
// are sharper than the narrow phase is validated for.
constexpr double smallest_blockiness = 2, largest_blockiness = 20;

ShapeConfig read_shape(const Value& value, UniqueNames& names) {
  const Mapping map(value, {"name", "superquadric"});
  ShapeConfig shape;
  shape.name = unique_name(map.get("name"), names);
  const Mapping sq(map.get("superquadric"), {"half_axes", "blockiness"});
  const Value axes = sq.get("half_axes");
  shape.half_axes = vector3(axes, "semi-axes a, b, c in metres");
  for (double axis : shape.half_axes)
    if (!(axis > 0))
      axes.expected("three positive semi-axes a, b, c in metres");
  const Value blockiness = sq.get("blockiness");
  const std::vector<double> exponents =
      number_list(blockiness, "a sequence [n1, n2] of two blockiness exponents",
                  "a blockiness exponent in [2, 20]",
                  [](double n) { return n >= smallest_blockiness && n <= largest_blockiness; });
  if (exponents.size() != 2)
    blockiness.expected("a sequence [n1, n2] of two blockiness exponents");
  shape.n1 = exponents[0];
  shape.n2 = exponents[1];
  return shape;
}

std::vector<ShapeConfig> read_shapes(const Value& list) {
  std::vector<ShapeConfig> shapes;
  UniqueNames names("shapes");
  for_each_item(list, "a sequence of shapes", true,
                [&](const Value& item) { shapes.push_back(read_shape(item, names)); });
  return shapes;
}

KeyList shape_names(const std::vector<ShapeConfig>& shapes) {
  KeyList names;
  for (const auto& shape : shapes)
    names.push_back(shape.name);
  return names;
}

const ShapeConfig& shape_named(const Value& value, const std::vector<ShapeConfig>& shapes) {
  const std::string expectation =
      shapes.empty()
          ? "the name of a shape defined under shapes (none is defined)"
          : "the name of a shape defined under shapes (" + join(shape_names(shapes)) + ")";
  const std::string name = text(value, expectation);
  for (const auto& shape : shapes)
    if (shape.name == name)
      return shape;
  value.expected(expectation);
}

SuperquadricContactConfig read_superquadric_contact(const Value& value) {
  const Mapping map(value, {"tolerance", "max_iterations", "curvature_limit",
                            "separation_certificates", "compact_candidates", "team_size"});
  SuperquadricContactConfig config;
  if (auto value_found = map.find("tolerance"))
    config.tolerance = number_where(*value_found, "a Newton tolerance in (0, 1e-2]",
                                    [](double t) { return t > 0 && t <= 1e-2; });
  if (auto value_found = map.find("max_iterations"))
    config.max_iterations = int(whole_number(*value_found, 1));
  if (auto value_found = map.find("curvature_limit"))
    config.curvature_limit =
        number_where(*value_found, "a factor >= 1", [](double f) { return f >= 1; });
  if (auto value_found = map.find("separation_certificates"))
    config.separation_certificates = boolean(*value_found);
  if (auto value_found = map.find("compact_candidates"))
    config.compact_candidates = boolean(*value_found);
  if (auto value_found = map.find("team_size"))
    config.team_size = int(whole_number(*value_found, 0));
  return config;
}

// A shaped source places one template; its `sizes` say the smallest semi-axis (for the default
// skin) while the engine sizes the bounding spheres.
SizeDistributionConfig sizes_of_shape(const ShapeConfig& shape) {
  SizeDistributionConfig sizes;
  sizes.kind = SizeDistributionConfig::Kind::Monodisperse;
  sizes.radius = *std::min_element(shape.half_axes.begin(), shape.half_axes.end());
  return sizes;
}

} // namespace kdem::scene_yaml
