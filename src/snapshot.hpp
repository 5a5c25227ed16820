#pragma once
// Host copies of what output writers need: one frame of particles, and wall surfaces.
#include <cstdint>
#include <string>
#include <vector>

namespace kdem {

// Triangles in a body frame: 3 coordinates per point (m), 3 point indices per triangle.
struct BodySurface {
  std::vector<double> points;
  std::vector<int> triangles;
};

// A named value of `components` numbers per item (per particle in a snapshot, per template in
// a shape template).
struct ShapeField {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

struct ParticleSnapshot {
  std::int64_t step = 0;
  double time = 0; // s
  // N rows each; vectors flattened row-major (x0, y0, z0, x1, ...).
  std::vector<double> position;         // 3N, m
  std::vector<double> velocity;         // 3N, m/s
  std::vector<double> angular_velocity; // 3N, rad/s, world frame
  std::vector<double> quaternion;       // 4N, (w, x, y, z), body to world
  std::vector<double> radius;           // N, m (bounding radius)
  std::vector<int> shape;               // N, shape template id (0 = sphere)
  std::vector<int> material;            // N
  std::vector<std::int64_t> id;         // N, stable particle id
  // N each: index of the source that made the particle (-1: added by the program) and of its
  // tag (-1: none), with the names they index; empty when the writer has no sources.
  std::vector<int> source, tag;
  std::vector<std::string> source_names, tag_names;
  // Values that the shape families describe their shapes by (a superquadric's half_axes and
  // blockiness), per particle; NaN for a particle whose shape has no such value.
  std::vector<ShapeField> shape_fields;
  // The surface of each shape id in its body frame, for pictures; shape 0 (spheres) is of unit
  // radius, drawn scaled by each particle's radius. Empty when the writer has no shapes (then
  // frames carry only the radius).
  std::vector<BodySurface> shape_surfaces;
  std::size_t size() const { return radius.size(); }
};

// The contact force at the last step on the particle of id `id`: from the particle of id
// `partner` (a touching pair: the sum of its contact points' forces), or from a wall element
// (partner -1, wall: the wall's index in the scene's list), N.
struct ContactForceRecord {
  std::int64_t id = 0, partner = -1;
  int wall = -1;
  double force[3] = {0, 0, 0};
};

// A wall's surface as triangles in world coordinates at one instant.
struct WallSurface {
  std::string name;
  std::vector<double> points; // 3 per point, m
  std::vector<int> triangles; // 3 point indices per triangle
};

} // namespace kdem
