#include "engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "../kernels/diagnostics.hpp"
#include "../kernels/force_sum.hpp"
#include "../kernels/integrate.hpp"
#include "../kernels/pair_forces.hpp"
#include "body_surface.hpp"
#include "engine_state.hpp"
#include "generate.hpp"
#include "host_copy.hpp"
#include "restitution.hpp"
#include "wall_builder.hpp"

namespace kdem {
namespace {

Vec3 to_vec3(const Vec3d& a) {
  return {a[0], a[1], a[2]};
}

// Pairs of different materials without an `interactions` entry take the mean of both values.
double mean(double a, double b) {
  return 0.5 * (a + b);
}

// E* and G* of Hertz-Mindlin (Johnson 1985; Mindlin 1949 as in LIGGGHTS and EDEM).
PairCoefficients coefficients_for(const MaterialConfig& a, const MaterialConfig& b,
                                  const std::vector<InteractionConfig>& interactions) {
  PairCoefficients c;
  c.effective_youngs = 1.0 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                              (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
  c.effective_shear = 1.0 / (2 * (2 - a.poisson_ratio) * (1 + a.poisson_ratio) / a.youngs_modulus +
                             2 * (2 - b.poisson_ratio) * (1 + b.poisson_ratio) / b.youngs_modulus);
  double restitution = mean(a.restitution, b.restitution);
  c.friction = mean(a.friction, b.friction);
  c.rolling_friction = mean(a.rolling_friction, b.rolling_friction);
  for (const InteractionConfig& i : interactions) {
    if ((i.material_a == a.name && i.material_b == b.name) ||
        (i.material_a == b.name && i.material_b == a.name)) {
      restitution = i.restitution;
      c.friction = i.friction;
      c.rolling_friction = i.rolling_friction;
    }
  }
  c.damping = damping_for_restitution(restitution);
  return c;
}

WallMotion motion_of(const WallMotionData& m) {
  WallMotion d;
  d.pivot = to_vec3(m.pivot);
  d.velocity = to_vec3(m.velocity);
  d.omega = to_vec3(m.omega);
  d.start = m.start;
  d.active_from = m.active_from;
  d.active_until = m.active_until;
  return d;
}

Vec3 geometry_point(const std::array<double, 9>& g, int first) {
  return {g[first], g[first + 1], g[first + 2]};
}

// Whether a sphere at reference-frame centre p touches or reaches through element g: behind or
// within r of a plane, outside or within r of a cylinder's surface along its length, within r of
// a triangle.
bool sphere_crosses_element(int kind, const std::array<double, 9>& g, Vec3 p, double r) {
  if (kind == plane_element)
    return plane_query(geometry_point(g, 0), geometry_point(g, 3), p).signed_distance < r;
  if (kind == cylinder_element) {
    double along = 0;
    const SurfaceQuery q =
        cylinder_inside_query(geometry_point(g, 0), geometry_point(g, 3), g[6], p, along);
    return along >= -r && along <= g[7] + r && q.signed_distance < r;
  }
  return triangle_query(geometry_point(g, 0), geometry_point(g, 3), geometry_point(g, 6), p)
             .signed_distance < r;
}

} // namespace

Engine::Engine(const SceneConfig& scene) : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.scene = scene;
  s.dt = scene.time_step;
  s.gravity = to_vec3(scene.gravity);
  s.setup_materials();
  s.setup_shapes();
  s.setup_domain();
  s.setup_walls();
  s.setup_outlets();
  s.setup_leaving_bounds();
  s.setup_sources();
  s.compute_forces_at_current_state();
  s.start_energy_budget();
}

Engine::~Engine() = default;

void Engine::State::setup_materials() {
  const int n = int(scene.materials.size());
  if (n == 0)
    throw std::runtime_error(scene.source_file + ": no materials defined");
  coefficients = CoefficientTable("pair_coefficients", n, n);
  auto mirror = Kokkos::create_mirror_view(coefficients);
  rolling = false;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      mirror(a, b) = coefficients_for(scene.materials[a], scene.materials[b], scene.interactions);
      rolling = rolling || mirror(a, b).rolling_friction > 0;
    }
  Kokkos::deep_copy(coefficients, mirror);
}

int Engine::material_index(const std::string& name) const {
  return state_->material_index(name);
}

int Engine::State::material_index(const std::string& name) const {
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    if (scene.materials[m].name == name)
      return int(m);
  throw std::runtime_error(scene.source_file + ": unknown material '" + name + "'");
}

void Engine::State::setup_domain() {
  Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  auto include = [&](const Vec3d& a, const Vec3d& b) {
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], a[k]), hi[k] = std::max(hi[k], b[k]);
  };
  if (scene.has_domain) {
    include(scene.domain_min, scene.domain_max);
  } else {
    Vec3d wall_lo, wall_hi;
    if (walls_bounding_box(scene.walls, wall_lo, wall_hi))
      include(wall_lo, wall_hi);
    for (const ParticleSourceConfig& src : scene.sources) {
      const RegionConfig& r = src.region;
      if (r.kind == RegionConfig::Kind::Box) {
        include(r.min, r.max);
      } else {
        const Vec3d& c = r.base_center;
        include({c[0] - r.radius, c[1] - r.radius, c[2]},
                {c[0] + r.radius, c[1] + r.radius, c[2] + r.height});
      }
    }
    if (lo[0] > hi[0])
      lo = {-1, -1, -1}, hi = {1, 1, 1};
  }
  domain_min = lo;
  domain_max = hi;
  for (const ParticleSourceConfig& src : scene.sources) {
    const RadiusRange radii = possible_radii(src.sizes);
    largest_radius = std::max(largest_radius, radii.largest);
    smallest_radius = std::min(smallest_radius, radii.smallest);
  }
  skin = scene.skin;
}

void Engine::State::setup_walls() {
  table = build_wall_elements(scene.walls, domain_min, domain_max,
                              largest_radius > 0 ? 2 * largest_radius + effective_skin() : 0);
  motions = wall_motions(scene.walls);
  WallSet& w = walls;
  w.wall_count = int(scene.walls.size());
  w.elements = upload_wall_elements(table);
  std::vector<WallMotion> device_motions;
  for (const WallMotionData& m : motions) {
    WallMotion d = motion_of(m);
    d.material = material_index(m.material);
    device_motions.push_back(d);
  }
  w.motion = upload<WallMotion>("wall_motion", device_motions);
  w.pose = DeviceView<WallPose*>("wall_pose", w.wall_count);
  update_wall_poses(w, time);
  bin_walls(largest_radius + effective_skin());
}

// Mesh grids for particles of radius plus skin up to `reach` (a reach of 0, before any particle
// size is known, gives grids for a reach of 1 mm; larger particles are then rebinned by
// rebuild_lists).
void Engine::State::bin_walls(double reach) {
  wall_bins = bin_wall_elements(table, walls.wall_count, reach > 0 ? reach : 1e-3);
  upload_wall_lookup(walls, wall_bins);
}

void Engine::State::setup_outlets() {
  std::vector<OutletBox> boxes;
  for (const OutletConfig& o : scene.outlets) {
    OutletBox b;
    for (int a = 0; a < 3; ++a)
      b.min[a] = o.min[a], b.max[a] = o.max[a];
    boxes.push_back(b);
  }
  outlet_count = int(boxes.size());
  outlets = upload<OutletBox>("outlets", boxes);
}

// With a `domain`, particles must stay in it; without one, in the box of the walls, plane points,
// particle regions and outlets grown by half its largest side on every side (the neighbour
// grid's derived domain is tight, and particles may rest just outside it, on a plane).
void Engine::State::setup_leaving_bounds() {
  Vec3d lo = domain_min, hi = domain_max;
  if (!scene.has_domain) {
    auto include = [&](const Vec3d& a, const Vec3d& b) {
      for (int k = 0; k < 3; ++k)
        lo[k] = std::min(lo[k], a[k]), hi[k] = std::max(hi[k], b[k]);
    };
    for (const OutletConfig& o : scene.outlets)
      include(o.min, o.max);
    for (const WallConfig& w : scene.walls)
      if (w.kind == WallConfig::Kind::Plane)
        include(w.point, w.point);
    const double margin = 0.5 * std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    for (int k = 0; k < 3; ++k)
      lo[k] -= margin, hi[k] += margin;
  }
  for (int k = 0; k < 3; ++k)
    leaving_bounds.min[k] = lo[k], leaving_bounds.max[k] = hi[k];
  leaving_bounds.active = scene.checks.leaving_domain == ChecksConfig::Leaving::Remove;
}

void Engine::State::start_energy_budget() {
  energy_budget = kinetic_and_potential_energy(particles, gravity).mechanical();
  initial_overlap_ratio =
      std::max(pair_contact_statistics(particles, pairs).largest_overlap_ratio,
               wall_contact_statistics(particles, wall_contacts).largest_overlap_ratio);
}

// The index of `tag` in tag_names, adding it when new; -1 for no tag.
static int tag_index(std::vector<std::string>& tag_names, const std::string& tag) {
  if (tag.empty())
    return -1;
  for (std::size_t k = 0; k < tag_names.size(); ++k)
    if (tag_names[k] == tag)
      return int(k);
  tag_names.push_back(tag);
  return int(tag_names.size()) - 1;
}

void Engine::State::setup_sources() {
  sources.resize(scene.sources.size());
  for (std::size_t k = 0; k < scene.sources.size(); ++k)
    sources[k].tag = tag_index(tag_names, scene.sources[k].tag);
  for (std::size_t k = 0; k < scene.sources.size(); ++k) {
    const ParticleSourceConfig& src = scene.sources[k];
    SourceState& st = sources[k];
    st.rng.seed(src.seed);
    st.material = material_index(src.material);
    st.shape = source_shape[k];
    st.next_insertion = src.start;
    if (src.rate > 0)
      continue;
    const std::int64_t wanted = src.count > 0 ? src.count : std::int64_t(1) << 40;
    const std::vector<ParticleSeed> seeds =
        generate_particles(src, wanted, current_obstacles(), st.rng);
    if (src.count > 0 && std::int64_t(seeds.size()) < src.count) {
      std::ostringstream msg;
      msg << scene.source_file << ": particles '" << src.name << "': only " << seeds.size()
          << " of " << src.count
          << " particles fit in the region without overlaps; enlarge the region or lower the count";
      throw std::runtime_error(msg.str());
    }
    st.inserted = std::int64_t(seeds.size());
    append_seeds(seeds, int(k));
  }
}

// The particles that new ones must not overlap: positions and radii only, brought to the host
// as input of the insertion (see docs/architecture.md, memory spaces).
Obstacles Engine::State::current_obstacles() const {
  Kokkos::Profiling::pushRegion("kdem::input");
  const std::vector<double> position = flatten_to_host(particles.position, particles.count);
  const std::vector<double> radius = flatten_to_host(particles.radius, particles.count);
  Kokkos::Profiling::popRegion();
  Obstacles obstacles;
  obstacles.crosses_wall = [this](const Vec3d& centre, double r) {
    return sphere_crosses_wall(centre, r);
  };
  obstacles.radii = radius;
  obstacles.centres.reserve(radius.size());
  for (std::size_t i = 0; i < radius.size(); ++i)
    obstacles.centres.push_back({position[3 * i], position[3 * i + 1], position[3 * i + 2]});
  return obstacles;
}

// Against every wall active now, at its pose now. Host code: insertion is input (see
// docs/architecture.md); it tests the elements of the sphere's cell of each mesh grid.
bool Engine::State::sphere_crosses_wall(const Vec3d& centre, double r) const {
  const Vec3 world = to_vec3(centre);
  bool crosses = false;
  for (int w = 0; w < int(motions.size()) && !crosses; ++w) {
    if (time < motions[w].active_from || time >= motions[w].active_until)
      continue;
    const Vec3 p = wall_pose_at(motion_of(motions[w]), time).to_reference(world);
    for_each_candidate_on_host(wall_bins, w, p, r, [&](int e) {
      crosses = crosses || sphere_crosses_element(table.kind[e], table.geometry[e], p, r);
    });
  }
  return crosses;
}

void Engine::State::append_seeds(const std::vector<ParticleSeed>& seeds, int source) {
  const SourceState& st = sources[source];
  std::vector<ParticleInit> inits;
  inits.reserve(seeds.size());
  for (const ParticleSeed& seed : seeds) {
    ParticleInit p;
    p.position = seed.position;
    p.velocity = seed.velocity;
    p.angular_velocity = seed.angular_velocity;
    p.orientation = seed.orientation;
    p.radius = seed.radius;
    p.material = st.material;
    p.shape = st.shape;
    p.source = source;
    p.tag = st.tag;
    inits.push_back(p);
  }
  append_particles(inits);
}

void Engine::add_particles(const std::vector<ParticleInit>& particles) {
  state_->append_particles(particles);
  state_->compute_forces_at_current_state();
}

// New particles go at the end, with fresh stable ids; lists are rebuilt before the next forces.
void Engine::State::append_particles(const std::vector<ParticleInit>& added) {
  if (added.empty())
    return;
  // Input: the one host-to-device transfer a time step may make (see docs/architecture.md).
  Kokkos::Profiling::pushRegion("kdem::input");
  const ParticleViews fresh = upload_new_particles(added);
  Kokkos::Profiling::popRegion();
  energy_budget += kinetic_and_potential_energy(fresh, gravity).mechanical();
  const int old_count = particles.count;
  ParticleViews grown;
  grown.allocate(old_count + fresh.count);
  copy_particle_rows(particles, grown, old_count);
  copy_particle_rows(fresh, grown, fresh.count, old_count);
  particles = grown;
  for (const ParticleInit& p : added) {
    const double radius =
        p.shape == sphere_shape ? p.radius : shape_templates[p.shape - 1].bounding_radius;
    largest_radius = std::max(largest_radius, radius);
    smallest_radius = std::min(smallest_radius, radius);
    mark_family_present(p.shape);
  }
  needs_rebuild = true;
}

// Device rows for `added`, with mass and inertia from the material and fresh ids.
ParticleViews Engine::State::upload_new_particles(const std::vector<ParticleInit>& added) {
  ParticleViews p;
  p.allocate(int(added.size()));
  auto x = Kokkos::create_mirror_view(p.position);
  auto v = Kokkos::create_mirror_view(p.velocity);
  auto w = Kokkos::create_mirror_view(p.angular_velocity);
  auto q = Kokkos::create_mirror_view(p.orientation);
  auto radius = Kokkos::create_mirror_view(p.radius);
  auto mass = Kokkos::create_mirror_view(p.mass);
  auto inertia = Kokkos::create_mirror_view(p.inertia);
  auto material = Kokkos::create_mirror_view(p.material);
  auto shape = Kokkos::create_mirror_view(p.shape);
  auto source = Kokkos::create_mirror_view(p.source);
  auto tag = Kokkos::create_mirror_view(p.tag);
  auto id = Kokkos::create_mirror_view(p.id);
  for (int i = 0; i < p.count; ++i) {
    const ParticleInit& a = added[i];
    if (a.shape < 0 || a.shape > int(shape_templates.size()))
      throw std::runtime_error("particle shape id out of range");
    if (a.shape == sphere_shape && !(a.radius > 0))
      throw std::runtime_error("particle radius must be positive");
    if (a.material < 0 || a.material >= int(scene.materials.size()))
      throw std::runtime_error("particle material index out of range");
    if (a.source < -1 || a.source >= int(sources.size()))
      throw std::runtime_error("particle source index out of range");
    if (a.tag < -1 || a.tag >= int(tag_names.size()))
      throw std::runtime_error("particle tag index out of range");
    for (int c = 0; c < 3; ++c)
      x(i, c) = a.position[c], v(i, c) = a.velocity[c], w(i, c) = a.angular_velocity[c];
    for (int c = 0; c < 4; ++c)
      q(i, c) = a.orientation[c];
    const double density = scene.materials[a.material].density;
    if (a.shape == sphere_shape) {
      radius(i) = a.radius;
      mass(i) = density * sphere_volume(a.radius);
      for (int c = 0; c < 3; ++c)
        inertia(i, c) = sphere_inertia(mass(i), a.radius);
    } else {
      const int k = a.shape - 1;
      const ShapeTemplate& t = shape_templates[k];
      radius(i) = t.bounding_radius;
      mass(i) = density * t.volume;
      inertia(i, 0) = density * t.inertia_per_density.x;
      inertia(i, 1) = density * t.inertia_per_density.y;
      inertia(i, 2) = density * t.inertia_per_density.z;
    }
    material(i) = a.material;
    shape(i) = a.shape;
    source(i) = a.source;
    tag(i) = a.tag;
    id(i) = next_id + i;
  }
  next_id += p.count;
  Kokkos::deep_copy(p.position, x);
  Kokkos::deep_copy(p.velocity, v);
  Kokkos::deep_copy(p.angular_velocity, w);
  Kokkos::deep_copy(p.orientation, q);
  Kokkos::deep_copy(p.radius, radius);
  Kokkos::deep_copy(p.mass, mass);
  Kokkos::deep_copy(p.inertia, inertia);
  Kokkos::deep_copy(p.material, material);
  Kokkos::deep_copy(p.shape, shape);
  Kokkos::deep_copy(p.source, source);
  Kokkos::deep_copy(p.tag, tag);
  Kokkos::deep_copy(p.id, id);
  return p;
}

double Engine::State::effective_skin() const {
  return skin > 0 ? skin
                  : default_skin_per_radius *
                        (smallest_radius < 1e300 ? smallest_radius : largest_radius);
}

// Fastest speed of any point of a wall within the domain: its translation plus its spin times
// the domain's diagonal.
double Engine::State::wall_surface_speed(const WallMotionData& m) const {
  const Vec3d extent{domain_max[0] - domain_min[0], domain_max[1] - domain_min[1],
                     domain_max[2] - domain_min[2]};
  const double reach =
      std::sqrt(extent[0] * extent[0] + extent[1] * extent[1] + extent[2] * extent[2]);
  const double speed = std::sqrt(m.velocity[0] * m.velocity[0] + m.velocity[1] * m.velocity[1] +
                                 m.velocity[2] * m.velocity[2]);
  const double spin =
      std::sqrt(m.omega[0] * m.omega[0] + m.omega[1] * m.omega[1] + m.omega[2] * m.omega[2]);
  return speed + spin * reach;
}

// Conservative bound on how far any wall surface point has moved since the lists were built.
double Engine::State::wall_travel_since_build() const {
  const double elapsed = time - last_build_time;
  double travel = 0;
  for (const WallMotionData& m : motions)
    travel = std::max(travel, wall_surface_speed(m) * elapsed);
  return travel;
}

bool Engine::State::lists_are_stale() const {
  if (needs_rebuild || rebuild_every_step)
    return true;
  const double half_skin = 0.5 * effective_skin();
  const double moved = std::sqrt(max_displacement_squared(particles));
  return moved > half_skin || moved + wall_travel_since_build() > effective_skin();
}

void Engine::State::rebuild_lists() {
  const double list_skin = effective_skin();
  // Old lists are indexed by the particle order of their build, which insertion and removal
  // have changed since; map ids through the order saved at that build.
  const IndexView old_rows = rows_by_id(ids_at_build, int(ids_at_build.extent(0)), next_id);
  const double lo[3] = {domain_min[0], domain_min[1], domain_min[2]};
  const double hi[3] = {domain_max[0], domain_max[1], domain_max[2]};
  double cell_size = 2 * largest_radius + list_skin;
  if (!(cell_size > 0) || !std::isfinite(cell_size))
    cell_size = std::max(hi[0] - lo[0], 1e-3);
  const CellGrid grid = make_cell_grid(lo, hi, cell_size, 8'000'000);
  const CellBins bins = sort_particles_by_cell(particles, grid, scene.sort_by_cell);
  families_present |= present_families(particles, shape_families);
  PairList fresh_pairs = build_pair_list(particles, bins, list_skin);
  classify_families(fresh_pairs);
  assign_slots_by_pair_type<Families>(fresh_pairs, particles, shape_families, families_present);
  allocate_pair_contacts(fresh_pairs, rolling, needs_narrow_phase_state());
  if (pairs.pair_count > 0)
    transfer_pair_history(fresh_pairs, pairs, old_rows, particles.id);
  pairs = fresh_pairs;
  if (largest_radius + list_skin > wall_bins.reach)
    bin_walls(largest_radius + list_skin);
  WallContactList fresh_walls = build_wall_contact_list(particles, walls, list_skin, sphere_shape);
  assign_wall_slots_by_family<Families>(fresh_walls, particles, shape_families, families_present);
  allocate_wall_contacts(fresh_walls, walls.elements, rolling);
  if (wall_contacts.entry_count > 0)
    transfer_wall_history(fresh_walls, wall_contacts, old_rows, particles.id, particles.count);
  wall_contacts = fresh_walls;
  remember_build_positions(particles);
  ids_at_build = particles.id;
  last_build_time = time;
  needs_rebuild = false;
  ++list_builds;
}

void Engine::State::mark_family_present(int shape_id) {
  families_present |= 1 << family_of_shape.at(shape_id);
}

bool Engine::State::rigid_rotation() const {
  return any_present_family(families_present,
                            [](auto tag) { return decltype(tag)::type::rigid_rotation; });
}

bool Engine::State::needs_narrow_phase_state() const {
  return any_present_family(families_present,
                            [](auto tag) { return decltype(tag)::type::iterative_narrow_phase; });
}

ContactContext Engine::State::contact_context() const {
  ContactContext c;
  c.particles = particles;
  c.pairs = pairs;
  c.walls = walls;
  c.wall_contacts = wall_contacts;
  c.coefficients = coefficients;
  c.shape_families = shape_families;
  c.tables = family_tables;
  c.counters = narrow_phase;
  c.dt = dt;
  c.surface_travel = surface_travel;
  return c;
}

// The typed kernels of the families and pair types the scene holds, each over its rows.
template <class Law> void Engine::State::compute_forces_of_families() {
  const ContactContext c = contact_context();
  const int present = families_present;
  for_each_present_family(present, [&](auto tag) {
    using F = typename decltype(tag)::type;
    compute_family_wall_contacts<F, Law>(c, family_rows.of<F>());
  });
  for_each_pair_type<Families>([&](auto tag_a, auto tag_b) {
    using A = typename decltype(tag_a)::type;
    using B = typename decltype(tag_b)::type;
    const int both = (1 << family_index_v<A, Families>) | (1 << family_index_v<B, Families>);
    if constexpr (pair_type_implemented<A, B>::value)
      if ((present & both) == both)
        compute_pair_type<A, B, Law>(c, family_rows.of_pair<A, B>());
  });
}

void Engine::State::compute_forces() {
  if (rolling)
    compute_forces_of_families<HertzMindlin<true>>();
  else
    compute_forces_of_families<HertzMindlin<false>>();
  sum_forces(particles, gravity, wall_contacts, pairs);
}

void Engine::State::compute_forces_at_current_state() {
  update_wall_poses(walls, time);
  if (lists_are_stale())
    rebuild_lists();
  compute_forces();
}

void Engine::State::insert_due_particles() {
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const ParticleSourceConfig& src = scene.sources[k];
    SourceState& st = sources[k];
    if (src.rate <= 0 || st.inserted >= src.count || time < st.next_insertion)
      continue;
    st.owed += src.rate * src.interval;
    const std::int64_t batch =
        std::min<std::int64_t>(std::int64_t(st.owed), src.count - st.inserted);
    const std::vector<ParticleSeed> seeds =
        generate_particles(src, batch, current_obstacles(), st.rng);
    st.owed -= double(seeds.size());
    st.inserted += std::int64_t(seeds.size());
    st.next_insertion += src.interval;
    append_seeds(seeds, int(k));
  }
}

// Outlets and the domain's bounds: removed particles are counted, and their energy leaves the
// budget.
void Engine::State::remove_departed_particles() {
  if ((outlet_count == 0 && !leaving_bounds.active) || particles.count == 0)
    return;
  IndexView keep("keep", particles.count);
  IndexView lost("lost", particles.count);
  const Removals removed =
      mark_removals(particles, outlets, outlet_count, leaving_bounds, keep, lost);
  if (removed.discharged + removed.lost == 0)
    return;
  if (removed.lost > 0)
    latest_lost_ids = ids_of_flagged(lost, 5);
  energy_budget -= energy_of_removed(particles, gravity, keep).mechanical();
  int kept = 0;
  const IndexView source = kept_indices(keep, kept);
  permute_particles(particles, source, kept);
  discharged_mass += removed.discharged_mass;
  discharged_count += removed.discharged;
  lost_mass += removed.lost_mass;
  lost_count += removed.lost;
  needs_rebuild = true;
}

void Engine::step() {
  state_->step();
}

// Each addition is raised by more than its rounding, so that a difference of two sums is never
// below the travel of the steps between them.
void Engine::State::add_surface_travel(double farthest) {
  surface_travel +=
      farthest * (1 + 1e-12) + 4 * std::numeric_limits<double>::epsilon() * surface_travel;
}

void Engine::State::step() {
  if (rigid_rotation())
    add_surface_travel(kick_and_drift_rigid(particles, dt));
  else
    kick_and_drift(particles, dt);
  time = double(step_count + 1) * dt;
  insert_due_particles();
  if ((step_count + 1) % outlet_check_interval == 0)
    remove_departed_particles();
  compute_forces_at_current_state();
  if (rigid_rotation())
    kick_rigid(particles, dt);
  else
    kick(particles, dt);
  ++step_count;
}

void Engine::advance(std::int64_t steps) {
  for (std::int64_t k = 0; k < steps; ++k)
    state_->step();
}

double Engine::time() const {
  return state_->time;
}
std::int64_t Engine::step_count() const {
  return state_->step_count;
}
int Engine::particle_count() const {
  return state_->particles.count;
}
int Engine::pair_candidates() const {
  return state_->pairs.pair_count;
}

int Engine::wall_candidates() const {
  return state_->wall_contacts.entry_count;
}

double Engine::time_step() const {
  return state_->dt;
}
double Engine::skin() const {
  return state_->effective_skin();
}
void Engine::set_rebuild_every_step(bool every_step) {
  state_->rebuild_every_step = every_step;
}

std::string Engine::backend_name() {
  return ExecSpace::name();
}
int Engine::backend_concurrency() {
  return ExecSpace().concurrency();
}

Diagnostics Engine::diagnostics() const {
  const State& s = *state_;
  Diagnostics d;
  d.step = s.step_count;
  d.time = s.time;
  d.particles = s.particles.count;
  const EnergySums e = kinetic_and_potential_energy(s.particles, s.gravity);
  d.translational_energy = e.translational;
  d.rotational_energy = e.rotational;
  d.potential_energy = e.potential;
  const ContactStatistics pair = pair_contact_statistics(s.particles, s.pairs);
  const ContactStatistics wall = wall_contact_statistics(s.particles, s.wall_contacts);
  d.pair_contacts = pair.contacts;
  d.wall_contacts = wall.contacts;
  d.largest_overlap_ratio = std::max(pair.largest_overlap_ratio, wall.largest_overlap_ratio);
  d.discharged_mass = s.discharged_mass;
  d.discharged_count = s.discharged_count;
  d.lost_mass = s.lost_mass;
  d.lost_count = s.lost_count;
  d.list_builds = s.list_builds;
  d.particles_per_source = count_by_label(s.particles, s.particles.source, int(s.sources.size()));
  d.particles_per_tag = count_by_label(s.particles, s.particles.tag, int(s.tag_names.size()));
  return d;
}

ParticleSnapshot Engine::State::make_snapshot() const {
  ParticleSnapshot snap;
  const ParticleViews& p = particles;
  snap.step = step_count;
  snap.time = time;
  if (p.count == 0)
    return snap;
  snap.position = flatten_to_host(p.position, p.count);
  snap.velocity = flatten_to_host(p.velocity, p.count);
  snap.angular_velocity = flatten_to_host(p.angular_velocity, p.count);
  snap.quaternion = flatten_to_host(p.orientation, p.count);
  snap.radius = flatten_to_host(p.radius, p.count);
  snap.shape = flatten_to_host(p.shape, p.count);
  snap.material = flatten_to_host(p.material, p.count);
  snap.id = flatten_to_host(p.id, p.count);
  snap.source = flatten_to_host(p.source, p.count);
  snap.tag = flatten_to_host(p.tag, p.count);
  snap.source_names = source_names();
  snap.tag_names = tag_names;
  if (!shape_templates.empty())
    add_shapes_to_snapshot(snap);
  return snap;
}

// Output fields per particle (NaN for spheres and shapes without the field); a surface per
// shape id, the unit sphere for shape 0.
void Engine::State::add_shapes_to_snapshot(ParticleSnapshot& snap) const {
  std::vector<int> template_of_particle(snap.size());
  for (std::size_t i = 0; i < snap.size(); ++i)
    template_of_particle[i] = snap.shape[i] - 1;
  snap.shape_fields = output_fields_of(shape_templates, template_of_particle);
  snap.shape_surfaces = {unit_sphere_surface(output_surface_resolution)};
  for (const ShapeTemplate& t : shape_templates)
    snap.shape_surfaces.push_back(t.surface);
}

std::vector<std::string> Engine::State::source_names() const {
  std::vector<std::string> names;
  for (const ParticleSourceConfig& src : scene.sources)
    names.push_back(src.name);
  return names;
}

std::vector<std::string> Engine::source_names() const {
  return state_->source_names();
}

std::vector<std::string> Engine::tag_names() const {
  return state_->tag_names;
}

ParticleSnapshot Engine::snapshot() const {
  return state_->make_snapshot();
}

std::vector<WallSurface> Engine::wall_surfaces() const {
  const State& s = *state_;
  std::vector<WallSurface> surfaces;
  for (std::size_t w = 0; w < s.scene.walls.size(); ++w) {
    const WallPose pose = wall_pose_at(motion_of(s.motions[w]), s.time);
    WallSurface surface;
    surface.name = s.scene.walls[w].name;
    const std::vector<double>& ref = s.table.surface_points[w];
    for (std::size_t k = 0; k + 2 < ref.size(); k += 3) {
      const Vec3 world = pose.to_world(Vec3{ref[k], ref[k + 1], ref[k + 2]});
      surface.points.insert(surface.points.end(), {world.x, world.y, world.z});
    }
    surface.triangles = s.table.surface_triangles[w];
    surfaces.push_back(std::move(surface));
  }
  return surfaces;
}

std::vector<ContactForceRecord> Engine::contact_forces() const {
  const State& s = *state_;
  std::vector<ContactForceRecord> records;
  const int n = s.particles.count;
  if (n == 0)
    return records;
  const std::vector<std::int64_t> id = flatten_to_host(s.particles.id, n);
  const auto nonzero = [](const double* f) { return f[0] != 0 || f[1] != 0 || f[2] != 0; };
  if (s.pairs.pair_count > 0) {
    const std::vector<int> pair_i = flatten_to_host(s.pairs.pair_i, s.pairs.pair_count);
    const std::vector<int> pair_j = flatten_to_host(s.pairs.pair_j, s.pairs.pair_count);
    const std::vector<double> force = flatten_to_host(s.pairs.force_on_i, s.pairs.pair_count);
    for (int k = 0; k < s.pairs.pair_count; ++k) {
      const double* f = &force[3 * std::size_t(k)];
      if (nonzero(f))
        records.push_back(
            {id[std::size_t(pair_i[k])], id[std::size_t(pair_j[k])], -1, {f[0], f[1], f[2]}});
    }
  }
  const WallContactList& walls = s.wall_contacts;
  if (walls.entry_count > 0) {
    const std::vector<int> row_start = flatten_to_host(walls.row_start, n + 1);
    const std::vector<int> element = flatten_to_host(walls.element, walls.entry_count);
    const std::vector<double> force = flatten_to_host(walls.force_on_i, walls.entry_count);
    const std::vector<int> wall_of = flatten_to_host(s.walls.elements.wall, s.walls.elements.count);
    // An entry touches when its first slot does (as sum_forces reads it); its force is not
    // written otherwise.
    const std::vector<double> overlap = flatten_to_host(walls.overlap, walls.slot_count);
    const std::vector<int> slot_start =
        walls.contact_start.extent(0) == 0
            ? std::vector<int>{}
            : flatten_to_host(walls.contact_start, walls.entry_count + 1);
    const auto first_slot = [&](int k) {
      return slot_start.empty() ? std::size_t(k) : std::size_t(slot_start[std::size_t(k)]);
    };
    for (int i = 0; i < n; ++i)
      for (int k = row_start[std::size_t(i)]; k < row_start[std::size_t(i) + 1]; ++k) {
        const double* f = &force[3 * std::size_t(k)];
        if (overlap[first_slot(k)] != 0 && nonzero(f))
          records.push_back({id[std::size_t(i)],
                             -1,
                             wall_of[std::size_t(element[std::size_t(k)])],
                             {f[0], f[1], f[2]}});
      }
  }
  return records;
}

// The radius the time step is sized for: the smallest particle's (of a shaped body, that of the
// sphere of equal volume, not its bounding radius); 0 when the scene has no particles yet.
double Engine::State::time_step_radius() const {
  double r = smallest_radius < 1e300 ? smallest_radius : largest_radius;
  for (const ShapeTemplate& t : shape_templates)
    r = std::min(r, t.equivalent_radius);
  return r > 0 ? r : 0;
}

// Hertz duration of a head-on impact of two equal spheres of the smallest radius at `speed`
// (Johnson 1985): 2.87 (m*^2 / (R* E*^2 v))^(1/5), the shortest over the materials.
double Engine::State::hertz_time_at(double speed) const {
  const double r = time_step_radius();
  double shortest = 1e300;
  for (const MaterialConfig& m : scene.materials) {
    const double mass = m.density * sphere_volume(r);
    const double m_eff = 0.5 * mass, r_eff = 0.5 * r;
    const double e_eff = m.youngs_modulus / (2 * (1 - m.poisson_ratio * m.poisson_ratio));
    shortest =
        std::min(shortest, 2.87 * std::pow(m_eff * m_eff / (r_eff * e_eff * e_eff * speed), 0.2));
  }
  return shortest;
}

// Rayleigh time (Li et al. 2005): pi r sqrt(rho / G) / (0.1631 nu + 0.8766), and the Hertz
// duration at the reference speed. The 20 % and 10 % factors are the usual limits (LIGGGHTS
// checks the same two).
TimeStepAdvice Engine::time_step_advice() const {
  return state_->time_step_advice();
}

TimeStepAdvice Engine::State::time_step_advice() const {
  const State& s = *this;
  TimeStepAdvice advice;
  const double r = s.time_step_radius();
  if (!(r > 0))
    return advice;
  double height = s.domain_max[2] - s.domain_min[2];
  advice.reference_speed = std::max(1.0, std::sqrt(2 * 9.81 * std::max(height, 0.0)));
  for (const ParticleSourceConfig& src : s.scene.sources)
    advice.reference_speed =
        std::max(advice.reference_speed,
                 std::sqrt(src.velocity[0] * src.velocity[0] + src.velocity[1] * src.velocity[1] +
                           src.velocity[2] * src.velocity[2]));
  advice.rayleigh = 1e300;
  for (const MaterialConfig& m : s.scene.materials) {
    const double shear = m.youngs_modulus / (2 * (1 + m.poisson_ratio));
    advice.rayleigh = std::min(advice.rayleigh, pi * r * std::sqrt(m.density / shear) /
                                                    (0.1631 * m.poisson_ratio + 0.8766));
  }
  advice.hertz = s.hertz_time_at(advice.reference_speed);
  advice.suggested = std::min(0.2 * advice.rayleigh, 0.1 * advice.hertz);
  return advice;
}

// The one instantiation of the integrators (see the note in kernels/integrate.hpp); here, with
// their one caller, where the compiler gave them 23 instructions per particle-step fewer than in
// a unit of their own.
template double kick_and_drift<IsotropicRotation>(const ParticleViews&, double);
template double kick_and_drift<RigidBodyRotation>(const ParticleViews&, double);
template void kick<IsotropicRotation>(const ParticleViews&, double);
template void kick<RigidBodyRotation>(const ParticleViews&, double);

// The one instantiation of the slot assignments, which hold a KOKKOS_LAMBDA (checkpoint_checks.cpp
// declares them extern; scripts/check_cuda_lambdas.sh).
template void assign_slots_by_pair_type<Families>(PairList&, const ParticleViews&,
                                                  const ShapeFamilies&, int);
template void assign_wall_slots_by_family<Families>(WallContactList&, const ParticleViews&,
                                                    const ShapeFamilies&, int);

} // namespace kdem
