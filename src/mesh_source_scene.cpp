// The keys of a shape entry that give a closed triangle mesh (mesh_source_scene.hpp).
#include "mesh_source_scene.hpp"

#include <map>
#include <stdexcept>
#include <utility>

#include "core_builders.hpp"
#include "scene_loader.hpp"

namespace kdem {
namespace {

using namespace scene_yaml;

constexpr std::int64_t most_nodes = 1000000;
constexpr std::int64_t highest_degree = 100;

TriangleMesh read_file_mesh(const Mapping& map, std::string& description) {
  if (auto nodes = map.find("nodes"))
    nodes->fail("expected nodes only with a superquadric or harmonics core, not with mesh");
  const Value mesh_value = map.get("mesh");
  description = existing_mesh_file(mesh_value);
  try {
    return read_mesh(description);
  } catch (const std::runtime_error& unreadable) {
    mesh_value.expected("a closed triangle mesh", unreadable.what());
  }
}

int node_count(const Mapping& map, int default_nodes) {
  const auto found = map.find("nodes");
  if (!found)
    return default_nodes;
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

TriangleMesh read_built_mesh(const Mapping& map, const std::string& source, int default_nodes,
                             std::string& description) {
  const int nodes = node_count(map, default_nodes);
  description = "(" + source + " mesh of " + std::to_string(nodes) + " nodes)";
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

} // namespace

const std::vector<std::string>& mesh_source_keys() {
  static const std::vector<std::string> keys = {"mesh",  "superquadric", "harmonics",  "nodes",
                                                "scale", "convex_hull",  "simplify_to"};
  return keys;
}

MeshSource read_mesh_source(const Mapping& map, int default_nodes) {
  MeshSource made;
  const std::string source = exactly_one_key(map, {"mesh", "superquadric", "harmonics"});
  TriangleMesh mesh = source == "mesh"
                          ? read_file_mesh(map, made.description)
                          : read_built_mesh(map, source, default_nodes, made.description);
  if (auto found = map.find("scale"))
    mesh = scaled(std::move(mesh),
                  number_where(*found, "a positive factor on the mesh's coordinates", is_positive));
  made.mesh = simplified_if_asked(map, convex_hull_if_asked(map, std::move(mesh)));
  return made;
}

} // namespace kdem
