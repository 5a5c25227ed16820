// The scene keys of superquadric particles: a shape entry's `superquadric` (book Eq. 2.1:
// semi-axes and blockiness exponents) and `superquadric_contact` (narrow-phase controls).
#include "superquadric_scene.hpp"

#include "body_surface.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kdem {
namespace {

using namespace scene_yaml;

// The family's key in a shape entry and in SceneConfig::family_settings (SuperquadricFamily::name).
const char* const family_name = "superquadric";

std::shared_ptr<const FamilyShapeParameters> read_superquadric(const Value& value) {
  auto shape = std::make_shared<SuperquadricShapeParameters>();
  const Mapping sq(value, {"half_axes", "blockiness"});
  const Value axes = sq.get("half_axes");
  shape->half_axes = vector3(axes, "semi-axes a, b, c in metres");
  for (double axis : shape->half_axes)
    if (!(axis > 0))
      axes.expected("three positive semi-axes a, b, c in metres");
  read_blockiness(sq.get("blockiness"), shape->n1, shape->n2);
  return shape;
}

std::shared_ptr<const FamilySettings> read_superquadric_contact(const Value& value) {
  return read_newton_settings(value,
                              {"tolerance", "max_iterations", "curvature_limit",
                               "separation_certificates", "box_certificates", "compact_candidates",
                               "extrapolate_start", "ellipsoid_scalar_root", "lanes", "team_size"});
}

} // namespace

std::shared_ptr<SuperquadricContactConfig> read_newton_settings(const scene_yaml::Value& value,
                                                                const scene_yaml::KeyList& keys) {
  using namespace scene_yaml;
  const Mapping map(value, keys);
  auto settings = std::make_shared<SuperquadricContactConfig>();
  SuperquadricContactConfig& config = *settings;
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
  if (auto value_found = map.find("box_certificates"))
    config.box_certificates = boolean(*value_found);
  if (auto value_found = map.find("compact_candidates"))
    config.compact_candidates = boolean(*value_found);
  if (auto value_found = map.find("extrapolate_start"))
    config.extrapolate_start = boolean(*value_found);
  if (auto value_found = map.find("ellipsoid_scalar_root"))
    config.ellipsoid_scalar_root = boolean(*value_found);
  if (auto value_found = map.find("lanes"))
    config.lanes = boolean(*value_found);
  if (auto value_found = map.find("team_size"))
    config.team_size = int(whole_number(*value_found, 0));
  return settings;
}

// n >= 2 keeps the Hessian of the shape function finite on the surface; beyond 20 the corners
// are sharper than the narrow phase is validated for.
void read_blockiness(const scene_yaml::Value& value, double& n1, double& n2) {
  using namespace scene_yaml;
  constexpr double smallest = 2, largest = 20;
  const std::vector<double> exponents = number_list(
      value, "a sequence [n1, n2] of two blockiness exponents", "a blockiness exponent in [2, 20]",
      [](double n) { return n >= smallest && n <= largest; });
  if (exponents.size() != 2)
    value.expected("a sequence [n1, n2] of two blockiness exponents");
  n1 = exponents[0];
  n2 = exponents[1];
}

double SuperquadricShapeParameters::smallest_size() const {
  return *std::min_element(half_axes.begin(), half_axes.end());
}

FamilyScene superquadric_scene() {
  return {family_name, "superquadric_contact", read_superquadric, read_superquadric_contact};
}

const SuperquadricShapeParameters& superquadric_parameters(const ShapeConfig& shape) {
  const auto* parameters = dynamic_cast<const SuperquadricShapeParameters*>(shape.parameters.get());
  if (parameters == nullptr)
    throw std::logic_error("shape '" + shape.name + "' carries no superquadric parameters");
  return *parameters;
}

const SuperquadricContactConfig& superquadric_contact(const SceneConfig& scene) {
  static const SuperquadricContactConfig defaults;
  const auto found = scene.family_settings.find(family_name);
  if (found == scene.family_settings.end())
    return defaults;
  return dynamic_cast<const SuperquadricContactConfig&>(*found->second);
}

SuperquadricContactConfig& modify_superquadric_contact(SceneConfig& scene) {
  auto copy = std::make_shared<SuperquadricContactConfig>(superquadric_contact(scene));
  scene.family_settings[family_name] = copy;
  return *copy;
}

// x = a c1^e1 c2^e2, y = b c1^e1 s2^e2, z = c s1^e1 with e1 = 2/n1, e2 = 2/n2.
BodySurface superquadric_surface(Vec3d half_axes, double n1, double n2, int resolution) {
  const double e1 = 2.0 / n1, e2 = 2.0 / n2;
  const double a = half_axes[0], b = half_axes[1], c = half_axes[2];
  return latitude_longitude_surface(resolution, [&](double eta, double omega) {
    return std::array<double, 3>{
        a * signed_power(std::cos(eta), e1) * signed_power(std::cos(omega), e2),
        b * signed_power(std::cos(eta), e1) * signed_power(std::sin(omega), e2),
        c * signed_power(std::sin(eta), e1)};
  });
}

ShapeConfig superquadric_shape_config(const std::string& name, Vec3d half_axes, double n1,
                                      double n2) {
  auto parameters = std::make_shared<SuperquadricShapeParameters>();
  parameters->half_axes = half_axes;
  parameters->n1 = n1;
  parameters->n2 = n2;
  return {name, family_name, parameters};
}

} // namespace kdem
