// The scene keys of clumps: a shape entry's `clump` (a list of sphere and superquadric elements
// placed in the clump's frame, optionally scaled to a volume-equivalent diameter) and
// `clump_contact` (the superquadric elements' Newton and the seam rule).
#include "clump_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kdem {
namespace {

using namespace scene_yaml;

// The family's key in a shape entry and in SceneConfig::family_settings (ClumpFamily::name).
const char* const family_name = "clump";
// ClumpFamily::contact_points (kernels/clump/family.hpp), which the scene loader cannot include.
constexpr int most_elements = 16;

Vec3d positive_axes(const Value& value) {
  const std::string meaning = "three positive semi-axes a, b, c in metres";
  const Vec3d axes = vector3(value, meaning);
  for (double axis : axes)
    if (!(axis > 0))
      value.expected(meaning);
  return axes;
}

std::array<double, 4> unit_quaternion(const Value& value) {
  const std::string expectation = "a quaternion [w, x, y, z] of non-zero length";
  const std::vector<double> q =
      number_list(value, expectation, "a finite number", [](double) { return true; });
  if (q.size() != 4)
    value.expected(expectation);
  const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(length > 0))
    value.expected(expectation);
  return {q[0] / length, q[1] / length, q[2] / length, q[3] / length};
}

ClumpElementParameters read_element(const Value& value) {
  const Mapping map(value, {"sphere", "superquadric", "position", "orientation"});
  ClumpElementParameters element;
  if (exactly_one_key(map, {"sphere", "superquadric"}) == "sphere") {
    element.sphere = true;
    const Mapping sphere(map.get("sphere"), {"radius"});
    const double radius = positive(sphere.get("radius"), "m");
    element.half_axes = {radius, radius, radius};
  } else {
    const Mapping sq(map.get("superquadric"), {"half_axes", "blockiness"});
    element.half_axes = positive_axes(sq.get("half_axes"));
    read_blockiness(sq.get("blockiness"), element.n1, element.n2);
  }
  element.position = vector3(map.get("position"), "in metres (the element's centre)");
  if (auto orientation = map.find("orientation")) {
    if (element.sphere)
      orientation->expected("no orientation for a sphere element");
    element.orientation = unit_quaternion(*orientation);
  }
  return element;
}

std::shared_ptr<const FamilyShapeParameters> read_clump(const Value& value) {
  auto clump = std::make_shared<ClumpShapeParameters>();
  const Mapping map(value, {"elements", "equivalent_diameter", "union_precision"});
  const Value elements = map.get("elements");
  const std::string expectation = "a sequence of 1 to " + std::to_string(most_elements) +
                                  " elements, each {sphere: {radius}} or {superquadric: "
                                  "{half_axes, blockiness}} with a position";
  for_each_item(elements, expectation, false,
                [&](const Value& item) { clump->elements.push_back(read_element(item)); });
  if (int(clump->elements.size()) > most_elements)
    elements.expected(expectation, std::to_string(clump->elements.size()) + " elements");
  if (auto diameter = map.find("equivalent_diameter"))
    clump->equivalent_diameter = positive(*diameter, "m");
  if (auto precision = map.find("union_precision"))
    clump->union_precision = number_where(*precision, "a relative precision in [1e-6, 1e-2]",
                                          [](double p) { return p >= 1e-6 && p <= 1e-2; });
  return clump;
}

std::shared_ptr<const FamilySettings> read_clump_contact(const Value& value) {
  const KeyList newton_keys{"tolerance", "max_iterations", "curvature_limit",
                            "separation_certificates", "ellipsoid_scalar_root"};
  KeyList keys = newton_keys;
  keys.insert(keys.end(), {"seam", "seam_distance", "seam_angle"});
  auto settings = std::make_shared<ClumpContactConfig>();
  static_cast<SuperquadricContactConfig&>(*settings) = *read_newton_settings(value, keys);
  const Mapping map(value, keys);
  if (auto seam = map.find("seam"))
    settings->seam_weighted = one_of_words(*seam, {"weighted", "summed"}) == "weighted";
  if (auto distance = map.find("seam_distance"))
    settings->seam_distance =
        number_where(*distance, "a fraction in (0, 2]", [](double d) { return d > 0 && d <= 2; });
  if (auto angle = map.find("seam_angle"))
    settings->seam_angle = number_where(*angle, "an angle in degrees in (0, 90)",
                                        [](double a) { return a > 0 && a < 90; });
  return settings;
}

} // namespace

double ClumpShapeParameters::smallest_size() const {
  double smallest = 1e300, volume = 0;
  for (const ClumpElementParameters& e : elements) {
    smallest = std::min(smallest, *std::min_element(e.half_axes.begin(), e.half_axes.end()));
    volume += e.half_axes[0] * e.half_axes[1] * e.half_axes[2]; // x 4 pi / 3
  }
  if (equivalent_diameter > 0)
    smallest *= 0.5 * equivalent_diameter / std::cbrt(volume);
  return smallest;
}

FamilyScene clump_scene() {
  return {family_name, "clump_contact", read_clump, read_clump_contact};
}

const ClumpShapeParameters& clump_parameters(const ShapeConfig& shape) {
  const auto* parameters = dynamic_cast<const ClumpShapeParameters*>(shape.parameters.get());
  if (parameters == nullptr)
    throw std::logic_error("shape '" + shape.name + "' carries no clump parameters");
  return *parameters;
}

ShapeConfig clump_shape_config(const std::string& name,
                               const std::vector<ClumpElementParameters>& elements,
                               double equivalent_diameter) {
  auto parameters = std::make_shared<ClumpShapeParameters>();
  parameters->elements = elements;
  parameters->equivalent_diameter = equivalent_diameter;
  return {name, family_name, parameters};
}

} // namespace kdem
