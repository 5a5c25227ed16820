#pragma once
// Scene description: everything a run needs, in SI units, as read from a YAML scene file.
// Plain host data; validated by the loader, consumed by the Engine.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace kdem {

using Vec3d = std::array<double, 3>;

// Default Verlet skin relative to the smallest radius: lists then last for a displacement of
// 0.2 radii, tens of steps in dense flows, while the candidate shell stays thin (a pair list
// about 1.7 times the contacts in a dense packing of equal spheres).
constexpr double default_skin_per_radius = 0.4;

struct MaterialConfig {
  std::string name;
  double density = 0;          // kg/m^3
  double youngs_modulus = 0;   // Pa
  double poisson_ratio = 0;    // -
  double restitution = 0.5;    // coefficient of restitution against the same material
  double friction = 0.5;       // sliding friction coefficient
  double rolling_friction = 0; // rolling friction coefficient
};

// Overrides for one material pair; absent pairs use the mean of the two materials' values.
struct InteractionConfig {
  std::string material_a, material_b;
  double restitution = 0.5;
  double friction = 0.5;
  double rolling_friction = 0;
};

struct SizeDistributionConfig {
  enum class Kind { Monodisperse, Uniform, Gaussian, Discrete };
  Kind kind = Kind::Monodisperse;
  double radius = 0;                  // monodisperse
  double min_radius = 0;              // uniform, gaussian (truncation)
  double max_radius = 0;              // uniform, gaussian (truncation)
  double mean_radius = 0;             // gaussian
  double std_radius = 0;              // gaussian
  std::vector<double> radii;          // discrete
  std::vector<double> mass_fractions; // discrete, same length as radii, summing to 1
};

struct RegionConfig {
  enum class Kind { Box, Cylinder };
  Kind kind = Kind::Box;
  Vec3d min{0, 0, 0}, max{0, 0, 0}; // box
  Vec3d base_center{0, 0, 0};       // cylinder: axis along +z from base_center
  double radius = 0;
  double height = 0;
};

// What a shape family reads from its entry of `shapes` (and checks), for its setup to build
// the template from: a superquadric's semi-axes and exponents, later a clump's elements or a
// mesh file. Each family derives its own (src/<family>_scene.hpp).
struct FamilyShapeParameters {
  virtual ~FamilyShapeParameters() = default;
  // The smallest size of the body (a superquadric's smallest semi-axis), m: the default skin
  // is sized from it.
  virtual double smallest_size() const = 0;
};

// A family's scene-wide settings (its narrow-phase controls), read from its top-level key.
struct FamilySettings {
  virtual ~FamilySettings() = default;
};

// A particle shape template other than a sphere, of the family named `family` (its key in the
// shape's entry, e.g. "superquadric").
struct ShapeConfig {
  std::string name;
  std::string family;
  std::shared_ptr<const FamilyShapeParameters> parameters;
};

struct ParticleSourceConfig {
  std::string name;
  std::string tag; // user label of its particles (frames, checkpoints, series.csv); may repeat
                   // across sources; empty: none
  std::string material;
  std::string shape;            // name of a ShapeConfig; empty: spheres sized by `sizes`
  SizeDistributionConfig sizes; // for a shaped source: monodisperse, radius = smallest semi-axis
                                // as loaded; the engine sets it to the bounding radius
  double particle_volume_ratio = 1; // particle volume / volume of the placed sphere (the
                                    // bounding sphere of a shaped particle), set by the engine
  RegionConfig region;
  std::int64_t count = 0;     // particles to place; 0 when volume_fraction is used
  double volume_fraction = 0; // target solid fraction of the region; 0 when count is used
  bool random_orientation = true;
  std::array<double, 4> orientation{1, 0, 0, 0}; // unit quaternion (w, x, y, z) of every
                                                 // particle when random_orientation is false
  Vec3d velocity{0, 0, 0};                       // initial velocity, m/s
  Vec3d angular_velocity{0, 0, 0};               // initial angular velocity, rad/s, world frame
  std::uint64_t seed = 1;
  // Insertion over time ("rain"): when rate > 0, particles are inserted at `rate` per second
  // from `start` on, in batches every `interval` seconds, until `count` are in.
  double rate = 0;
  double start = 0;
  double interval = 0.01;
};

struct MotionConfig {
  Vec3d velocity{0, 0, 0};       // m/s, constant translation
  Vec3d axis_point{0, 0, 0};     // a point of the rotation axis (reference position)
  Vec3d axis_direction{0, 0, 1}; // rotation axis (normalised by the loader)
  double rpm = 0;                // revolutions per minute, right-handed about axis_direction
  double start = 0;              // s, motion begins
  bool moves() const {
    return rpm != 0 || velocity[0] != 0 || velocity[1] != 0 || velocity[2] != 0;
  }
};

struct WallConfig {
  enum class Kind { Plane, Box, Cylinder, Mesh };
  Kind kind = Kind::Plane;
  std::string name;
  std::string material;
  // plane: a point and the normal pointing to the particles' side
  Vec3d point{0, 0, 0};
  Vec3d normal{0, 0, 1};
  // box: particles inside [min, max]; faces named in open_faces (xmin, xmax, ymin, ymax, zmin,
  // zmax) are left out
  Vec3d min{0, 0, 0}, max{0, 0, 0};
  std::vector<std::string> open_faces;
  // cylinder: particles inside; axis from base_center along axis_direction, finite length
  Vec3d base_center{0, 0, 0};
  Vec3d axis_direction{0, 0, 1};
  double radius = 0;
  double length = 0;
  // mesh: STL file (path relative to the scene file), scaled then translated
  std::string file; // as loaded: absolute, resolved against the scene file's folder
  double scale = 1;
  Vec3d translate{0, 0, 0};
  MotionConfig motion;
  double active_from = 0;      // s
  double active_until = 1e300; // s; a gate that opens is a wall with active_until
};

struct OutletConfig {
  std::string name;
  Vec3d min{0, 0, 0}, max{0, 0, 0}; // particles whose centre enters this box are removed
};

struct OutputConfig {
  std::string directory = "out";
  double frame_interval = 0;      // s between .vtu frames; 0 = no frames
  double series_interval = 0;     // s between series.csv rows; 0 = every 100 steps
  double checkpoint_interval = 0; // s between HDF5 checkpoints; 0 = only at the end
  bool final_checkpoint = true;
  bool contact_forces = false; // with each frame, the contact forces (frames/contacts_*.csv)
};

// When a run is stopped as gone wrong (checked every `interval` steps; see docs/scene.md,
// "checks") and what happens to particles that leave the domain.
struct ChecksConfig {
  enum class Leaving { Remove, Stop };
  int interval = 10;               // steps between two checks
  double max_overlap_ratio = 0.25; // deepest overlap / particle radius
  double max_energy_gain = 1.0;    // kinetic energy above its bound, relative to the bound
  Leaving leaving_domain = Leaving::Remove;
};

struct SceneConfig {
  std::string source_file; // for messages
  Vec3d gravity{0, 0, -9.81};
  double time_step = 0;     // s
  double duration = 0;      // s of simulated time
  double skin = 0;          // m, Verlet skin; when the file has none, the loader sets
                            // default_skin_per_radius x the smallest particle radius of the scene
  bool sort_by_cell = true; // permute particle arrays into cell order at list rebuilds
  bool has_domain = false;
  Vec3d domain_min{0, 0, 0}, domain_max{0, 0, 0}; // else derived from walls and regions
  std::vector<MaterialConfig> materials;
  std::vector<InteractionConfig> interactions;
  std::vector<ShapeConfig> shapes;
  // Settings of each family that the scene sets, by family name; a family absent here runs
  // with its defaults.
  std::map<std::string, std::shared_ptr<const FamilySettings>> family_settings;
  std::vector<ParticleSourceConfig> sources;
  std::vector<WallConfig> walls;
  std::vector<OutletConfig> outlets;
  OutputConfig output;
  ChecksConfig checks;
};

} // namespace kdem
