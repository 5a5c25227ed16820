// The scene keys of dilated polyhedra: a shape entry's `dilated_polyhedron` (the core from a
// closed STL or OBJ mesh, a superquadric or spherical harmonics sampled at Fibonacci directions,
// optionally its convex hull and simplified; its scale and the dilation radius) and
// `dilated_polyhedron_contact` (normal-cone slack and the averaging of contact points).
#include "dilated_polyhedron_scene.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <utility>

#include "mesh_source_scene.hpp"
#include "scene_loader.hpp"

namespace kdem {
namespace {

using namespace scene_yaml;

// The family's key in a shape entry and in SceneConfig::family_settings
// (DilatedPolyhedronFamily::name).
const char* const family_name = "dilated_polyhedron";

// Chosen from the speed-against-error study (docs/performance.md, section 27): at 1000 nodes a
// dilated lattice of a superquadric misses no probe overlapping it by 1 % of its size and errs
// by a tenth of that overlap, where the book's 200 nodes (Sect. 4.1) miss 15 to 26 % of them.
constexpr int default_node_count = 1000;

std::shared_ptr<const FamilyShapeParameters> read_dilated_polyhedron(const Value& value) {
  auto shape = std::make_shared<DilatedPolyhedronShapeParameters>();
  std::vector<std::string> keys = mesh_source_keys();
  keys.insert(keys.end(), {"dilation_radius", "mass_precision"});
  const Mapping map(value, keys);
  MeshSource core = read_mesh_source(map, default_node_count);
  shape->mesh_file = core.description;
  shape->dilation_radius = positive(map.get("dilation_radius"), "m");
  if (auto precision = map.find("mass_precision"))
    shape->mass_precision = number_where(*precision, "a relative precision in [1e-6, 1e-2]",
                                         [](double p) { return p >= 1e-6 && p <= 1e-2; });
  shape->points = std::move(core.mesh.points);
  shape->triangles = std::move(core.mesh.triangles);
  return shape;
}

std::shared_ptr<const FamilySettings> read_dilated_polyhedron_contact(const Value& value) {
  auto settings = std::make_shared<DilatedPolyhedronContactConfig>();
  const Mapping map(value,
                    {"cone_slack", "cone_fade", "merge_distance", "averaging", "averaging_angle"});
  if (auto slack = map.find("cone_slack"))
    settings->cone_slack = number_where(*slack, "an angle in radians in [0, 0.1]",
                                        [](double a) { return a >= 0 && a <= 0.1; });
  if (auto fade = map.find("cone_fade"))
    settings->cone_fade = number_where(*fade, "an angle in radians in [0, 0.2]",
                                       [](double a) { return a >= 0 && a <= 0.2; });
  if (auto merge = map.find("merge_distance"))
    settings->merge_distance = number_where(*merge, "a fraction of the dilation radius in [0, 2]",
                                            [](double m) { return m >= 0 && m <= 2; });
  if (auto averaging = map.find("averaging"))
    settings->averaging = one_of_words(*averaging, {"averaged", "summed"}) == "averaged";
  if (auto angle = map.find("averaging_angle"))
    settings->averaging_angle = number_where(*angle, "an angle in degrees in (0, 90)",
                                             [](double a) { return a > 0 && a < 90; });
  return settings;
}

} // namespace

double DilatedPolyhedronShapeParameters::smallest_size() const {
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& p : points)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  double smallest = 1e300;
  for (int k = 0; k < 3; ++k)
    smallest = std::min(smallest, 0.5 * (hi[k] - lo[k]));
  return smallest + dilation_radius;
}

FamilyScene dilated_polyhedron_scene() {
  return {family_name, "dilated_polyhedron_contact", read_dilated_polyhedron,
          read_dilated_polyhedron_contact};
}

const DilatedPolyhedronShapeParameters& dilated_polyhedron_parameters(const ShapeConfig& shape) {
  const auto* parameters =
      dynamic_cast<const DilatedPolyhedronShapeParameters*>(shape.parameters.get());
  if (parameters == nullptr)
    throw std::logic_error("shape '" + shape.name + "' carries no dilated-polyhedron parameters");
  return *parameters;
}

ShapeConfig dilated_polyhedron_shape_config(const std::string& name,
                                            std::vector<std::array<double, 3>> points,
                                            std::vector<std::array<int, 3>> triangles,
                                            double dilation_radius, double mass_precision) {
  auto parameters = std::make_shared<DilatedPolyhedronShapeParameters>();
  parameters->mesh_file = "(" + name + ", made in code)";
  parameters->points = std::move(points);
  parameters->triangles = std::move(triangles);
  parameters->dilation_radius = dilation_radius;
  parameters->mass_precision = mass_precision;
  return {name, family_name, parameters};
}

} // namespace kdem
