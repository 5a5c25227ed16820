// The poly-superquadric family's host setup: a template per scene shape with its volume,
// centroid and inertia in closed form (shapes/poly_superquadric_properties.hpp), the principal
// frame that becomes the particle's body frame, a conservative bounding radius about the
// centroid, its output fields and surface, the device table and the narrow-phase settings.
#include <cmath>
#include <stdexcept>

#include "../shapes/poly_superquadric_properties.hpp"
#include "body_surface.hpp"
#include "engine_state.hpp"
#include "poly_superquadric_scene.hpp"
#include "superquadric_settings.hpp"

namespace kdem {
namespace {

PolySuperquadricShape shape_of(const PolySuperquadricShapeParameters& config) {
  const auto vec = [](const Vec3d& v) { return Vec3{v[0], v[1], v[2]}; };
  return make_poly_superquadric(vec(config.half_axes_plus), vec(config.half_axes_minus), config.n1,
                                config.n2);
}

// Everything of one shape in its principal frame: the device template, and the host template
// (its principal inertia in the order of the chosen axes).
struct PrincipalForm {
  PolySuperquadricTemplate device;
  ShapeTemplate host;
};

PrincipalForm principal_form(const PolySuperquadricShapeParameters& config) {
  const PolySuperquadricShape shape = shape_of(config);
  const PolySuperquadricMassProperties mass = poly_superquadric_mass_properties(shape);
  const Mat3 axes = principal_frame_nearest(mass.inertia_per_density, mass.principal_axes);
  const Mat3 to_principal = transpose(axes);
  PrincipalForm form;
  form.device.shape = shape;
  form.device.origin = to_principal * (-1.0 * mass.centroid);
  form.device.octant_axes = to_principal;
  const Mat3 principal = to_principal * mass.inertia_per_density * axes;
  ShapeTemplate& t = form.host;
  t.volume = mass.volume;
  t.inertia_per_density = Vec3{principal.m[0][0], principal.m[1][1], principal.m[2][2]};
  t.bounding_radius = poly_superquadric_bounding_radius(shape, mass.centroid);
  t.equivalent_radius = std::cbrt(3.0 * t.volume / (4.0 * pi));
  const Vec3d& plus = config.half_axes_plus;
  const Vec3d& minus = config.half_axes_minus;
  t.output_fields = {{"half_axes_plus", 3, {plus[0], plus[1], plus[2]}},
                     {"half_axes_minus", 3, {minus[0], minus[1], minus[2]}},
                     {"blockiness", 2, {config.n1, config.n2}}};
  t.surface = poly_superquadric_surface(config, output_surface_resolution);
  for (std::size_t p = 0; p + 2 < t.surface.points.size(); p += 3) {
    const Vec3 octant{t.surface.points[p], t.surface.points[p + 1], t.surface.points[p + 2]};
    const Vec3 body = to_principal * (octant - mass.centroid);
    t.surface.points[p] = body.x, t.surface.points[p + 1] = body.y,
    t.surface.points[p + 2] = body.z;
  }
  return form;
}

} // namespace

std::vector<ShapeTemplate> PolySuperquadricFamily::setup_templates(const FamilyShapes& family,
                                                                   Table& table) {
  const int count = int(family.shapes.size());
  table.shapes = DeviceView<PolySuperquadricTemplate*>("poly_superquadric_templates", count);
  table.equivalent_radius = ScalarView("poly_superquadric_equivalent_radius", count);
  auto shape_mirror = Kokkos::create_mirror_view(table.shapes);
  auto radius_mirror = Kokkos::create_mirror_view(table.equivalent_radius);
  std::vector<ShapeTemplate> templates;
  for (int k = 0; k < count; ++k) {
    PrincipalForm form = principal_form(poly_superquadric_parameters(*family.shapes[k]));
    shape_mirror(k) = form.device;
    radius_mirror(k) = form.host.equivalent_radius;
    templates.push_back(std::move(form.host));
  }
  Kokkos::deep_copy(table.shapes, shape_mirror);
  Kokkos::deep_copy(table.equivalent_radius, radius_mirror);
  table.settings = superquadric_device_settings(family.settings);
  return templates;
}

} // namespace kdem
