#include "scene_loader.hpp"

#include "family_scene.hpp"
#include "mesh.hpp"
#include "scene_yaml.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

namespace kdem {

SceneError::SceneError(const std::string& message, int line, int column, std::string key_path)
    : std::runtime_error(message), line_(line), column_(column), key_path_(std::move(key_path)) {}

SceneError::SceneError(const std::string& message) : std::runtime_error(message) {}

using namespace scene_yaml;

namespace {

// ---- materials --------------------------------------------------------------------------------

KeyList material_names(const std::vector<MaterialConfig>& materials) {
  KeyList names;
  for (const auto& material : materials)
    names.push_back(material.name);
  return names;
}

const MaterialConfig& material_named(const Value& value,
                                     const std::vector<MaterialConfig>& materials) {
  const std::string expectation =
      "the name of a material defined under materials (" + join(material_names(materials)) + ")";
  const std::string name = text(value, expectation);
  for (const auto& material : materials)
    if (material.name == name)
      return material;
  value.expected(expectation);
}

MaterialConfig read_material(const Value& value, UniqueNames& names) {
  const Mapping map(value, {"name", "density", "youngs_modulus", "poisson_ratio", "restitution",
                            "friction", "rolling_friction"});
  MaterialConfig material;
  material.name = unique_name(map.get("name"), names);
  material.density = positive(map.get("density"), "kg/m^3");
  material.youngs_modulus = positive(map.get("youngs_modulus"), "Pa");
  material.poisson_ratio = poisson_ratio(map.get("poisson_ratio"));
  if (auto value_found = map.find("restitution"))
    material.restitution = restitution(*value_found);
  if (auto value_found = map.find("friction"))
    material.friction = friction(*value_found);
  if (auto value_found = map.find("rolling_friction"))
    material.rolling_friction = friction(*value_found);
  return material;
}

std::vector<MaterialConfig> read_materials(const Value& list) {
  std::vector<MaterialConfig> materials;
  UniqueNames names("materials");
  for_each_item(list, "a non-empty sequence of materials", false,
                [&](const Value& item) { materials.push_back(read_material(item, names)); });
  return materials;
}

InteractionConfig read_interaction(const Value& value, const std::vector<MaterialConfig>& materials,
                                   UniqueNames& pairs) {
  const Mapping map(value, {"materials", "restitution", "friction", "rolling_friction"});
  const Value pair = map.get("materials");
  if (!pair.is_sequence() || pair.node().size() != 2)
    pair.expected("a sequence of 2 material names [a, b]");
  const MaterialConfig& a = material_named(pair.item(0), materials);
  const MaterialConfig& b = material_named(pair.item(1), materials);
  pairs.add(pair, std::min(a.name, b.name) + " + " + std::max(a.name, b.name));

  InteractionConfig interaction{a.name, b.name, 0.5 * (a.restitution + b.restitution),
                                0.5 * (a.friction + b.friction),
                                0.5 * (a.rolling_friction + b.rolling_friction)};
  if (auto value_found = map.find("restitution"))
    interaction.restitution = restitution(*value_found);
  if (auto value_found = map.find("friction"))
    interaction.friction = friction(*value_found);
  if (auto value_found = map.find("rolling_friction"))
    interaction.rolling_friction = friction(*value_found);
  return interaction;
}

std::vector<InteractionConfig> read_interactions(const Value& list,
                                                 const std::vector<MaterialConfig>& materials) {
  std::vector<InteractionConfig> interactions;
  UniqueNames pairs("interactions");
  for_each_item(list, "a sequence of material-pair interactions", true, [&](const Value& item) {
    interactions.push_back(read_interaction(item, materials, pairs));
  });
  return interactions;
}

// ---- boxes, regions, particle sources ---------------------------------------------------------

// Reads `min` and `max` of a box; max must exceed min in every coordinate.
void read_box_corners(const Mapping& map, Vec3d& min, Vec3d& max) {
  min = vector3(map.get("min"), "in metres");
  const Value max_value = map.get("max");
  max = vector3(max_value, "in metres");
  for (std::size_t axis = 0; axis < 3; ++axis)
    if (max[axis] <= min[axis])
      max_value.expected("a corner greater than min = " + format_vector(min) +
                         " in x, y and z (in metres)");
}

RegionConfig read_region(const Value& value) {
  const Mapping map(value, {"box", "cylinder"});
  RegionConfig region;
  if (exactly_one_key(map, {"box", "cylinder"}) == "box") {
    region.kind = RegionConfig::Kind::Box;
    read_box_corners(Mapping(map.get("box"), {"min", "max"}), region.min, region.max);
    return region;
  }
  const Mapping cylinder(map.get("cylinder"), {"base_center", "radius", "height"});
  region.kind = RegionConfig::Kind::Cylinder;
  region.base_center = vector3(cylinder.get("base_center"), "in metres");
  region.radius = positive(cylinder.get("radius"), "metres");
  region.height = positive(cylinder.get("height"), "metres");
  return region;
}

void region_bounds(const RegionConfig& region, Vec3d& low, Vec3d& high) {
  if (region.kind == RegionConfig::Kind::Box) {
    low = region.min;
    high = region.max;
    return;
  }
  const Vec3d& base = region.base_center;
  low = {base[0] - region.radius, base[1] - region.radius, base[2]};
  high = {base[0] + region.radius, base[1] + region.radius, base[2] + region.height};
}

void check_region_in_domain(const Value& where, const RegionConfig& region,
                            const SceneConfig& scene) {
  if (!scene.has_domain)
    return;
  Vec3d low{}, high{};
  region_bounds(region, low, high);
  for (std::size_t axis = 0; axis < 3; ++axis)
    if (low[axis] < scene.domain_min[axis] || high[axis] > scene.domain_max[axis])
      where.fail("expected a region inside the domain " + format_vector(scene.domain_min) + " .. " +
                 format_vector(scene.domain_max) + ", got one reaching " + format_vector(low) +
                 " .. " + format_vector(high));
}

using SizeKind = SizeDistributionConfig::Kind;

SizeKind size_kind(const std::string& word) {
  if (word == "uniform")
    return SizeKind::Uniform;
  if (word == "gaussian")
    return SizeKind::Gaussian;
  if (word == "discrete")
    return SizeKind::Discrete;
  return SizeKind::Monodisperse;
}

KeyList size_keys(SizeKind kind) {
  switch (kind) {
  case SizeKind::Uniform:
    return {"distribution", "min_radius", "max_radius"};
  case SizeKind::Gaussian:
    return {"distribution", "mean_radius", "std_radius", "min_radius", "max_radius"};
  case SizeKind::Discrete:
    return {"distribution", "radii", "mass_fractions"};
  case SizeKind::Monodisperse:
    break;
  }
  return {"distribution", "radius"};
}

void read_radius_bounds(const Mapping& map, SizeDistributionConfig& sizes) {
  sizes.min_radius = positive(map.get("min_radius"), "metres");
  const Value max_value = map.get("max_radius");
  sizes.max_radius = positive(max_value, "metres");
  if (sizes.max_radius < sizes.min_radius)
    max_value.expected("a radius >= min_radius (" + format_number(sizes.min_radius) + " m)");
}

void read_gaussian(const Mapping& map, SizeDistributionConfig& sizes) {
  const Value mean_value = map.get("mean_radius");
  sizes.mean_radius = positive(mean_value, "metres");
  sizes.std_radius = positive(map.get("std_radius"), "metres");
  read_radius_bounds(map, sizes);
  if (sizes.mean_radius < sizes.min_radius || sizes.mean_radius > sizes.max_radius)
    mean_value.expected("a radius between min_radius (" + format_number(sizes.min_radius) +
                        " m) and max_radius (" + format_number(sizes.max_radius) + " m)");
}

void read_discrete(const Mapping& map, SizeDistributionConfig& sizes) {
  sizes.radii = number_list(map.get("radii"), "a non-empty sequence of radii in metres",
                            "a positive number in metres", is_positive);
  const Value fractions_value = map.get("mass_fractions");
  sizes.mass_fractions =
      number_list(fractions_value, "a sequence of mass fractions, one per radius",
                  "a mass fraction in [0, 1]", [](double f) { return f >= 0 && f <= 1; });
  if (sizes.mass_fractions.size() != sizes.radii.size())
    fractions_value.expected("a sequence of " + std::to_string(sizes.radii.size()) +
                             " mass fractions, one per radius");
  double sum = 0;
  for (double fraction : sizes.mass_fractions)
    sum += fraction;
  constexpr double fraction_sum_tolerance = 1e-6;
  if (std::fabs(sum - 1) > fraction_sum_tolerance)
    fractions_value.expected("mass fractions summing to 1 (within 1e-6)",
                             "they sum to " + format_number(sum));
}

SizeDistributionConfig read_sizes(const Value& value) {
  const KeyList distributions{"monodisperse", "uniform", "gaussian", "discrete"};
  const Mapping all_keys(value, {"distribution", "radius", "min_radius", "max_radius",
                                 "mean_radius", "std_radius", "radii", "mass_fractions"});
  SizeDistributionConfig sizes;
  std::string distribution = "monodisperse";
  if (auto value_found = all_keys.find("distribution"))
    distribution = one_of_words(*value_found, distributions);
  sizes.kind = size_kind(distribution);
  const Mapping map(value, size_keys(sizes.kind), "(for distribution " + distribution + ")");
  switch (sizes.kind) {
  case SizeKind::Monodisperse:
    sizes.radius = positive(map.get("radius"), "metres");
    break;
  case SizeKind::Uniform:
    read_radius_bounds(map, sizes);
    break;
  case SizeKind::Gaussian:
    read_gaussian(map, sizes);
    break;
  case SizeKind::Discrete:
    read_discrete(map, sizes);
    break;
  }
  return sizes;
}

double smallest_radius(const SizeDistributionConfig& sizes) {
  switch (sizes.kind) {
  case SizeKind::Monodisperse:
    return sizes.radius;
  case SizeKind::Discrete:
    return *std::min_element(sizes.radii.begin(), sizes.radii.end());
  case SizeKind::Uniform:
  case SizeKind::Gaussian:
    break;
  }
  return sizes.min_radius;
}

// The densest packing of equal spheres; no generator can fill a region beyond it.
constexpr double densest_sphere_packing = 0.7405;

void read_amount(const Mapping& map, ParticleSourceConfig& source) {
  if (exactly_one_key(map, {"count", "volume_fraction"}) == "count") {
    source.count = whole_number(map.get("count"), 1);
    return;
  }
  source.volume_fraction =
      number_where(map.get("volume_fraction"), "a solid volume fraction in (0, 0.74]",
                   [](double f) { return f > 0 && f <= densest_sphere_packing; });
}

// Insertion over time stops once `count` particles are in, so it needs a count.
void read_insertion_timing(const Mapping& map, ParticleSourceConfig& source) {
  if (auto value_found = map.find("rate")) {
    source.rate = non_negative(*value_found, "particles per second");
    if (source.rate > 0 && source.count == 0)
      value_found->expected("0 for a source with a volume_fraction",
                            "insertion over time needs a count");
  }
  if (auto value_found = map.find("start"))
    source.start = non_negative(*value_found, "seconds");
  if (auto value_found = map.find("interval"))
    source.interval = positive(*value_found, "seconds");
}

// ---- shapes: an entry names its family by a key that its family's reader reads ----------------

KeyList shape_family_names() {
  KeyList names;
  for (const FamilyScene& family : family_scenes())
    names.push_back(family.name);
  return names;
}

const FamilyScene& family_named(const std::string& name) {
  for (const FamilyScene& family : family_scenes())
    if (family.name == name)
      return family;
  throw std::logic_error("no scene reader for the shape family " + name);
}

ShapeConfig read_shape(const Value& value, UniqueNames& names) {
  KeyList keys = shape_family_names();
  keys.insert(keys.begin(), "name");
  const Mapping map(value, keys);
  ShapeConfig shape;
  shape.name = unique_name(map.get("name"), names);
  shape.family = exactly_one_key(map, shape_family_names());
  shape.parameters = family_named(shape.family).read_shape(map.get(shape.family));
  return shape;
}

std::vector<ShapeConfig> read_shapes(const Value& list) {
  std::vector<ShapeConfig> shapes;
  UniqueNames names("shapes");
  for_each_item(list, "a sequence of shapes", true,
                [&](const Value& item) { shapes.push_back(read_shape(item, names)); });
  return shapes;
}

KeyList shape_names(const std::vector<ShapeConfig>& shapes) {
  KeyList names;
  for (const auto& shape : shapes)
    names.push_back(shape.name);
  return names;
}

// The shape a source names; refuses unknown names with the list of defined ones.
const ShapeConfig& shape_named(const Value& value, const std::vector<ShapeConfig>& shapes) {
  const std::string expectation =
      shapes.empty()
          ? "the name of a shape defined under shapes (none is defined)"
          : "the name of a shape defined under shapes (" + join(shape_names(shapes)) + ")";
  const std::string name = text(value, expectation);
  for (const auto& shape : shapes)
    if (shape.name == name)
      return shape;
  value.expected(expectation);
}

// A shaped source places one template; its `sizes` say the template's smallest size (for the
// default skin) while the engine sizes the bounding spheres.
SizeDistributionConfig sizes_of_shape(const ShapeConfig& shape) {
  SizeDistributionConfig sizes;
  sizes.kind = SizeDistributionConfig::Kind::Monodisperse;
  sizes.radius = shape.parameters->smallest_size();
  return sizes;
}

void read_family_settings(const Mapping& map, SceneConfig& scene) {
  for (const FamilyScene& family : family_scenes())
    if (!family.settings_key.empty())
      if (auto value_found = map.find(family.settings_key))
        scene.family_settings[family.name] = family.read_settings(*value_found);
}

// A fixed `orientation` and random orientations exclude each other; a fixed one is normalised.
void read_orientation(const Mapping& map, ParticleSourceConfig& source) {
  const auto random = map.find("random_orientation");
  if (random)
    source.random_orientation = boolean(*random);
  const auto fixed = map.find("orientation");
  if (!fixed)
    return;
  if (random && source.random_orientation)
    fixed->expected("no orientation, or random_orientation: false", "random_orientation is true");
  const std::string expectation = "a quaternion [w, x, y, z] of non-zero length";
  const std::vector<double> q =
      number_list(*fixed, expectation, "a number", [](double x) { return std::isfinite(x); });
  const double length =
      q.size() == 4 ? std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) : 0;
  if (!(length > 0))
    fixed->expected(expectation);
  for (int k = 0; k < 4; ++k)
    source.orientation[k] = q[k] / length;
  source.random_orientation = false;
}

ParticleSourceConfig read_source(const Value& value, const SceneConfig& scene, UniqueNames& names) {
  const Mapping map(value, {"name", "material", "size", "shape", "region", "count",
                            "volume_fraction", "random_orientation", "orientation", "velocity",
                            "angular_velocity", "seed", "rate", "start", "interval", "tag"});
  ParticleSourceConfig source;
  source.name = unique_name(map.get("name"), names);
  if (auto value_found = map.find("tag"))
    source.tag = text(*value_found, "a tag (a word or phrase)");
  source.material = material_named(map.get("material"), scene.materials).name;
  if (exactly_one_key(map, {"size", "shape"}) == "size") {
    source.sizes = read_sizes(map.get("size"));
  } else {
    const ShapeConfig& shape = shape_named(map.get("shape"), scene.shapes);
    source.shape = shape.name;
    source.sizes = sizes_of_shape(shape);
  }
  const Value region_value = map.get("region");
  source.region = read_region(region_value);
  check_region_in_domain(region_value, source.region, scene);
  read_amount(map, source);
  read_orientation(map, source);
  if (auto value_found = map.find("angular_velocity"))
    source.angular_velocity = vector3(*value_found, "in rad/s");
  if (auto value_found = map.find("velocity"))
    source.velocity = vector3(*value_found, "in m/s");
  if (auto value_found = map.find("seed"))
    source.seed = static_cast<std::uint64_t>(whole_number(*value_found, 0));
  read_insertion_timing(map, source);
  return source;
}

// ---- walls ------------------------------------------------------------------------------------

const KeyList box_faces{"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};

void read_plane(const Value& value, WallConfig& wall) {
  const Mapping map(value, {"point", "normal"});
  wall.point = vector3(map.get("point"), "in metres");
  wall.normal = unit_direction(map.get("normal"));
}

void read_open_faces(const Value& list, WallConfig& wall) {
  UniqueNames faces("open_faces");
  for_each_item(list, "a sequence of face names (" + join(box_faces) + ")", true,
                [&](const Value& item) {
                  wall.open_faces.push_back(one_of_words(item, box_faces));
                  faces.add(item, wall.open_faces.back());
                });
}

void read_wall_box(const Value& value, WallConfig& wall) {
  const Mapping map(value, {"min", "max", "open_faces"});
  read_box_corners(map, wall.min, wall.max);
  if (auto value_found = map.find("open_faces"))
    read_open_faces(*value_found, wall);
}

void read_wall_cylinder(const Value& value, WallConfig& wall) {
  const Mapping map(value, {"base_center", "axis", "radius", "length"});
  wall.base_center = vector3(map.get("base_center"), "in metres");
  if (auto value_found = map.find("axis"))
    wall.axis_direction = unit_direction(*value_found);
  wall.radius = positive(map.get("radius"), "metres");
  wall.length = positive(map.get("length"), "metres");
}

} // namespace

std::string existing_mesh_file(const Value& value) {
  const std::string expectation =
      "the path of an existing STL or OBJ file (relative to the scene file's folder)";
  const fs::path written(text(value, expectation));
  const fs::path relative_to_scene =
      written.is_absolute() ? written : value.source().base_dir / written;
  const fs::path resolved = fs::absolute(relative_to_scene).lexically_normal();
  std::error_code error;
  if (!fs::is_regular_file(resolved, error))
    value.expected(expectation, "no file at " + resolved.string());
  if (!is_mesh_file_name(resolved.string()))
    value.expected(expectation, "the name ends in neither .stl nor .obj");
  return resolved.string();
}

namespace {

void read_mesh(const Value& value, WallConfig& wall) {
  const Mapping map(value, {"file", "scale", "translate"});
  wall.file = existing_mesh_file(map.get("file"));
  if (auto value_found = map.find("scale"))
    wall.scale = number_where(*value_found, "a positive scale factor", is_positive);
  if (auto value_found = map.find("translate"))
    wall.translate = vector3(*value_found, "in metres");
}

MotionConfig read_motion(const Value& value) {
  const Mapping map(value, {"velocity", "axis_point", "axis", "rpm", "start"});
  MotionConfig motion;
  if (auto value_found = map.find("velocity"))
    motion.velocity = vector3(*value_found, "in m/s");
  if (auto value_found = map.find("axis_point"))
    motion.axis_point = vector3(*value_found, "in metres");
  if (auto value_found = map.find("axis"))
    motion.axis_direction = unit_direction(*value_found);
  if (auto value_found = map.find("rpm"))
    motion.rpm = finite_number(*value_found, "a number in revolutions per minute");
  if (auto value_found = map.find("start"))
    motion.start = non_negative(*value_found, "seconds");
  return motion;
}

void read_activity(const Mapping& map, WallConfig& wall) {
  if (auto value_found = map.find("active_from"))
    wall.active_from = non_negative(*value_found, "seconds");
  if (auto value_found = map.find("active_until")) {
    const double from = wall.active_from;
    wall.active_until =
        number_where(*value_found, "a time after active_from (" + format_number(from) + " s)",
                     [from](double until) { return until > from; });
  }
}

WallConfig read_wall(const Value& value, const SceneConfig& scene, UniqueNames& names) {
  const KeyList shapes{"plane", "box", "cylinder", "mesh"};
  const Mapping map(value, {"name", "material", "plane", "box", "cylinder", "mesh", "motion",
                            "active_from", "active_until"});
  WallConfig wall;
  wall.name = unique_name(map.get("name"), names);
  wall.material = material_named(map.get("material"), scene.materials).name;
  const std::string shape = exactly_one_key(map, shapes);
  if (shape == "plane") {
    wall.kind = WallConfig::Kind::Plane;
    read_plane(map.get(shape), wall);
  } else if (shape == "box") {
    wall.kind = WallConfig::Kind::Box;
    read_wall_box(map.get(shape), wall);
  } else if (shape == "cylinder") {
    wall.kind = WallConfig::Kind::Cylinder;
    read_wall_cylinder(map.get(shape), wall);
  } else {
    wall.kind = WallConfig::Kind::Mesh;
    read_mesh(map.get(shape), wall);
  }
  if (auto value_found = map.find("motion"))
    wall.motion = read_motion(*value_found);
  read_activity(map, wall);
  return wall;
}

// ---- outlets, output, domain, scene -----------------------------------------------------------

OutletConfig read_outlet(const Value& value, UniqueNames& names) {
  const Mapping map(value, {"name", "box"});
  OutletConfig outlet;
  outlet.name = unique_name(map.get("name"), names);
  read_box_corners(Mapping(map.get("box"), {"min", "max"}), outlet.min, outlet.max);
  return outlet;
}

OutputConfig read_output(const Value& value) {
  const Mapping map(value, {"directory", "frame_interval", "series_interval", "checkpoint_interval",
                            "final_checkpoint", "contact_forces"});
  OutputConfig output;
  if (auto value_found = map.find("directory"))
    output.directory = text(*value_found, "a folder path");
  if (auto value_found = map.find("frame_interval"))
    output.frame_interval = non_negative(*value_found, "seconds");
  if (auto value_found = map.find("series_interval"))
    output.series_interval = non_negative(*value_found, "seconds");
  if (auto value_found = map.find("checkpoint_interval"))
    output.checkpoint_interval = non_negative(*value_found, "seconds");
  if (auto value_found = map.find("final_checkpoint"))
    output.final_checkpoint = boolean(*value_found);
  if (auto value_found = map.find("contact_forces"))
    output.contact_forces = boolean(*value_found);
  return output;
}

ChecksConfig read_checks(const Value& value) {
  const Mapping map(value, {"interval", "max_overlap_ratio", "max_energy_gain", "leaving_domain"});
  ChecksConfig checks;
  if (auto value_found = map.find("interval"))
    checks.interval = int(std::min<std::int64_t>(whole_number(*value_found, 1), 1'000'000'000));
  if (auto value_found = map.find("max_overlap_ratio"))
    checks.max_overlap_ratio = positive(*value_found, "particle radii");
  if (auto value_found = map.find("max_energy_gain"))
    checks.max_energy_gain = positive(*value_found, "units of the bound");
  if (auto value_found = map.find("leaving_domain"))
    checks.leaving_domain = one_of_words(*value_found, {"remove", "stop"}) == "stop"
                                ? ChecksConfig::Leaving::Stop
                                : ChecksConfig::Leaving::Remove;
  return checks;
}

void read_domain(const Value& value, SceneConfig& scene) {
  read_box_corners(Mapping(value, {"min", "max"}), scene.domain_min, scene.domain_max);
  scene.has_domain = true;
}

void read_bodies(const Mapping& map, SceneConfig& scene) {
  UniqueNames source_names("particles");
  for_each_item(
      map.get("particles"), "a non-empty sequence of particle sources", false,
      [&](const Value& item) { scene.sources.push_back(read_source(item, scene, source_names)); });
  UniqueNames wall_names("walls");
  if (auto value_found = map.find("walls"))
    for_each_item(*value_found, "a sequence of walls", true, [&](const Value& item) {
      scene.walls.push_back(read_wall(item, scene, wall_names));
    });
  UniqueNames outlet_names("outlets");
  if (auto value_found = map.find("outlets"))
    for_each_item(*value_found, "a sequence of outlets", true, [&](const Value& item) {
      scene.outlets.push_back(read_outlet(item, outlet_names));
    });
}

// Default Verlet skin: default_skin_per_radius x the smallest particle radius of the scene.
double default_skin(const SceneConfig& scene) {
  double smallest = smallest_radius(scene.sources.front().sizes);
  for (const auto& source : scene.sources)
    smallest = std::min(smallest, smallest_radius(source.sizes));
  return default_skin_per_radius * smallest;
}

// The schema's keys, and each family's settings key after `shapes`.
KeyList scene_keys() {
  KeyList keys{"time_step", "duration",  "gravity",      "skin",   "sort_by_cell",
               "domain",    "materials", "interactions", "shapes", "particles",
               "walls",     "outlets",   "output",       "checks"};
  auto after_shapes = keys.begin() + 9;
  for (const FamilyScene& family : family_scenes())
    if (!family.settings_key.empty())
      after_shapes = keys.insert(after_shapes, family.settings_key) + 1;
  return keys;
}

SceneConfig read_scene(const Value& root) {
  const Mapping map(root, scene_keys());
  SceneConfig scene;
  scene.source_file = root.source().display_name;
  scene.time_step = positive(map.get("time_step"), "seconds");
  scene.duration = positive(map.get("duration"), "seconds");
  if (auto value_found = map.find("gravity"))
    scene.gravity = vector3(*value_found, "in m/s^2");
  if (auto value_found = map.find("domain"))
    read_domain(*value_found, scene);
  scene.materials = read_materials(map.get("materials"));
  if (auto value_found = map.find("interactions"))
    scene.interactions = read_interactions(*value_found, scene.materials);
  if (auto value_found = map.find("shapes"))
    scene.shapes = read_shapes(*value_found);
  read_family_settings(map, scene);
  read_bodies(map, scene);
  if (auto value_found = map.find("output"))
    scene.output = read_output(*value_found);
  if (auto value_found = map.find("checks"))
    scene.checks = read_checks(*value_found);
  const auto skin_value = map.find("skin");
  scene.skin = skin_value ? positive(*skin_value, "metres") : default_skin(scene);
  if (auto value_found = map.find("sort_by_cell"))
    scene.sort_by_cell = boolean(*value_found);
  return scene;
}

// Sees one YAML document's events: where its first node starts and whether it holds any node
// other than a null.
class DocumentProbe : public YAML::EventHandler {
public:
  bool has_content = false;
  YAML::Mark content_mark;

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { note(mark); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                const std::string&) override {
    note(mark);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    note(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {
    note(mark);
  }
  void OnMapEnd() override {}

private:
  void note(const YAML::Mark& mark) {
    if (!has_content)
      content_mark = mark;
    has_content = true;
  }
};

// Whether the text holds a document, how many further documents hold more than nulls, and where
// the first of those starts. yaml-cpp 0.7 (Debian 12) loops for ever in YAML::LoadAll on some
// malformed input, its parser reporting null documents without end after an error (found by
// fuzzing; fixed upstream in yaml-cpp 0.9), so documents are read one at a time, at most
// `documents_read`.
struct DocumentCount {
  bool has_first = false;
  int further = 0;
  YAML::Mark first_further;
};
DocumentCount count_documents(const std::string& yaml_text) {
  constexpr int documents_read = 64;
  std::istringstream stream(yaml_text);
  YAML::Parser parser(stream);
  DocumentCount count;
  for (int document = 0; document < documents_read; ++document) {
    DocumentProbe probe;
    if (!parser.HandleNextDocument(probe))
      break;
    if (document == 0)
      count.has_first = true;
    else if (probe.has_content && count.further++ == 0)
      count.first_further = probe.content_mark;
  }
  return count;
}

YAML::Node parse_single_document(const std::string& yaml_text, const SceneSource& source) {
  YAML::Node root;
  DocumentCount documents;
  try {
    documents = count_documents(yaml_text);
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& error) {
    throw_at(source, error.mark, "", "YAML syntax error: " + error.msg);
  }
  if (!documents.has_first)
    throw_at(source, YAML::Mark(), "",
             "expected a mapping with keys " + join(scene_keys()) + ", got an empty file");
  if (documents.further > 0)
    throw_at(source, documents.first_further, "",
             "expected a single YAML document, got " + std::to_string(1 + documents.further));
  return root;
}

std::string read_scene_file(const std::string& path) {
  const std::string prefix = path + ": cannot read the scene file (";
  std::error_code error;
  if (!fs::exists(path, error))
    throw SceneError(prefix + "no such file)");
  if (fs::is_directory(path, error))
    throw SceneError(prefix + "it is a folder)");
  std::ifstream file(path, std::ios::binary);
  if (!file)
    throw SceneError(prefix + std::strerror(errno) + ")");
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad())
    throw SceneError(prefix + "read failed)");
  return contents.str();
}

} // namespace

SceneConfig load_scene_from_string(const std::string& yaml_text, const std::string& display_name,
                                   const std::string& base_dir) {
  const SceneSource source{display_name, fs::path(base_dir.empty() ? "." : base_dir)};
  const YAML::Node root = parse_single_document(yaml_text, source);
  try {
    return read_scene(Value(root, "", root.Mark(), source));
  } catch (const YAML::Exception& error) { // not expected: every access above is checked
    throw_at(source, error.mark.is_null() ? YAML::Mark() : error.mark, "", error.msg);
  }
}

SceneConfig load_scene(const std::string& path) {
  const std::string yaml_text = read_scene_file(path);
  return load_scene_from_string(yaml_text, path, fs::path(path).parent_path().string());
}

} // namespace kdem
