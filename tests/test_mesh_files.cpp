// Mesh files for walls: ASCII and binary STL and Wavefront OBJ read to the same welded mesh, and
// clear errors for a missing, empty or unknown file.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include "src/mesh.hpp"
#include "src/wall_builder.hpp"

namespace {

namespace fs = std::filesystem;
using kdem::TriangleMesh;

// The unit square in z = 0 as two triangles sharing the diagonal (0,0,0)-(1,1,0).
const std::array<std::array<double, 3>, 6> square_corners{
    {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}}};

fs::path scratch(const std::string& name) {
  const fs::path folder = fs::path(testing::TempDir()) / "kdem_mesh_files";
  fs::create_directories(folder);
  return folder / name;
}

fs::path write_text(const std::string& name, const std::string& text) {
  const fs::path path = scratch(name);
  std::ofstream(path) << text;
  return path;
}

fs::path write_ascii_stl(const std::string& name) {
  std::string text = "solid square\n";
  for (int t = 0; t < 2; ++t) {
    text += " facet normal 0 0 1\n  outer loop\n";
    for (int v = 0; v < 3; ++v) {
      const auto& p = square_corners[3 * t + v];
      text += "   vertex " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
              std::to_string(p[2]) + "\n";
    }
    text += "  endloop\n endfacet\n";
  }
  return write_text(name, text + "endsolid square\n");
}

// Binary STL: 80-byte header, triangle count, then per triangle 12 floats and a 2-byte word.
fs::path write_binary_stl(const std::string& name) {
  const fs::path path = scratch(name);
  std::ofstream out(path, std::ios::binary);
  char header[80] = {};
  std::strncpy(header, "binary square", sizeof header);
  out.write(header, sizeof header);
  const std::uint32_t count = 2;
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (int t = 0; t < 2; ++t) {
    const float normal[3] = {0, 0, 1};
    out.write(reinterpret_cast<const char*>(normal), sizeof normal);
    for (int v = 0; v < 3; ++v)
      for (int a = 0; a < 3; ++a) {
        const float x = float(square_corners[3 * t + v][a]);
        out.write(reinterpret_cast<const char*>(&x), 4);
      }
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
  return path;
}

std::set<std::array<double, 3>> point_set(const TriangleMesh& mesh) {
  return {mesh.points.begin(), mesh.points.end()};
}

void expect_welded_square(const TriangleMesh& mesh) {
  EXPECT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.points.size(), 4u); // the shared corners welded
  const std::set<std::array<double, 3>> corners{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(point_set(mesh), corners);
}

TEST(MeshFiles, AsciiAndBinaryStlGiveTheSameMesh) {
  expect_welded_square(kdem::read_mesh(write_ascii_stl("ascii.stl").string()));
  expect_welded_square(kdem::read_mesh(write_binary_stl("binary.STL").string()));
}

TEST(MeshFiles, ObjQuadIsSplitIntoTwoTriangles) {
  const fs::path path = write_text("quad.obj", "# a unit square\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                               "v 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n");
  const TriangleMesh mesh = kdem::read_mesh(path.string());
  expect_welded_square(mesh);
  for (const auto& t : mesh.triangles) // both triangles keep the face's orientation (+z)
    EXPECT_GT((mesh.points[t[1]][0] - mesh.points[t[0]][0]) *
                      (mesh.points[t[2]][1] - mesh.points[t[0]][1]) -
                  (mesh.points[t[1]][1] - mesh.points[t[0]][1]) *
                      (mesh.points[t[2]][0] - mesh.points[t[0]][0]),
              0);
}

TEST(MeshFiles, ObjTrianglesMatchTheStl) {
  const fs::path path = write_text("two.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                              "f 1 2 3\nf 1 3 4\n");
  const TriangleMesh obj = kdem::read_mesh(path.string());
  const TriangleMesh stl = kdem::read_mesh(write_ascii_stl("same.stl").string());
  EXPECT_EQ(point_set(obj), point_set(stl));
  EXPECT_EQ(obj.triangles.size(), stl.triangles.size());
}

void expect_error(const fs::path& path, const std::string& words) {
  try {
    kdem::read_mesh(path.string());
    ADD_FAILURE() << path << " was read";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(words), std::string::npos) << message;
  }
}

TEST(MeshFiles, MissingEmptyAndUnknownFilesAreRefusedByName) {
  expect_error(scratch("absent.stl"), "STL file not found");
  expect_error(write_text("empty.obj", ""), "no triangles read (is it an OBJ file?)");
  expect_error(write_text("no_faces.obj", "v 0 0 0\nv 1 0 0\n"), "no triangles read");
  expect_error(write_text("empty.stl", "solid e\nendsolid e\n"), "no triangles read");
  expect_error(write_text("square.ply", "ply\n"), "expected a mesh file ending in .stl or .obj");
}

TEST(MeshFiles, ObjCornerFormsAndNegativeIndicesGiveTheSameSquare) {
  // Corners as i, i/t, i//n and i/t/n; negative numbers count back from the last vertex so far.
  const fs::path path = write_text("forms.obj", "o square\ng all\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                                "vt 0 0\nvn 0 0 1\nf 1/1 2//1 -1/1/1\n"
                                                "v 0 1 0\ns off\nf -4 -2 -1\n");
  expect_welded_square(kdem::read_mesh(path.string()));
}

TEST(MeshFiles, MalformedFilesAreRefusedWithTheirLine) {
  expect_error(write_text("zero.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 0\n"),
               "line 4: expected a face corner as a vertex number");
  expect_error(write_text("ahead.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 1 1 0\n"),
               "line 3: face corner 3 refers to a vertex not defined yet (2 so far)");
  expect_error(write_text("back.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -1 -2 -4\n"),
               "line 4: face corner -4 refers to a vertex not defined yet (3 so far)");
  expect_error(write_text("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"),
               "line 3: a face needs at least three corners");
  expect_error(write_text("nan.obj", "v 0 nan 0\n"), "line 1: expected 'v x y z'");
  expect_error(write_text("short.obj", "v 0 0\n"), "line 1: expected 'v x y z'");
  expect_error(write_text("outside.stl", "solid s\nvertex 0 0 0\nendsolid s\n"),
               "line 2: vertex outside a facet");
  expect_error(write_text("four.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                      "vertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\n"),
               "line 7: a facet with more than three vertices");
  expect_error(write_text("open.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"),
               "the file ends inside a facet");
  expect_error(write_text("word.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 x\n"),
               "line 4: expected 'vertex x y z' with three finite numbers");
  expect_error(write_text("other.stl", "solid s\nfacets\n"), "line 2: expected an STL keyword");
}

TEST(MeshFiles, BinaryStlWithANonFiniteCornerIsRefused) {
  const fs::path path = write_binary_stl("infinite.stl");
  std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
  const float infinite = INFINITY;
  file.seekp(84 + 12 + 4); // first triangle, first corner, y
  file.write(reinterpret_cast<const char*>(&infinite), 4);
  file.close();
  expect_error(path, "triangle 1 has a corner coordinate that is not a finite number");
}

TEST(MeshFiles, BinaryStlWithAWrongCountIsReadAsTextAndRefused) {
  const fs::path path = write_binary_stl("truncated.stl");
  fs::resize_file(path, fs::file_size(path) - 1);
  expect_error(path, "expected an STL keyword");
}

} // namespace

namespace {

// A 6 x 5 grid of squares at z = 0 in shuffled order, with an unused point.
TriangleMesh shuffled_grid() {
  TriangleMesh mesh;
  const int nx = 6, ny = 5;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      mesh.points.push_back({0.01 * i, 0.01 * j, 0});
  mesh.points.push_back({5, 5, 5});
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  std::vector<std::array<int, 3>> shuffled;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k)
    shuffled.push_back(mesh.triangles[(k * 37) % mesh.triangles.size()]);
  mesh.triangles = shuffled;
  return mesh;
}

std::multiset<std::array<std::array<double, 3>, 3>> corner_positions(const TriangleMesh& mesh) {
  std::multiset<std::array<std::array<double, 3>, 3>> corners;
  for (const auto& t : mesh.triangles)
    corners.insert({mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]});
  return corners;
}

} // namespace

// The same triangles with their corners in their order, in the order of the cells of their
// centroids (x fastest, then y, then z), points in the order of first use and none unused.
TEST(MeshFiles, SpatialOrderKeepsTheTrianglesAndSortsThemByCell) {
  const TriangleMesh mesh = shuffled_grid();
  const double cell = 0.02;
  const TriangleMesh ordered = kdem::spatially_ordered(mesh, {0, 0, 0}, cell);
  EXPECT_EQ(corner_positions(ordered), corner_positions(mesh));
  EXPECT_EQ(ordered.points.size(), mesh.points.size() - 1);
  long previous_key = -1;
  int next_new_point = 0;
  for (const auto& t : ordered.triangles) {
    double cx = 0, cy = 0;
    for (int v : t) {
      cx += ordered.points[v][0] / 3, cy += ordered.points[v][1] / 3;
      if (v >= next_new_point) {
        EXPECT_EQ(v, next_new_point);
        ++next_new_point;
      }
    }
    const long key = long(std::floor(cy / cell)) * 1000 + long(std::floor(cx / cell));
    EXPECT_GE(key, previous_key);
    previous_key = key;
  }
}

// A triangle 1e30 m away (found by fuzzing: its cell number overflowed the sort key) sorts after
// the near ones, one far the other way before them (all three in the same y and z cells).
TEST(MeshFiles, SpatialOrderPutsFarTrianglesAtTheEnds) {
  TriangleMesh mesh;
  mesh.points = {{0, 0, 0},    {1, 1, 0},     {0, 0, 1},     {1e30, 0, 0}, {1e30, 1, 0},
                 {1e30, 0, 1}, {-1e30, 0, 0}, {-1e30, 1, 0}, {-1e30, 0, 1}};
  mesh.triangles = {{3, 4, 5}, {0, 1, 2}, {6, 7, 8}};
  const TriangleMesh ordered = kdem::spatially_ordered(mesh, {0, 0, 0}, 0.1);
  ASSERT_EQ(ordered.triangles.size(), 3u);
  EXPECT_EQ(ordered.points[ordered.triangles[0][0]][0], -1e30);
  EXPECT_EQ(ordered.points[ordered.triangles[1][0]][0], 0);
  EXPECT_EQ(ordered.points[ordered.triangles[2][0]][0], 1e30);
}

// Three triangles on one edge (a fin on a floor): refused, naming the wall, its file and the
// edge; the floor alone (two triangles on the edge) is accepted.
TEST(MeshFiles, EdgeOfThreeTrianglesIsRefusedByName) {
  const std::string floor = "solid fin\n"
                            "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                            "vertex 0.5 1 0\nendloop\nendfacet\n"
                            "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 0 0 0\n"
                            "vertex 0.5 -1 0\nendloop\nendfacet\n";
  const std::string fin = "facet normal 0 1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                          "vertex 0.5 0 1\nendloop\nendfacet\n";
  kdem::WallConfig wall;
  wall.kind = kdem::WallConfig::Kind::Mesh;
  wall.name = "fin";
  wall.file = write_text("floor.stl", floor + "endsolid fin\n").string();
  EXPECT_NO_THROW(kdem::build_wall_elements({wall}, {-1, -1, -1}, {1, 1, 1}));
  wall.file = write_text("fin.stl", floor + fin + "endsolid fin\n").string();
  try {
    kdem::build_wall_elements({wall}, {-1, -1, -1}, {1, 1, 1});
    FAIL() << "a mesh with an edge of three triangles was accepted";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("mesh wall 'fin' (" + wall.file + ")"), std::string::npos) << message;
    EXPECT_NE(message.find("from (0, 0, 0) to (1, 0, 0) is shared by 3 triangles"),
              std::string::npos)
        << message;
  }
}
