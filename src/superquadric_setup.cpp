// The superquadric family's host setup: a template per scene shape (book Eq. 2.1) with its
// volume, principal inertia and bounding radius in closed form, the device table the kernels
// read, and the narrow-phase settings of the scene.
#include <cmath>

#include "../shapes/superquadric_properties.hpp"
#include "engine_state.hpp"

namespace kdem {
namespace {

SuperquadricShape template_of(const ShapeConfig& config) {
  return make_superquadric(config.half_axes[0], config.half_axes[1], config.half_axes[2], config.n1,
                           config.n2);
}

ShapeTemplate host_template(const SuperquadricShape& shape, int row) {
  ShapeTemplate t;
  t.family = family_index_v<SuperquadricFamily, Families>;
  t.family_template = row;
  t.volume = superquadric_volume(shape);
  t.inertia_per_density = superquadric_principal_inertia(shape, 1.0);
  t.bounding_radius = superquadric_bounding_radius(shape);
  t.equivalent_radius = std::cbrt(3.0 * t.volume / (4.0 * pi));
  t.output_half_axes = {shape.a, shape.b, shape.c};
  t.output_blockiness = {shape.n1, shape.n2};
  return t;
}

} // namespace

// Every entry of the scene's shapes is a superquadric: shape id k + 1, table row k.
void Engine::State::setup_superquadric_shapes() {
  const int count = int(scene.shapes.size());
  SuperquadricFamily::Table& table =
      std::get<family_index_v<SuperquadricFamily, Families>>(family_tables);
  table.shapes = DeviceView<SuperquadricShape*>("superquadric_templates", count);
  table.equivalent_radius = ScalarView("superquadric_equivalent_radius", count);
  auto shape_mirror = Kokkos::create_mirror_view(table.shapes);
  auto radius_mirror = Kokkos::create_mirror_view(table.equivalent_radius);
  for (int k = 0; k < count; ++k) {
    const SuperquadricShape shape = template_of(scene.shapes[k]);
    shape_templates.push_back(host_template(shape, k));
    shape_mirror(k) = shape;
    radius_mirror(k) = shape_templates.back().equivalent_radius;
  }
  Kokkos::deep_copy(table.shapes, shape_mirror);
  Kokkos::deep_copy(table.equivalent_radius, radius_mirror);

  SuperquadricContactSettings& settings = table.settings;
  settings.curvature_limit = scene.superquadric_contact.curvature_limit;
  settings.separation_certificates = scene.superquadric_contact.separation_certificates;
  settings.compact_candidates = scene.superquadric_contact.compact_candidates;
  settings.team_size = scene.superquadric_contact.team_size;
  if (scene.superquadric_contact.tolerance > 0)
    settings.newton.tolerance = scene.superquadric_contact.tolerance;
  if (scene.superquadric_contact.max_iterations > 0)
    settings.newton.max_iterations = scene.superquadric_contact.max_iterations;
}

} // namespace kdem
