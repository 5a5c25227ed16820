#pragma once
// Triangle meshes for walls: reading STL and OBJ, welding coincident vertices, and the edge/vertex
// topology that sphere-mesh contact needs.
#include <array>
#include <string>
#include <vector>

namespace kdem {

struct TriangleMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;
};

// Reads an ASCII or binary STL file, or a Wavefront OBJ file (its faces; a face of n > 3 corners
// as a fan of triangles), and welds its vertices. Throws std::runtime_error naming the file (and
// the line, for text files) when it cannot be read, is malformed or holds no triangles. read_mesh
// picks the reader by the file name's extension (.stl or .obj, in any case) and refuses any other.
TriangleMesh read_stl(const std::string& path);
TriangleMesh read_obj(const std::string& path);
TriangleMesh read_mesh(const std::string& path);
// The same before welding (src/mesh_readers.cpp): STL corners each their own vertex, OBJ vertices
// as numbered in the file.
TriangleMesh read_stl_unwelded(const std::string& path);
TriangleMesh read_obj_unwelded(const std::string& path);
bool is_mesh_file_name(const std::string& path);

// Merges points closer than `tolerance` and drops triangles that become degenerate.
TriangleMesh weld(const TriangleMesh& mesh, double tolerance);

// The same triangles (corners in their order) sorted by the cell of their centroids in a grid
// of `cell` from `origin`, cells in the order the engine sorts particles (x fastest, then y, then
// z), and the points they use numbered in the order of first use: the triangles that neighbouring
// particles touch come close in memory, whatever the order of the file, which is what the wall
// contacts of a large mesh need (they are bound by the latency of loading triangles). Ties keep
// the file's order.
TriangleMesh spatially_ordered(const TriangleMesh& mesh, const std::array<double, 3>& origin,
                               double cell);

struct MeshTopology {
  std::vector<std::array<int, 3>> triangle_edges; // edges ab, bc, ca of each triangle
  std::vector<std::array<int, 2>> edge_vertices;
  std::vector<std::vector<int>> edge_triangles;      // adjacent triangles of each edge
  std::vector<std::array<double, 3>> edge_direction; // unit, from edge_vertices[0] to [1]
  std::vector<std::array<double, 6>> edge_outward;   // per adjacent triangle (first two), unit
                                                     // in-plane direction away from the triangle
  std::vector<std::vector<int>> vertex_triangles;
  std::vector<std::vector<std::array<double, 3>>> vertex_edge_directions;
};

MeshTopology build_topology(const TriangleMesh& mesh);

} // namespace kdem
