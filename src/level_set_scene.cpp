// The scene keys of level-set bodies: a shape entry's `level_set` (the mesh from a closed STL or
// OBJ file, a superquadric or spherical harmonics, as for dilated polyhedra; the grid spacing and
// padding, the surface points' spacing) and `level_set_contact` (patches, averaging, one way or
// both ways).
#include "level_set_scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "mesh_source_scene.hpp"
#include "scene_loader.hpp"

namespace kdem {
namespace {

using namespace scene_yaml;

// The family's key in a shape entry and in SceneConfig::family_settings (LevelSetFamily::name).
const char* const family_name = "level_set";

// Chosen from the speed-against-error study (docs/performance.md, section 28): two level-set
// superquadrics overlapping by 1 % of their size. The mesh's faceting sets a floor on the overlap
// error (about 17 % of that overlap at 2000 nodes, 4 to 7 % at 8000); at 8000 nodes, a grid of 40
// cells across the smallest extent and points 2 cells apart err by a median 9 to 13 % with
// about 2000 points and 1.5 to 1.8 MiB of grid per shape; 20 cells err by 14 to 21 %.
constexpr int default_node_count = 8000;
constexpr double default_cells_across = 40;
constexpr double default_point_spacing_in_cells = 2;

std::shared_ptr<const FamilyShapeParameters> read_level_set(const Value& value) {
  auto shape = std::make_shared<LevelSetShapeParameters>();
  std::vector<std::string> keys = mesh_source_keys();
  keys.insert(keys.end(), {"grid_spacing", "padding", "point_spacing", "point_count"});
  const Mapping map(value, keys);
  MeshSource source = read_mesh_source(map, default_node_count);
  shape->mesh_file = source.description;
  shape->points = std::move(source.mesh.points);
  shape->triangles = std::move(source.mesh.triangles);
  const double size = 2 * shape->smallest_size();
  shape->grid_spacing = size / default_cells_across;
  if (auto found = map.find("grid_spacing"))
    shape->grid_spacing =
        number_where(*found, "a spacing in m between 1e-3 and 1 of the mesh's smallest extent",
                     [&](double h) { return h >= 1e-3 * size && h <= size; });
  if (auto found = map.find("padding")) {
    const std::int64_t padding = whole_number(*found, 1);
    if (padding > 100)
      found->expected("a whole number of cells in [1, 100]");
    shape->padding = int(padding);
  }
  shape->point_spacing = default_point_spacing_in_cells * shape->grid_spacing;
  if (auto found = map.find("point_spacing"))
    shape->point_spacing =
        number_where(*found, "a spacing in m between 1e-3 and 1 of the mesh's smallest extent",
                     [&](double l) { return l >= 1e-3 * size && l <= size; });
  if (auto found = map.find("point_count")) {
    if (map.find("point_spacing"))
      found->expected("either point_spacing or point_count, not both");
    const std::int64_t count = whole_number(*found, 4);
    if (count > 1000000)
      found->expected("a whole number of surface points in [4, 1000000]");
    shape->point_count = int(count);
  }
  return shape;
}

std::shared_ptr<const FamilySettings> read_level_set_contact(const Value& value) {
  auto settings = std::make_shared<LevelSetContactConfig>();
  const Mapping map(value, {"merge_distance", "averaging", "averaging_angle", "points"});
  if (auto merge = map.find("merge_distance"))
    settings->merge_distance =
        number_where(*merge, "a fraction of the smaller equivalent radius in [0, 2]",
                     [](double m) { return m >= 0 && m <= 2; });
  if (auto averaging = map.find("averaging"))
    settings->averaging = one_of_words(*averaging, {"averaged", "summed"}) == "averaged";
  if (auto angle = map.find("averaging_angle"))
    settings->averaging_angle = number_where(*angle, "an angle in degrees in (0, 90)",
                                             [](double a) { return a > 0 && a < 90; });
  if (auto points = map.find("points"))
    settings->both_ways = one_of_words(*points, {"both_ways", "one_way"}) == "both_ways";
  return settings;
}

} // namespace

double LevelSetShapeParameters::smallest_size() const {
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& p : points)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  double smallest = 1e300;
  for (int k = 0; k < 3; ++k)
    smallest = std::min(smallest, 0.5 * (hi[k] - lo[k]));
  return smallest;
}

FamilyScene level_set_scene() {
  return {family_name, "level_set_contact", read_level_set, read_level_set_contact};
}

const LevelSetShapeParameters& level_set_parameters(const ShapeConfig& shape) {
  const auto* parameters = dynamic_cast<const LevelSetShapeParameters*>(shape.parameters.get());
  if (parameters == nullptr)
    throw std::logic_error("shape '" + shape.name + "' carries no level-set parameters");
  return *parameters;
}

ShapeConfig level_set_shape_config(const std::string& name,
                                   std::vector<std::array<double, 3>> points,
                                   std::vector<std::array<int, 3>> triangles, double grid_spacing,
                                   double point_spacing, int padding) {
  auto parameters = std::make_shared<LevelSetShapeParameters>();
  parameters->mesh_file = "(" + name + ", made in code)";
  parameters->points = std::move(points);
  parameters->triangles = std::move(triangles);
  parameters->grid_spacing = grid_spacing;
  parameters->point_spacing = point_spacing;
  parameters->padding = padding;
  return {name, family_name, parameters};
}

} // namespace kdem
