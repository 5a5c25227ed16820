#pragma once
// The keys of a shape entry that give a closed triangle mesh, shared by the families whose shapes
// are built from one (dilated polyhedra, level sets): `mesh` (an STL or OBJ file), or
// `superquadric` or `harmonics` sampled at `nodes` Fibonacci directions (src/core_builders.hpp);
// then `scale`, `convex_hull` and `simplify_to`, in that order.
#include <cstdint>
#include <string>
#include <vector>

#include "mesh.hpp"
#include "scene_yaml.hpp"

namespace kdem {

// The keys read_mesh_source reads.
const std::vector<std::string>& mesh_source_keys();

struct MeshSource {
  TriangleMesh mesh;
  std::string description; // the file's absolute path, or "(how the mesh was built)"
};

// The mesh of a shape entry's mapping; `default_nodes` where a built mesh gives no `nodes`.
// Errors name the key and what was expected.
MeshSource read_mesh_source(const scene_yaml::Mapping& map, int default_nodes);

} // namespace kdem
