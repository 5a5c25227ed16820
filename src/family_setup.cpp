// The families of a scene: its shapes (each set up by its family), the map from shape id to
// family and template, and the rows of each family and pair type at a list build.
#include <stdexcept>

#include "engine_state.hpp"
#include "host_copy.hpp"

namespace kdem {
// Shape id 0 is a sphere of its particle's radius; shape id k + 1 is entry k of the scene's
// shapes, set up by its family. Then the device map from shape id to family and template, and
// the shape id of each source.
void Engine::State::setup_shapes() {
  setup_superquadric_shapes();
  std::vector<int> template_of_shape{0};
  family_of_shape = {family_index_v<SphereFamily, Families>};
  for (const ShapeTemplate& t : shape_templates) {
    family_of_shape.push_back(t.family);
    template_of_shape.push_back(t.family_template);
  }
  shape_families.family_of_shape = upload<int>("shape_family", family_of_shape);
  shape_families.template_of_shape = upload<int>("shape_template", template_of_shape);

  // A shaped source places bounding spheres; its volume fraction counts the true volume.
  for (ParticleSourceConfig& source : scene.sources) {
    int id = sphere_shape;
    if (!source.shape.empty()) {
      id = shape_id_of(scene, source.shape);
      const ShapeTemplate& t = shape_templates[id - 1];
      source.sizes.kind = SizeDistributionConfig::Kind::Monodisperse;
      source.sizes.radius = t.bounding_radius;
      source.particle_volume_ratio = t.volume / sphere_volume(source.sizes.radius);
    }
    source_shape.push_back(id);
    mark_family_present(id);
  }
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
