#pragma once
// Internal state of the Engine (device stores and host bookkeeping). Only engine sources
// include this.
#include <limits>
#include <random>

#include "../kernels/binning.hpp"
#include "../kernels/diagnostics.hpp"
#include "../kernels/families/registry.hpp"
#include "../kernels/pair_list.hpp"
#include "../kernels/walls.hpp"
#include "engine.hpp"
#include "generate.hpp"
#include "wall_builder.hpp"
#include "wall_tables.hpp"

namespace kdem {

// Shape id of the named entry of scene.shapes (k + 1 for entry k); throws for unknown names.
int shape_id_of(const SceneConfig& scene, const std::string& name);

// A scene shape as the engine's host code needs it, whatever its family.
struct ShapeTemplate {
  int family = 0;               // index in the family registry
  int family_template = 0;      // its row in the family's device table
  double bounding_radius = 0;   // m, about the centre
  double volume = 0;            // m^3
  Vec3 inertia_per_density;     // m^5, principal, body frame
  double equivalent_radius = 0; // m, of the sphere of equal volume
  int contact_features = 1;     // features it may touch another body with (a clump's elements)
  // How output describes and draws it: values its family names it by (frames per particle,
  // checkpoints per template) and its surface in the body frame.
  std::vector<ShapeField> output_fields;
  BodySurface surface;
};

// What a family's setup hook (F::setup_templates, in src/<family>_setup.cpp) gets: the scene's
// shapes of the family in scene order and its settings (null: none in the scene, defaults).
// It returns one ShapeTemplate per shape, in that order (the engine sets family and row), and
// fills the family's device table.
struct FamilyShapes {
  std::vector<const ShapeConfig*> shapes;
  const FamilySettings* settings = nullptr;
};

// The output fields of `templates`, one row per item: item k takes the values of template
// template_of_item[k], or NaN where that template has no such field or the index is negative
// (a sphere). Fields in the order the templates first name them.
std::vector<ShapeField> output_fields_of(const std::vector<ShapeTemplate>& templates,
                                         const std::vector<int>& template_of_item);

struct SourceState {
  std::mt19937_64 rng;
  int material = 0;
  int shape = 0;
  int tag = -1; // index in tag_names
  std::int64_t inserted = 0;
  double next_insertion = 0; // s
  double owed = 0;           // particles due but not yet placed
};

struct Engine::State {
  SceneConfig scene;
  double dt = 0;
  double time = 0;
  std::int64_t step_count = 0;
  Vec3 gravity;
  Vec3d domain_min{0, 0, 0}, domain_max{0, 0, 0};
  double largest_radius = 0;
  double smallest_radius = std::numeric_limits<double>::infinity();
  double skin = 0; // 0: half the smallest radius

  bool rolling = false;
  CoefficientTable coefficients;
  // The scene's shapes (index k: shape id k + 1) as host code needs them, filled by each
  // family's setup; per source, the shape id its particles get.
  std::vector<ShapeTemplate> shape_templates;
  std::vector<int> source_shape;
  // Families: of each shape id (host and device), the template tables, which families the
  // scene holds (bit f: family f of the registry; from its sources and particles), and the rows
  // of each family and pair type at the last list build.
  std::vector<int> family_of_shape;
  ShapeFamilies shape_families;
  ContactContext::Tables family_tables;
  int families_present = 0;
  EngineFamilyRows family_rows;
  NarrowPhaseCounters narrow_phase = NarrowPhaseCounters::allocate();
  ParticleViews particles;
  std::int64_t next_id = 0;
  PairList pairs;
  IdView ids_at_build; // particle ids in the order the lists were built for
  WallContactList wall_contacts;
  WallElementTable table;
  std::vector<WallMotionData> motions;
  WallSet walls;
  WallBinTable wall_bins; // host copy of walls.lookup and walls.cells
  DeviceView<OutletBox*> outlets;
  int outlet_count = 0;
  int outlet_check_interval = 50;
  std::vector<SourceState> sources;
  std::vector<std::string> tag_names; // distinct source tags, in source order

  bool needs_rebuild = true;
  bool rebuild_every_step = false;
  double last_build_time = 0;
  std::int64_t list_builds = 0;
  double discharged_mass = 0;
  std::int64_t discharged_count = 0;
  DomainBounds leaving_bounds; // active: particles wholly outside are removed (lost)
  double lost_mass = 0;
  std::int64_t lost_count = 0;
  std::vector<std::int64_t> latest_lost_ids;
  // J: the mechanical energy the particles may hold without a work source: at the start, plus
  // that of particles inserted, less that of particles removed. Checked by check_health.
  double energy_budget = 0;
  double initial_overlap_ratio = 0; // largest overlap / radius after setup
  // m: the farthest any surface point of a rigid body moved in a step, summed over the steps
  // (from the start of the run). While it grows by less than half a separation certificate's
  // gap, no surface moved far enough to close that gap (SeparationCertificates::unexpired).
  double surface_travel = 0;

  void setup_materials();
  void setup_shapes();
  template <class F> void setup_family_shapes(std::vector<bool>& set_up);
  void refuse_pairs_without_narrow_phase() const;
  void classify_families(const PairList& list);
  void setup_domain();
  void setup_walls();
  void bin_walls(double reach);
  void setup_outlets();
  void setup_leaving_bounds();
  void start_energy_budget();
  void add_surface_travel(double farthest);
  // Throw std::runtime_error naming path, the dataset and the broken rule when the state read
  // from a checkpoint is not one the engine could have written (src/checkpoint_checks.cpp):
  // the particles first, then (with the families present updated) the lists.
  void check_restored_particles(const std::string& path) const;
  void check_restored_lists(const std::string& path) const;
  void setup_sources();
  int material_index(const std::string& name) const;

  Obstacles current_obstacles() const;
  bool sphere_crosses_wall(const Vec3d& centre, double r) const;
  void append_seeds(const std::vector<ParticleSeed>& seeds, int source);
  void append_particles(const std::vector<ParticleInit>& added);
  ParticleViews upload_new_particles(const std::vector<ParticleInit>& added);

  double effective_skin() const;
  double wall_surface_speed(const WallMotionData& m) const;
  double wall_travel_since_build() const;
  bool lists_are_stale() const;
  void rebuild_lists();
  void mark_family_present(int shape_id);
  bool rigid_rotation() const;
  bool needs_narrow_phase_state() const;
  ContactContext contact_context() const;
  template <class Law> void compute_forces_of_families();
  void compute_forces();
  void compute_forces_at_current_state();
  void insert_due_particles();
  void remove_departed_particles();
  std::vector<std::int64_t> ids_of_flagged(const IndexView& flag, int most) const;
  HealthReport check_overlaps() const;
  HealthReport check_energy() const;
  std::vector<std::string> likely_causes(const std::string& trigger) const;
  std::vector<ParticleReport> reports_of(const std::vector<int>& rows) const;
  TimeStepAdvice time_step_advice() const;
  HealthReport check_health() const;
  double time_step_radius() const;
  double hertz_time_at(double speed) const;
  void step();
  ParticleSnapshot make_snapshot() const;
  std::vector<std::string> source_names() const;
  void add_shapes_to_snapshot(ParticleSnapshot& snap) const;
};

} // namespace kdem
