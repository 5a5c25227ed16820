// Shape templates of a scene: superquadric parameters, volume, inertia and bounding radius,
// computed once on the host, and the device table the kernels read.
#include <cmath>
#include <stdexcept>

#include "../shapes/superquadric_properties.hpp"
#include "engine_state.hpp"

namespace kdem {
namespace {

SuperquadricShape template_of(const ShapeConfig& config) {
  return make_superquadric(config.half_axes[0], config.half_axes[1], config.half_axes[2], config.n1,
                           config.n2);
}

} // namespace

void Engine::State::setup_shapes() {
  const int count = int(scene.shapes.size());
  shapes.superquadric_count = count;
  shapes.superquadric = DeviceView<SuperquadricShape*>("superquadric_templates", count);
  shapes.equivalent_radius = ScalarView("superquadric_equivalent_radius", count);
  auto shape_mirror = Kokkos::create_mirror_view(shapes.superquadric);
  auto radius_mirror = Kokkos::create_mirror_view(shapes.equivalent_radius);
  for (int k = 0; k < count; ++k) {
    const SuperquadricShape shape = template_of(scene.shapes[k]);
    superquadric_templates.push_back(shape);
    template_volume.push_back(superquadric_volume(shape));
    template_inertia_per_density.push_back(superquadric_principal_inertia(shape, 1.0));
    template_bounding_radius.push_back(superquadric_bounding_radius(shape));
    template_equivalent_radius.push_back(std::cbrt(3.0 * template_volume.back() / (4.0 * pi)));
    shape_mirror(k) = shape;
    radius_mirror(k) = template_equivalent_radius.back();
  }
  Kokkos::deep_copy(shapes.superquadric, shape_mirror);
  Kokkos::deep_copy(shapes.equivalent_radius, radius_mirror);

  // A shaped source places bounding spheres; its volume fraction counts the true volume.
  for (ParticleSourceConfig& source : scene.sources) {
    int id = sphere_shape;
    if (!source.shape.empty()) {
      const int k = shape_id_of(scene, source.shape) - 1;
      id = k + 1;
      source.sizes.kind = SizeDistributionConfig::Kind::Monodisperse;
      source.sizes.radius = template_bounding_radius[k];
      source.particle_volume_ratio = template_volume[k] / sphere_volume(source.sizes.radius);
      has_superquadrics = true;
    }
    source_shape.push_back(id);
  }

  superquadric_settings.curvature_limit = scene.superquadric_contact.curvature_limit;
  superquadric_settings.separation_certificates =
      scene.superquadric_contact.separation_certificates;
  superquadric_settings.compact_candidates = scene.superquadric_contact.compact_candidates;
  superquadric_settings.team_size = scene.superquadric_contact.team_size;
  if (scene.superquadric_contact.tolerance > 0)
    superquadric_settings.newton.tolerance = scene.superquadric_contact.tolerance;
  if (scene.superquadric_contact.max_iterations > 0)
    superquadric_settings.newton.max_iterations = scene.superquadric_contact.max_iterations;
}

int shape_id_of(const SceneConfig& scene, const std::string& name) {
  for (std::size_t k = 0; k < scene.shapes.size(); ++k)
    if (scene.shapes[k].name == name)
      return int(k) + 1;
  throw std::runtime_error(scene.source_file + ": unknown shape '" + name + "'");
}

int Engine::shape_id(const std::string& shape_name) const {
  return shape_id_of(state_->scene, shape_name);
}

void Engine::State::classify_families() {
  families = sort_into_families(particles, pairs, has_superquadrics);
}

NarrowPhaseTotals Engine::narrow_phase_totals() const {
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), state_->narrow_phase.totals);
  NarrowPhaseTotals totals;
  totals.evaluations = host().evaluations;
  totals.iterations = host().iterations;
  totals.fallbacks = host().fallbacks;
  totals.failures = host().failures;
  return totals;
}

} // namespace kdem
