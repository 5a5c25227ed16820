#pragma once
// Host copies of what output writers need: one frame of particles, and wall surfaces.
#include <cstdint>
#include <string>
#include <vector>

namespace kdem {

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
  // Shape of each particle as a superquadric (a sphere is a = b = c = r, n1 = n2 = 2); empty
  // when the writer of the snapshot has no shapes (then frames carry only the radius).
  std::vector<double> half_axes;  // 3N, m, semi-axes a, b, c along body x, y, z
  std::vector<double> blockiness; // 2N, n1 (profile along z), n2 (xy cross-section)
  std::size_t size() const { return radius.size(); }
};

// A wall's surface as triangles in world coordinates at one instant.
struct WallSurface {
  std::string name;
  std::vector<double> points; // 3 per point, m
  std::vector<int> triangles; // 3 point indices per triangle
};

} // namespace kdem
