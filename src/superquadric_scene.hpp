#pragma once
// The superquadric family's scene keys (superquadric_scene.cpp): the parameters of a shape
// entry `superquadric: {half_axes, blockiness}` (book Eq. 2.1) and the `superquadric_contact`
// settings.
#include "family_scene.hpp"
#include "snapshot.hpp"

namespace kdem {

// Semi-axes a, b, c along the body x, y, z and blockiness n1 (profile along z), n2 (xy
// cross-section).
struct SuperquadricShapeParameters : FamilyShapeParameters {
  Vec3d half_axes{0, 0, 0}; // m
  double n1 = 2, n2 = 2;
  double smallest_size() const override;
};

// Controls of the superquadric narrow phase and of its contact radius.
struct SuperquadricContactConfig : FamilySettings {
  double tolerance = 0;       // Newton tolerance; 0: the engine's default
  int max_iterations = 0;     // Newton iteration cap; 0: the engine's default
  double curvature_limit = 2; // R* from curvature is kept within [1/limit, limit] x R*_volume
  bool separation_certificates = true; // skip pairs whose gap bound outlasts their motion
  bool box_certificates = true;        // the box test's gap is a certificate too
  bool compact_candidates = true;      // scan the box tests' survivors into a dense list
  bool extrapolate_start = true;       // Newton starts from the last point moved by its last step
  bool ellipsoid_scalar_root = true;   // two ellipsoids: the midway point as a scalar root
  bool lanes = true;                   // host: four pairs of one shape pair solved in lock step
  int team_size = 0;                   // lanes per team of the narrow-phase kernels; 0: flat
};

// Its entry in the registry of scene readers.
FamilyScene superquadric_scene();

// Reads a `blockiness` value [n1, n2], each in [2, 20] (shared by the families made of
// superquadric pieces).
void read_blockiness(const scene_yaml::Value& value, double& n1, double& n2);

// Reads the narrow-phase settings of `keys` (those of SuperquadricContactConfig a family uses),
// refusing any other key: the superquadrics' reader, shared by the families whose contacts are
// solved by the superquadric Newton (poly-superquadrics).
std::shared_ptr<SuperquadricContactConfig> read_newton_settings(const scene_yaml::Value& value,
                                                                const scene_yaml::KeyList& keys);

// The parameters of a superquadric shape entry; throws std::logic_error for another family's.
const SuperquadricShapeParameters& superquadric_parameters(const ShapeConfig& shape);
// The scene's superquadric settings (the defaults where it sets none), and a modifiable copy
// that replaces them (for programs that build scenes).
const SuperquadricContactConfig& superquadric_contact(const SceneConfig& scene);
SuperquadricContactConfig& modify_superquadric_contact(SceneConfig& scene);
// Barr's parametric surface (1981) in the body frame on the latitude-longitude grid of
// body_surface.hpp, for output.
BodySurface superquadric_surface(Vec3d half_axes, double n1, double n2, int resolution);
// A superquadric shape entry made in code.
ShapeConfig superquadric_shape_config(const std::string& name, Vec3d half_axes, double n1,
                                      double n2);

} // namespace kdem
