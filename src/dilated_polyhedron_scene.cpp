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

#include "core_builders.hpp"
#include "mesh.hpp"
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
constexpr std::int64_t default_node_count = 1000;
constexpr std::int64_t most_nodes = 1000000;
constexpr std::int64_t highest_degree = 100;

TriangleMesh read_core_mesh(const Mapping& map, DilatedPolyhedronShapeParameters& shape) {
  if (auto nodes = map.find("nodes"))
    nodes->fail("expected nodes only with a superquadric or harmonics core, not with mesh");
  const Value mesh_value = map.get("mesh");
  shape.mesh_file = existing_mesh_file(mesh_value);
  try {
    return read_mesh(shape.mesh_file);
  } catch (const std::runtime_error& unreadable) {
    mesh_value.expected("a closed triangle mesh", unreadable.what());
  }
}

int node_count(const Mapping& map) {
  const auto found = map.find("nodes");
  if (!found)
    return int(default_node_count);
  const std::int64_t nodes = whole_number(*found, 4);
  if (nodes > most_nodes)
    found->expected("a whole number of nodes in [4, " + std::to_string(most_nodes) + "]");
  return int(nodes);
}

double blockiness_exponent(const Value& value) {
  // Below 1 the superquadric is concave with cusps on its axes, which a lattice of directions
  // cannot resolve; above 20 the family's own range ends.
  return number_where(value, "an exponent in [1, 20]", [](double n) { return n >= 1 && n <= 20; });
}

TriangleMesh read_superquadric_core(const Value& value, int nodes) {
  const Mapping map(value, {"a", "b", "c", "n1", "n2"});
  const double a = positive(map.get("a"), "m"), b = positive(map.get("b"), "m"),
               c = positive(map.get("c"), "m");
  const double n1 = blockiness_exponent(map.get("n1")), n2 = blockiness_exponent(map.get("n2"));
  try {
    return superquadric_core(a, b, c, n1, n2, nodes);
  } catch (const std::invalid_argument& refused) {
    value.expected("a superquadric the lattice can sample", refused.what());
  }
}

HarmonicCoefficient read_coefficient(const Value& item) {
  if (!item.is_sequence() || item.node().size() != 4)
    item.expected("a coefficient [n, m, re, im]: degree n, order 0 <= m <= n, and the real and "
                  "imaginary parts of A_nm in m");
  HarmonicCoefficient coefficient;
  const std::int64_t degree = whole_number(item.item(0), 0);
  if (degree > highest_degree)
    item.item(0).expected("a degree n in [0, " + std::to_string(highest_degree) + "]");
  const std::int64_t order = whole_number(item.item(1), 0);
  if (order > degree)
    item.item(1).expected("an order m in [0, n] (n = " + std::to_string(degree) + ")");
  coefficient.n = int(degree);
  coefficient.m = int(order);
  coefficient.real = finite_number(item.item(2), "a number in m (the real part of A_nm)");
  coefficient.imag = finite_number(item.item(3), "a number in m (the imaginary part of A_nm)");
  return coefficient;
}

std::vector<HarmonicCoefficient> read_coefficients(const Value& list) {
  std::vector<HarmonicCoefficient> coefficients;
  std::map<std::pair<int, int>, std::string> first_given;
  for_each_item(list, "a list of coefficients [n, m, re, im]", false, [&](const Value& item) {
    const HarmonicCoefficient coefficient = read_coefficient(item);
    const auto [earlier, inserted] =
        first_given.emplace(std::make_pair(coefficient.n, coefficient.m), item.path());
    if (!inserted)
      item.expected("each (n, m) once", "already given at " + earlier->second);
    coefficients.push_back(coefficient);
  });
  return coefficients;
}

TriangleMesh read_harmonic_core(const Value& value, int nodes) {
  const Mapping map(value, {"coefficients"});
  const Value list = map.get("coefficients");
  const std::vector<HarmonicCoefficient> coefficients = read_coefficients(list);
  try {
    return harmonic_core(coefficients, nodes);
  } catch (const std::invalid_argument& refused) {
    list.expected("coefficients whose radius is positive at every node", refused.what());
  }
}

TriangleMesh read_built_core(const Mapping& map, const std::string& source,
                             DilatedPolyhedronShapeParameters& shape) {
  const int nodes = node_count(map);
  shape.mesh_file = "(" + source + " core of " + std::to_string(nodes) + " nodes)";
  if (source == "superquadric")
    return read_superquadric_core(map.get(source), nodes);
  return read_harmonic_core(map.get(source), nodes);
}

TriangleMesh scaled(TriangleMesh mesh, double scale) {
  for (auto& p : mesh.points)
    p = {scale * p[0], scale * p[1], scale * p[2]};
  return mesh;
}

TriangleMesh convex_hull_if_asked(const Mapping& map, TriangleMesh core) {
  const auto found = map.find("convex_hull");
  if (!found || !boolean(*found))
    return core;
  try {
    return convex_hull_core(core.points);
  } catch (const std::invalid_argument& refused) {
    found->expected("true only for a core whose points span a volume", refused.what());
  }
}

TriangleMesh simplified_if_asked(const Mapping& map, TriangleMesh core) {
  const auto found = map.find("simplify_to");
  if (!found)
    return core;
  const std::string expectation =
      "a whole number of faces >= 4 and below the core's " + std::to_string(core.triangles.size());
  const std::int64_t target = whole_number(*found, 4);
  if (target >= std::int64_t(core.triangles.size()))
    found->expected(expectation);
  try {
    return simplify_core(core, int(target));
  } catch (const std::invalid_argument& refused) {
    found->expected(expectation, refused.what());
  }
}

std::shared_ptr<const FamilyShapeParameters> read_dilated_polyhedron(const Value& value) {
  auto shape = std::make_shared<DilatedPolyhedronShapeParameters>();
  const Mapping map(value, {"mesh", "superquadric", "harmonics", "nodes", "convex_hull",
                            "simplify_to", "scale", "dilation_radius", "mass_precision"});
  const std::string source = exactly_one_key(map, {"mesh", "superquadric", "harmonics"});
  TriangleMesh core =
      source == "mesh" ? read_core_mesh(map, *shape) : read_built_core(map, source, *shape);
  if (auto found = map.find("scale"))
    core = scaled(std::move(core),
                  number_where(*found, "a positive factor on the core's coordinates", is_positive));
  core = simplified_if_asked(map, convex_hull_if_asked(map, std::move(core)));
  shape->dilation_radius = positive(map.get("dilation_radius"), "m");
  if (auto precision = map.find("mass_precision"))
    shape->mass_precision = number_where(*precision, "a relative precision in [1e-6, 1e-2]",
                                         [](double p) { return p >= 1e-6 && p <= 1e-2; });
  shape->points = std::move(core.points);
  shape->triangles = std::move(core.triangles);
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
