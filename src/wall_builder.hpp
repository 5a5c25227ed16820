#pragma once
// Turns the scene's walls into flat element tables (host side) for the wall kernels: planes,
// box faces, cylinders, and mesh triangles with their edge and vertex topology.
#include <array>
#include <string>
#include <vector>

#include "scene.hpp"

namespace kdem {

struct WallElementTable {
  std::vector<int> kind; // WallElementKind
  std::vector<int> wall;
  std::vector<std::array<double, 9>> geometry;
  std::vector<std::array<int, 6>> features;
  double feature_tolerance = 0;
  std::vector<int> edge_owner, edge_sides;
  std::vector<std::array<double, 6>> edge_outward;
  std::vector<std::array<int, 2>> edge_vertices;
  std::vector<std::array<double, 3>> edge_direction;
  std::vector<int> vertex_owner, vertex_edge_start{0}, vertex_triangle_start{0}, vertex_triangle;
  std::vector<std::array<double, 3>> vertex_position, vertex_edge_direction;
  // For the mesh contacts of bodies that are not spheres: per element the stored unit normal of a
  // triangle (coplanar triangles of a mesh store the same bits, up to sign; zero for other
  // elements), per edge its two triangles (-1: none), per vertex whether it is a corner (on the
  // mesh boundary or where the faces around it are not coplanar) and the positions of the vertices
  // joined to it.
  std::vector<std::array<double, 3>> triangle_normal;
  std::vector<std::array<int, 2>> edge_triangles;
  std::vector<int> vertex_corner, vertex_ring_start{0};
  std::vector<std::array<double, 3>> vertex_ring;
  // For drawing: every wall's surface as triangles in its reference frame.
  std::vector<std::vector<double>> surface_points;
  std::vector<std::vector<int>> surface_triangles;
};

struct WallMotionData {
  Vec3d pivot{0, 0, 0}, velocity{0, 0, 0}, omega{0, 0, 0};
  double start = 0, active_from = 0, active_until = 1e300;
  std::string material;
};

// `domain_min/max` sizes the drawn patch of infinite planes. Mesh triangles are stored in the
// order of their cells in the particles' grid (from domain_min, cells of `particle_cell`; 0, when
// the particle size is not known yet: twice the mesh's median edge), see spatially_ordered.
WallElementTable build_wall_elements(const std::vector<WallConfig>& walls, const Vec3d& domain_min,
                                     const Vec3d& domain_max, double particle_cell = 0);
std::vector<WallMotionData> wall_motions(const std::vector<WallConfig>& walls);

// Bounding box of the walls that have one (boxes, cylinders, meshes); false if none has.
bool walls_bounding_box(const std::vector<WallConfig>& walls, Vec3d& lo, Vec3d& hi);

} // namespace kdem
