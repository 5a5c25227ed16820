// The families of a scene: its shapes (each set up by its family), the map from shape id to
// family and template, and the rows of each family and pair type at a list build.
#include <algorithm>
#include <limits>
#include <stdexcept>

#include "engine_state.hpp"
#include "host_copy.hpp"

namespace kdem {
// Shape id 0 is a sphere of its particle's radius; shape id k + 1 is entry k of the scene's
// shapes, set up by its family. Then the device map from shape id to family and template, and
// the shape id of each source.
void Engine::State::setup_shapes() {
  shape_templates.assign(scene.shapes.size(), ShapeTemplate{});
  std::vector<bool> set_up(scene.shapes.size(), false);
  for_each_family<Families>([&](auto tag) {
    using F = typename decltype(tag)::type;
    if constexpr (F::shape_templates)
      setup_family_shapes<F>(set_up);
  });
  for (std::size_t k = 0; k < scene.shapes.size(); ++k)
    if (!set_up[k])
      throw std::runtime_error(scene.source_file + ": shape '" + scene.shapes[k].name +
                               "' is of the family '" + scene.shapes[k].family +
                               "', which this build of the engine does not have");
  refuse_pairs_without_narrow_phase();
  std::vector<int> template_of_shape{0}, features_of_shape{1};
  family_of_shape = {family_index_v<SphereFamily, Families>};
  for (const ShapeTemplate& t : shape_templates) {
    family_of_shape.push_back(t.family);
    template_of_shape.push_back(t.family_template);
    features_of_shape.push_back(t.contact_features);
  }
  shape_families.family_of_shape = upload<int>("shape_family", family_of_shape);
  shape_families.template_of_shape = upload<int>("shape_template", template_of_shape);
  shape_families.features_of_shape = upload<int>("shape_features", features_of_shape);

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

// A scene whose shapes hold two families whose pair type has no narrow phase yet cannot run.
void Engine::State::refuse_pairs_without_narrow_phase() const {
  int held = 0;
  for (const ShapeTemplate& t : shape_templates)
    held |= 1 << t.family;
  for_each_pair_type<Families>([&](auto tag_a, auto tag_b) {
    using A = typename decltype(tag_a)::type;
    using B = typename decltype(tag_b)::type;
    const int both = (1 << family_index_v<A, Families>) | (1 << family_index_v<B, Families>);
    if (!pair_type_implemented<A, B>::value && (held & both) == both)
      throw std::runtime_error(scene.source_file + ": shapes of the families '" + A::name +
                               "' and '" + B::name +
                               "' cannot share a scene yet: contact between them is not "
                               "implemented");
  });
}

// The scene's shapes of family F get templates from F's setup hook, rows in scene order.
template <class F> void Engine::State::setup_family_shapes(std::vector<bool>& set_up) {
  FamilyShapes family;
  std::vector<std::size_t> shape_index;
  for (std::size_t k = 0; k < scene.shapes.size(); ++k)
    if (scene.shapes[k].family == F::name) {
      family.shapes.push_back(&scene.shapes[k]);
      shape_index.push_back(k);
    }
  const auto settings = scene.family_settings.find(F::name);
  if (settings != scene.family_settings.end())
    family.settings = settings->second.get();
  std::vector<ShapeTemplate> made;
  try {
    made = F::setup_templates(family, std::get<family_index_v<F, Families>>(family_tables));
  } catch (const std::runtime_error& refused) { // a shape the family cannot build
    throw std::runtime_error(scene.source_file + ": " + refused.what());
  }
  if (made.size() != shape_index.size())
    throw std::logic_error(std::string("the setup of the family ") + F::name + " made " +
                           std::to_string(made.size()) + " templates for " +
                           std::to_string(shape_index.size()) + " shapes");
  for (std::size_t row = 0; row < made.size(); ++row) {
    made[row].family = family_index_v<F, Families>;
    made[row].family_template = int(row);
    shape_templates[shape_index[row]] = std::move(made[row]);
    set_up[shape_index[row]] = true;
  }
}

std::vector<ShapeField> output_fields_of(const std::vector<ShapeTemplate>& templates,
                                         const std::vector<int>& template_of_item) {
  std::vector<ShapeField> fields;
  for (const ShapeTemplate& t : templates)
    for (const ShapeField& field : t.output_fields) {
      bool known = false;
      for (const ShapeField& f : fields)
        known = known || f.name == field.name;
      if (!known)
        fields.push_back({field.name, field.components, {}});
    }
  const double none = std::numeric_limits<double>::quiet_NaN();
  for (ShapeField& field : fields) {
    field.values.assign(template_of_item.size() * field.components, none);
    for (std::size_t k = 0; k < template_of_item.size(); ++k) {
      if (template_of_item[k] < 0)
        continue;
      for (const ShapeField& own : templates[template_of_item[k]].output_fields)
        if (own.name == field.name)
          std::copy(own.values.begin(), own.values.end(),
                    field.values.begin() + k * field.components);
    }
  }
  return fields;
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
  int single_family = 0, present = 0;
  for (int f = 0; f < Families::size; ++f)
    if (families_present & (1 << f)) {
      single_family = f;
      ++present;
    }
  if (present > 1)
    single_family = -1;
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
