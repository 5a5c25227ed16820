// The host registry of scene readers: one line per shape family. It mirrors the device
// registry (kernels/families/registry.hpp) because the scene loader is built once, without
// Kokkos, for every backend; Engine setup refuses a device family missing here.
#include "clump_scene.hpp"
#include "dilated_polyhedron_scene.hpp"
#include "family_scene.hpp"
#include "level_set_scene.hpp"
#include "poly_superquadric_scene.hpp"
#include "superquadric_scene.hpp"

namespace kdem {

const std::vector<FamilyScene>& family_scenes() {
  static const std::vector<FamilyScene> scenes{superquadric_scene(), poly_superquadric_scene(),
                                               clump_scene(), dilated_polyhedron_scene(),
                                               level_set_scene()};
  return scenes;
}

} // namespace kdem
