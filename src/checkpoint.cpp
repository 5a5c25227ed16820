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

// 2: particles carry their source and tag; pair and wall lists their contact slots. Format 1
// files are read too: their particles get no source or tag (-1), their lists one slot per
// pair or entry.
constexpr std::int64_t checkpoint_format = 2;

template <class View> void save_view(Hdf5Writer& out, const std::string& name, const View& view) {
  const int rows = view.data() ? int(view.extent(0)) : 0;
  const auto values =
      rows > 0 ? flatten_to_host(view, rows) : std::vector<typename View::non_const_value_type>{};
  out.write(name, values, {hsize_t(rows), hsize_t(columns_of(view))});
}

template <class View> void load_view(const Hdf5Reader& in, const std::string& name, View& view) {
  using Value = typename View::non_const_value_type;
  std::vector<Value> values;
  if constexpr (std::is_same_v<Value, double>)
    values = in.read_doubles(name);
  else if constexpr (std::is_same_v<Value, int>)
    values = in.read_ints(name);
  else
    values = in.read_int64(name);
  const auto shape = in.shape(name);
  constexpr std::size_t columns = View::rank == 1 ? 1 : View::static_extent(1);
  if (shape.size() != 2 || shape[1] != columns)
    throw std::runtime_error(in.path().string() + ": checkpoint dataset " + name +
                             " is not a table of " + std::to_string(columns) + " column(s)");
  if (shape[0] > hsize_t(std::numeric_limits<int>::max()))
    throw std::runtime_error(in.path().string() + ": checkpoint dataset " + name +
                             " has too many rows");
  view = view_from_host<View>(name, values, int(columns));
}

// The datasets format 2 added, and what a format 1 file stands for instead.
bool added_in_format_2(const std::string& name) {
  return name == "particles/source" || name == "particles/tag" || name == "pairs/contact_start" ||
         name == "pairs/feature_i" || name == "pairs/feature_j" ||
         name == "wall_contacts/contact_start" || name == "wall_contacts/feature";
}

template <class View>
void load_view_of_format(const Hdf5Reader& in, std::int64_t format, const std::string& name,
                         View& view, int particle_count) {
  if (format >= 2 || !added_in_format_2(name)) {
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

std::string rng_state(const std::mt19937_64& rng) {
  std::ostringstream text;
  text << rng;
  return text.str();
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
  Hdf5Reader in(path);
  auto require = [&](bool ok, const std::string& what) {
    if (!ok)
      throw std::runtime_error(path + ": checkpoint does not match the scene: " + what);
  };
  auto count_of = [&](const std::string& name) {
    const std::int64_t value = in.read_scalar_int64(name);
    if (value < 0 || value > std::numeric_limits<int>::max())
      throw std::runtime_error(path + ": checkpoint value " + name + " = " + std::to_string(value) +
                               " is not a count");
    return value;
  };
  auto finite_of = [&](const std::string& name) {
    const double value = in.read_scalar_double(name);
    if (!std::isfinite(value))
      throw std::runtime_error(path + ": checkpoint value " + name + " is not finite");
    return value;
  };
  const std::int64_t format = in.read_scalar_int64("format");
  require(format == 1 || format == checkpoint_format,
          "unknown checkpoint format " + std::to_string(format));
  require(in.read_scalar_int64("material_count") == std::int64_t(s.scene.materials.size()),
          "material count differs");
  require(in.read_scalar_int64("wall_element_count") == s.walls.elements.count,
          "wall elements differ");
  s.time = finite_of("time");
  s.step_count = in.read_scalar_int64("step");
  require(s.step_count >= 0, "negative step");
  s.next_id = in.read_scalar_int64("next_id");
  s.largest_radius = finite_of("largest_radius");
  s.smallest_radius = in.read_scalar_double("smallest_radius");
  s.last_build_time = finite_of("last_build_time");
  s.list_builds = in.read_scalar_int64("list_builds");
  s.needs_rebuild = in.read_scalar_int64("needs_rebuild") != 0;
  s.discharged_mass = finite_of("discharged_mass");
  s.discharged_count = in.read_scalar_int64("discharged_count");
  // Checkpoints written before the run checks existed lack these: nothing was lost, and the
  // energy budget starts from the restart's state (set after the particles are read).
  s.lost_mass = in.has("lost_mass") ? finite_of("lost_mass") : 0;
  s.lost_count = in.has("lost_count") ? in.read_scalar_int64("lost_count") : 0;
  require(s.discharged_count >= 0 && s.lost_count >= 0 && s.list_builds >= 0,
          "a negative count of discharged or lost particles or of list builds");
  require(s.smallest_radius > 0, "smallest_radius is not positive");
  const bool has_energy_budget = in.has("energy_budget");
  if (has_energy_budget) {
    s.energy_budget = finite_of("energy_budget");
    s.initial_overlap_ratio = finite_of("initial_overlap_ratio");
  }
  for (std::size_t k = 0; k < s.sources.size(); ++k) {
    const std::string group = "sources/" + std::to_string(k) + "/";
    require(in.has(group + "rng"), "particle sources differ");
    std::istringstream text(in.read_string(group + "rng"));
    text >> s.sources[k].rng;
    require(!text.fail(), "the random state of source " + std::to_string(k) + " does not parse");
    s.sources[k].inserted = in.read_scalar_int64(group + "inserted");
    require(s.sources[k].inserted >= 0, "negative insertion count of source " + std::to_string(k));
    s.sources[k].next_insertion = finite_of(group + "next_insertion");
    s.sources[k].owed = finite_of(group + "owed");
  }
  const int particle_count = int(count_of("particle_count"));
  for_each_particle_field([&](const char* name, auto member) {
    load_view_of_format(in, format, std::string("particles/") + name, s.particles.*member,
                        particle_count);
  });
  s.particles.count = particle_count;
  load_view(in, "ids_at_build", s.ids_at_build);
  for_each_pair_list_field([&](const char* name, auto member) {
    load_view_of_format(in, format, std::string("pairs/") + name, s.pairs.*member, 0);
  });
  s.pairs.pair_count = int(count_of("pair_count"));
  s.pairs.slot_count = int(s.pairs.overlap.extent(0));
  for_each_wall_contact_field([&](const char* name, auto member) {
    load_view_of_format(in, format, std::string("wall_contacts/") + name, s.wall_contacts.*member,
                        0);
  });
  s.wall_contacts.entry_count = int(count_of("wall_entry_count"));
  s.wall_contacts.slot_count = int(s.wall_contacts.overlap.extent(0));
  allocate_wall_contact_results(s.wall_contacts);
  s.check_restored_particles(path);
  s.families_present |= present_families(s.particles, s.shape_families);
  s.check_restored_lists(path);
  s.classify_families(s.pairs);
  update_wall_poses(s.walls, s.time);
  if (!has_energy_budget)
    s.start_energy_budget();
  *state_ = std::move(s);
}

} // namespace kdem
