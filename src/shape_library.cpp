// Shape templates of a scene: superquadric parameters, volume, inertia and bounding radius,
// computed once on the host, and the device table the kernels read.
#include <cmath>
#include <stdexcept>

#include "../shapes/superquadric_properties.hpp"
#include "engine_state.hpp"

namespace kdem {
namespace {

IndexView upload_ints(const std::string& label, const std::vector<int>& values) {
  IndexView view(label, values.size());
  auto mirror = Kokkos::create_mirror_view(view);
  for (std::size_t k = 0; k < values.size(); ++k)
    mirror(k) = values[k];
  Kokkos::deep_copy(view, mirror);
  return view;
}

SuperquadricShape template_of(const ShapeConfig& config) {
  return make_superquadric(config.half_axes[0], config.half_axes[1], config.half_axes[2], config.n1,
                           config.n2);
}

} // namespace

// Shape id 0 is a sphere; shape id k + 1 is entry k of the scene's shapes, a superquadric.
void Engine::State::setup_shapes() {
  const int count = int(scene.shapes.size());
  SuperquadricFamily::Table& table =
      std::get<family_index_v<SuperquadricFamily, Families>>(family_tables);
  table.shapes = DeviceView<SuperquadricShape*>("superquadric_templates", count);
  table.equivalent_radius = ScalarView("superquadric_equivalent_radius", count);
  auto shape_mirror = Kokkos::create_mirror_view(table.shapes);
  auto radius_mirror = Kokkos::create_mirror_view(table.equivalent_radius);
  std::vector<int> template_of_shape{0};
  family_of_shape = {family_index_v<SphereFamily, Families>};
  for (int k = 0; k < count; ++k) {
    const SuperquadricShape shape = template_of(scene.shapes[k]);
    superquadric_templates.push_back(shape);
    template_volume.push_back(superquadric_volume(shape));
    template_inertia_per_density.push_back(superquadric_principal_inertia(shape, 1.0));
    template_bounding_radius.push_back(superquadric_bounding_radius(shape));
    template_equivalent_radius.push_back(std::cbrt(3.0 * template_volume.back() / (4.0 * pi)));
    shape_mirror(k) = shape;
    radius_mirror(k) = template_equivalent_radius.back();
    family_of_shape.push_back(family_index_v<SuperquadricFamily, Families>);
    template_of_shape.push_back(k);
  }
  Kokkos::deep_copy(table.shapes, shape_mirror);
  Kokkos::deep_copy(table.equivalent_radius, radius_mirror);
  shape_families.family_of_shape = upload_ints("shape_family", family_of_shape);
  shape_families.template_of_shape = upload_ints("shape_template", template_of_shape);

  // A shaped source places bounding spheres; its volume fraction counts the true volume.
  for (ParticleSourceConfig& source : scene.sources) {
    int id = sphere_shape;
    if (!source.shape.empty()) {
      const int k = shape_id_of(scene, source.shape) - 1;
      id = k + 1;
      source.sizes.kind = SizeDistributionConfig::Kind::Monodisperse;
      source.sizes.radius = template_bounding_radius[k];
      source.particle_volume_ratio = template_volume[k] / sphere_volume(source.sizes.radius);
    }
    source_shape.push_back(id);
    mark_family_present(id);
  }

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

int shape_id_of(const SceneConfig& scene, const std::string& name) {
  for (std::size_t k = 0; k < scene.shapes.size(); ++k)
    if (scene.shapes[k].name == name)
      return int(k) + 1;
  throw std::runtime_error(scene.source_file + ": unknown shape '" + name + "'");
}

int Engine::shape_id(const std::string& shape_name) const {
  return shape_id_of(state_->scene, shape_name);
}

// With one family present (or none) its kernels run over all rows, without a sort.
void Engine::State::classify_families(const PairList& list) {
  int single_family = 0;
  for (int f = 0; f < Families::size; ++f)
    if (families_present & (1 << f))
      single_family = (families_present & ~(1 << f)) == 0 ? f : -1;
  family_rows = sort_into_families<Families>(particles, list, shape_families, single_family);
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
