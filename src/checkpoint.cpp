// HDF5 checkpoints: the whole engine state, in the current particle order and with the current
// contact lists, so that a restart continues bit for bit.
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "engine_state.hpp"
#include "hdf5_io.hpp"
#include "host_copy.hpp"

namespace kdem {
namespace {

// 2: particles carry their source and tag; pair and wall lists their contact slots.
// 3: pair lists carry the last step of each Newton warm start (pairs/midway_step).
// Files of formats 1 and 2 are read too: format 1 particles get no source or tag (-1), its
// lists one slot per pair or entry; formats 1 and 2 give every warm start a zero step.
constexpr std::int64_t checkpoint_format = 4;

template <class View> void save_view(Hdf5Writer& out, const std::string& name, const View& view) {
  const int rows = view.data() ? int(view.extent(0)) : 0;
  const auto values =
      rows > 0 ? flatten_to_host(view, rows) : std::vector<typename View::non_const_value_type>{};
  out.write(name, values, {hsize_t(rows), hsize_t(columns_of(view))});
}

template <class View> void load_view(const Hdf5Reader& in, const std::string& name, View& view) {
  using Value = typename View::non_const_value_type;
  std::vector<Value> values;
  std::vector<hsize_t> shape;
  if constexpr (std::is_same_v<Value, double>)
    values = in.read_doubles(name, &shape);
  else if constexpr (std::is_same_v<Value, int>)
    values = in.read_ints(name, &shape);
  else
    values = in.read_int64(name, &shape);
  constexpr std::size_t columns = View::rank == 1 ? 1 : View::static_extent(1);
  if (shape.size() != 2 || shape[1] != columns)
    throw std::runtime_error(in.path().string() + ": checkpoint dataset " + name +
                             " is not a table of " + std::to_string(columns) + " column(s)");
  if (shape[0] > hsize_t(std::numeric_limits<int>::max()))
    throw std::runtime_error(in.path().string() + ": checkpoint dataset " + name +
                             " has too many rows");
  view = view_from_host<View>(name, values, int(columns));
}

// The format that added a dataset (1: there from the start).
std::int64_t format_that_added(const std::string& name) {
  if (name == "particles/source" || name == "particles/tag" || name == "pairs/contact_start" ||
      name == "pairs/feature_i" || name == "pairs/feature_j" ||
      name == "wall_contacts/contact_start" || name == "wall_contacts/feature")
    return 2;
  if (name == "pairs/midway_step")
    return 3;
  if (name == "pairs/separation_expiry")
    return 4;
  return 1;
}

// What an older file stands for instead of a dataset it lacks: per particle -1 (no label), per
// pair nothing (one slot per pair), except the warm-start steps, zero for each warm start, and
// the certificates' expiries, zero (none) for each certificate.
template <class View>
void load_view_of_format(const Hdf5Reader& in, std::int64_t format, const std::string& name,
                         View& view, int particle_count) {
  if (format >= format_that_added(name)) {
    load_view(in, name, view);
    return;
  }
  const bool per_particle = name.rfind("particles/", 0) == 0;
  view = View(name, per_particle ? particle_count : 0);
  if (per_particle)
    Kokkos::deep_copy(view, -1);
}

// For readers of the file (pictures, analyses): shapes/<field> for each output field of the
// templates (a superquadric's half_axes, blockiness), shape id k > 0 is row k - 1, NaN where
// a template has no such field. Not read back: the scene defines the templates.
void write_shape_templates(Hdf5Writer& out, const std::vector<ShapeTemplate>& templates) {
  std::vector<int> rows(templates.size());
  for (std::size_t k = 0; k < rows.size(); ++k)
    rows[k] = int(k);
  for (const ShapeField& field : output_fields_of(templates, rows))
    out.write("shapes/" + field.name, field.values,
              {hsize_t(templates.size()), hsize_t(field.components)});
}

// For readers of the file: what the particles' `source` and `tag` index. Not read back: the
// scene defines them.
void write_names(Hdf5Writer& out, const std::string& name, const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& n : names)
    joined += n + "\n";
  out.write_string(name, joined);
}

// The checkpoint's datasets, each value checked as it is read; every refusal is a
// std::runtime_error naming the file.
class CheckedInput {
public:
  explicit CheckedInput(const std::string& path) : path_(path), file_(path) {}

  void require(bool ok, const std::string& what) const {
    if (!ok)
      throw std::runtime_error(path_ + ": checkpoint does not match the scene: " + what);
  }
  const Hdf5Reader& file() const { return file_; }
  bool has(const std::string& name) const { return file_.has(name); }
  std::int64_t integer(const std::string& name) const { return file_.read_scalar_int64(name); }
  std::string text(const std::string& name) const { return file_.read_string(name); }

  // A number of rows: what a View index holds.
  int count(const std::string& name) const {
    return int(bounded(name, std::numeric_limits<int>::max(), "a count"));
  }
  // A counter the run increments (steps, insertions): far from overflowing.
  std::int64_t counter(const std::string& name) const {
    return bounded(name, largest_counter, "a counter below 2^53");
  }
  double finite(const std::string& name) const {
    const double value = file_.read_scalar_double(name);
    if (!std::isfinite(value))
      throw std::runtime_error(path_ + ": checkpoint value " + name + " is not finite");
    return value;
  }
  // A number of particles held as a real (a source's fraction owed): converted to an integer.
  double amount(const std::string& name) const {
    const double value = finite(name);
    require(value >= 0 && value <= double(largest_counter), name + " is not between 0 and 2^53");
    return value;
  }
  double positive(const std::string& name) const {
    const double value = finite(name);
    require(value > 0, name + " is not positive");
    return value;
  }

private:
  static constexpr std::int64_t largest_counter = std::int64_t(1) << 53;

  std::int64_t bounded(const std::string& name, std::int64_t most, const char* what) const {
    const std::int64_t value = file_.read_scalar_int64(name);
    if (value < 0 || value > most)
      throw std::runtime_error(path_ + ": checkpoint value " + name + " = " +
                               std::to_string(value) + " is not " + what);
    return value;
  }

  std::string path_;
  Hdf5Reader file_;
};

std::string rng_state(const std::mt19937_64& rng) {
  std::ostringstream text;
  text << rng;
  return text.str();
}

// The scalars of the run; false when the file predates the energy budget. (Templates on the
// engine's private state type, which they never name.)
template <class State> bool read_counters(State& s, const CheckedInput& in) {
  s.time = in.finite("time");
  s.step_count = in.counter("step");
  s.next_id = in.counter("next_id");
  s.largest_radius = in.finite("largest_radius");
  s.smallest_radius = in.positive("smallest_radius");
  s.last_build_time = in.finite("last_build_time");
  s.list_builds = in.counter("list_builds");
  s.needs_rebuild = in.integer("needs_rebuild") != 0;
  s.discharged_mass = in.finite("discharged_mass");
  s.discharged_count = in.counter("discharged_count");
  // Checkpoints written before the run checks existed lack these: nothing was lost, and the
  // energy budget starts from the restart's state (set after the particles are read).
  s.lost_mass = in.has("lost_mass") ? in.finite("lost_mass") : 0;
  s.lost_count = in.has("lost_count") ? in.counter("lost_count") : 0;
  // Before format 4 no certificate held an expiry (read as none), so the sum may start anew.
  s.surface_travel = in.has("surface_travel") ? in.finite("surface_travel") : 0;
  const bool has_energy_budget = in.has("energy_budget");
  if (has_energy_budget) {
    s.energy_budget = in.finite("energy_budget");
    s.initial_overlap_ratio = in.finite("initial_overlap_ratio");
  }
  return has_energy_budget;
}

void read_sources(std::vector<SourceState>& sources, const CheckedInput& in) {
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const std::string group = "sources/" + std::to_string(k) + "/";
    in.require(in.has(group + "rng"), "particle sources differ");
    std::istringstream text(in.text(group + "rng"));
    text >> sources[k].rng;
    in.require(!text.fail(), "the random state of source " + std::to_string(k) + " does not parse");
    sources[k].inserted = in.counter(group + "inserted");
    sources[k].next_insertion = in.finite(group + "next_insertion");
    sources[k].owed = in.amount(group + "owed");
  }
}

// The particle, pair and wall-contact tables (checked afterwards, as a whole).
template <class State> void read_tables(State& s, const CheckedInput& in, std::int64_t format) {
  const int particle_count = in.count("particle_count");
  // The count sizes the fields a format 1 file lacks: it must be the rows the file holds.
  const auto id_shape = in.file().shape("particles/id");
  in.require(!id_shape.empty() && id_shape[0] == hsize_t(particle_count),
             "particle_count differs from the rows of particles/id");
  for_each_particle_field([&](const char* name, auto member) {
    load_view_of_format(in.file(), format, std::string("particles/") + name, s.particles.*member,
                        particle_count);
  });
  s.particles.count = particle_count;
  load_view(in.file(), "ids_at_build", s.ids_at_build);
  for_each_pair_list_field([&](const char* name, auto member) {
    load_view_of_format(in.file(), format, std::string("pairs/") + name, s.pairs.*member, 0);
  });
  s.pairs.pair_count = in.count("pair_count");
  s.pairs.slot_count = int(s.pairs.overlap.extent(0));
  allocate_torque_on_j(s.pairs);
  if (format < format_that_added("pairs/midway_step"))
    s.pairs.midway_step = Vec3View("pair_midway_step", s.pairs.midway_point.extent(0));
  if (format < format_that_added("pairs/separation_expiry"))
    s.pairs.separation_expiry =
        ScalarView("pair_separation_expiry", s.pairs.separation_margin.extent(0));
  for_each_wall_contact_field([&](const char* name, auto member) {
    load_view_of_format(in.file(), format, std::string("wall_contacts/") + name,
                        s.wall_contacts.*member, 0);
  });
  s.wall_contacts.entry_count = in.count("wall_entry_count");
  s.wall_contacts.slot_count = int(s.wall_contacts.overlap.extent(0));
}

} // namespace

void Engine::write_checkpoint(const std::string& path) const {
  const State& s = *state_;
  Hdf5Writer out(path);
  out.write_scalar("format", checkpoint_format);
  out.write_string("scene", s.scene.source_file);
  out.write_scalar("time", s.time);
  out.write_scalar("step", std::int64_t(s.step_count));
  out.write_scalar("next_id", std::int64_t(s.next_id));
  out.write_scalar("particle_count", std::int64_t(s.particles.count));
  out.write_scalar("material_count", std::int64_t(s.scene.materials.size()));
  out.write_scalar("wall_element_count", std::int64_t(s.walls.elements.count));
  out.write_scalar("largest_radius", s.largest_radius);
  out.write_scalar("smallest_radius", s.smallest_radius);
  out.write_scalar("last_build_time", s.last_build_time);
  out.write_scalar("list_builds", std::int64_t(s.list_builds));
  out.write_scalar("needs_rebuild", std::int64_t(s.needs_rebuild));
  out.write_scalar("discharged_mass", s.discharged_mass);
  out.write_scalar("discharged_count", std::int64_t(s.discharged_count));
  out.write_scalar("lost_mass", s.lost_mass);
  out.write_scalar("lost_count", std::int64_t(s.lost_count));
  out.write_scalar("energy_budget", s.energy_budget);
  out.write_scalar("initial_overlap_ratio", s.initial_overlap_ratio);
  out.write_scalar("surface_travel", s.surface_travel);
  out.write_scalar("pair_count", std::int64_t(s.pairs.pair_count));
  out.write_scalar("wall_entry_count", std::int64_t(s.wall_contacts.entry_count));
  for (std::size_t k = 0; k < s.sources.size(); ++k) {
    const std::string group = "sources/" + std::to_string(k) + "/";
    out.write_string(group + "rng", rng_state(s.sources[k].rng));
    out.write_scalar(group + "inserted", std::int64_t(s.sources[k].inserted));
    out.write_scalar(group + "next_insertion", s.sources[k].next_insertion);
    out.write_scalar(group + "owed", s.sources[k].owed);
  }
  for_each_particle_field([&](const char* name, auto member) {
    save_view(out, std::string("particles/") + name, s.particles.*member);
  });
  write_shape_templates(out, s.shape_templates);
  write_names(out, "source_names", s.source_names());
  write_names(out, "tag_names", s.tag_names);
  save_view(out, "ids_at_build", s.ids_at_build);
  for_each_pair_list_field([&](const char* name, auto member) {
    save_view(out, std::string("pairs/") + name, s.pairs.*member);
  });
  for_each_wall_contact_field([&](const char* name, auto member) {
    save_view(out, std::string("wall_contacts/") + name, s.wall_contacts.*member);
  });
  out.close();
}

// Read into a copy of the state, which replaces the engine's only when the whole file has been
// read and checked: a refused checkpoint leaves the engine as it was.
void Engine::read_checkpoint(const std::string& path) {
  State s = *state_;
  const CheckedInput in(path);
  const std::int64_t format = in.integer("format");
  in.require(format >= 1 && format <= checkpoint_format,
             "unknown checkpoint format " + std::to_string(format));
  in.require(in.integer("material_count") == std::int64_t(s.scene.materials.size()),
             "material count differs");
  in.require(in.integer("wall_element_count") == s.walls.elements.count, "wall elements differ");
  const bool has_energy_budget = read_counters(s, in);
  read_sources(s.sources, in);
  read_tables(s, in, format);
  s.check_restored_particles(path);
  s.families_present |= present_families(s.particles, s.shape_families);
  s.check_restored_lists(path);
  // Sized by the entry count, which the checks above have matched to the file's tables.
  allocate_wall_contact_results(s.wall_contacts, s.walls.elements);
  s.classify_families(s.pairs);
  update_wall_poses(s.walls, s.time);
  if (!has_energy_budget)
    s.start_energy_budget();
  *state_ = std::move(s);
}

} // namespace kdem
