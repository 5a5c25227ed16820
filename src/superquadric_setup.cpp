// The superquadric family's host setup: a template per scene shape (book Eq. 2.1) with its
// volume, principal inertia and bounding radius in closed form, its output fields and surface,
// the device table the kernels read, and the narrow-phase settings of the scene.
#include <cmath>
#include <stdexcept>

#include "../shapes/superquadric_properties.hpp"
#include "body_surface.hpp"
#include "engine_state.hpp"
#include "superquadric_scene.hpp"
#include "superquadric_settings.hpp"

namespace kdem {
namespace {

SuperquadricShape template_of(const SuperquadricShapeParameters& config) {
  return make_superquadric(config.half_axes[0], config.half_axes[1], config.half_axes[2], config.n1,
                           config.n2);
}

ShapeTemplate host_template(const SuperquadricShape& shape) {
  ShapeTemplate t;
  t.volume = superquadric_volume(shape);
  t.inertia_per_density = superquadric_principal_inertia(shape, 1.0);
  t.bounding_radius = superquadric_bounding_radius(shape);
  t.equivalent_radius = std::cbrt(3.0 * t.volume / (4.0 * pi));
  t.output_fields = {{"half_axes", 3, {shape.a, shape.b, shape.c}},
                     {"blockiness", 2, {shape.n1, shape.n2}}};
  t.surface = superquadric_surface({shape.a, shape.b, shape.c}, shape.n1, shape.n2,
                                   output_surface_resolution);
  return t;
}

} // namespace

SuperquadricContactSettings superquadric_device_settings(const FamilySettings* scene_settings) {
  const SuperquadricContactConfig config =
      scene_settings != nullptr ? dynamic_cast<const SuperquadricContactConfig&>(*scene_settings)
                                : SuperquadricContactConfig{};
  SuperquadricContactSettings settings;
  settings.curvature_limit = config.curvature_limit;
  settings.separation_certificates = config.separation_certificates;
  settings.box_certificates = config.box_certificates;
  settings.compact_candidates = config.compact_candidates;
  settings.extrapolate_start = config.extrapolate_start;
  settings.newton.ellipsoid_scalar_root = config.ellipsoid_scalar_root;
  settings.lanes = config.lanes;
  settings.team_size = config.team_size;
  if (config.tolerance > 0)
    settings.newton.tolerance = config.tolerance;
  if (config.max_iterations > 0)
    settings.newton.max_iterations = config.max_iterations;
  return settings;
}

std::vector<ShapeTemplate> SuperquadricFamily::setup_templates(const FamilyShapes& family,
                                                               Table& table) {
  const int count = int(family.shapes.size());
  table.shapes = DeviceView<SuperquadricShape*>("superquadric_templates", count);
  table.equivalent_radius = ScalarView("superquadric_equivalent_radius", count);
  auto shape_mirror = Kokkos::create_mirror_view(table.shapes);
  auto radius_mirror = Kokkos::create_mirror_view(table.equivalent_radius);
  std::vector<ShapeTemplate> templates;
  for (int k = 0; k < count; ++k) {
    const SuperquadricShape shape = template_of(superquadric_parameters(*family.shapes[k]));
    templates.push_back(host_template(shape));
    shape_mirror(k) = shape;
    radius_mirror(k) = templates.back().equivalent_radius;
  }
  Kokkos::deep_copy(table.shapes, shape_mirror);
  Kokkos::deep_copy(table.equivalent_radius, radius_mirror);
  table.settings = superquadric_device_settings(family.settings);
  return templates;
}

} // namespace kdem
