// The scene keys of poly-superquadric particles: a shape entry's `poly_superquadric` (book
// Eqs. 3.17 to 3.25: extents on each side of the origin and blockiness) and
// `poly_superquadric_contact` (narrow-phase controls, a subset of the superquadrics').
#include "poly_superquadric_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "body_surface.hpp"
#include "superquadric_scene.hpp"

namespace kdem {
namespace {

using namespace scene_yaml;

// The family's key in a shape entry and in SceneConfig::family_settings
// (PolySuperquadricFamily::name).
const char* const family_name = "poly_superquadric";

Vec3d positive_extents(const Value& value, const std::string& side) {
  const std::string meaning =
      "three positive extents r_x" + side + ", r_y" + side + ", r_z" + side + " in metres";
  const Vec3d extents = vector3(value, meaning);
  for (double extent : extents)
    if (!(extent > 0))
      value.expected(meaning);
  return extents;
}

std::shared_ptr<const FamilyShapeParameters> read_poly_superquadric(const Value& value) {
  auto shape = std::make_shared<PolySuperquadricShapeParameters>();
  const Mapping map(value, {"half_axes_plus", "half_axes_minus", "blockiness"});
  shape->half_axes_plus = positive_extents(map.get("half_axes_plus"), "+");
  shape->half_axes_minus = positive_extents(map.get("half_axes_minus"), "-");
  read_blockiness(map.get("blockiness"), shape->n1, shape->n2);
  return shape;
}

// The superquadric settings that apply to the octant elements' Newton; the superquadrics' lanes
// and start extrapolation have no counterpart here.
std::shared_ptr<const FamilySettings> read_poly_superquadric_contact(const Value& value) {
  return read_newton_settings(value, {"tolerance", "max_iterations", "curvature_limit",
                                      "separation_certificates", "box_certificates",
                                      "compact_candidates", "ellipsoid_scalar_root", "team_size"});
}

} // namespace

double PolySuperquadricShapeParameters::smallest_size() const {
  double smallest = 0.5 * (half_axes_plus[0] + half_axes_minus[0]);
  for (int k = 1; k < 3; ++k)
    smallest = std::min(smallest, 0.5 * (half_axes_plus[k] + half_axes_minus[k]));
  return smallest;
}

FamilyScene poly_superquadric_scene() {
  return {family_name, "poly_superquadric_contact", read_poly_superquadric,
          read_poly_superquadric_contact};
}

const PolySuperquadricShapeParameters& poly_superquadric_parameters(const ShapeConfig& shape) {
  const auto* parameters =
      dynamic_cast<const PolySuperquadricShapeParameters*>(shape.parameters.get());
  if (parameters == nullptr)
    throw std::logic_error("shape '" + shape.name + "' carries no poly-superquadric parameters");
  return *parameters;
}

// Barr's surface, x = a c1^e1 c2^e2, y = b c1^e1 s2^e2, z = c s1^e1 (e = 2 / n), with (a, b, c)
// taken on the side of each coordinate's sign.
BodySurface poly_superquadric_surface(const PolySuperquadricShapeParameters& shape,
                                      int resolution) {
  const double e1 = 2.0 / shape.n1, e2 = 2.0 / shape.n2;
  const auto side = [&](double t, int axis) {
    return t >= 0 ? shape.half_axes_plus[axis] : shape.half_axes_minus[axis];
  };
  return latitude_longitude_surface(resolution, [&](double eta, double omega) {
    const double x = signed_power(std::cos(eta), e1) * signed_power(std::cos(omega), e2);
    const double y = signed_power(std::cos(eta), e1) * signed_power(std::sin(omega), e2);
    const double z = signed_power(std::sin(eta), e1);
    return std::array<double, 3>{side(x, 0) * x, side(y, 1) * y, side(z, 2) * z};
  });
}

ShapeConfig poly_superquadric_shape_config(const std::string& name, Vec3d half_axes_plus,
                                           Vec3d half_axes_minus, double n1, double n2) {
  auto parameters = std::make_shared<PolySuperquadricShapeParameters>();
  parameters->half_axes_plus = half_axes_plus;
  parameters->half_axes_minus = half_axes_minus;
  parameters->n1 = n1;
  parameters->n2 = n2;
  return {name, family_name, parameters};
}

} // namespace kdem
