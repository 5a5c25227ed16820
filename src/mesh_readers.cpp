// STL (ASCII and binary) and Wavefront OBJ readers. Written here rather than taken from VTK:
// fuzzing found VTK 9.1's OBJ reader reading through a null pointer on a malformed file, and a
// reader of our own can name the line of a problem. Every problem is a std::runtime_error that
// starts with the file's path.
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh.hpp"

namespace kdem {
namespace {

using Point = std::array<double, 3>;

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

[[noreturn]] void refuse_line(const std::string& path, int line, const std::string& what) {
  refuse(path, "line " + std::to_string(line) + ": " + what);
}

std::string file_contents(const std::string& path, const std::string& format) {
  if (!std::filesystem::is_regular_file(path))
    refuse(path, format + " file not found");
  std::ifstream file(path, std::ios::binary);
  if (!file)
    refuse(path, "cannot open the " + format + " file");
  return {std::istreambuf_iterator<char>(file), {}};
}

void require_triangles(const std::string& path, const std::string& format,
                       const TriangleMesh& mesh) {
  if (mesh.triangles.empty())
    refuse(path, "no triangles read (is it an " + format + " file?)");
}

// The triangles of `corners` (three points per triangle, in order), each point its own vertex
// (welding merges the shared ones).
TriangleMesh mesh_of_corners(const std::vector<Point>& corners) {
  TriangleMesh mesh;
  mesh.points = corners;
  for (std::size_t t = 0; 3 * t + 2 < corners.size(); ++t)
    mesh.triangles.push_back({int(3 * t), int(3 * t + 1), int(3 * t + 2)});
  return mesh;
}

// ------------------------------------------------------------------------------ binary STL
// 80-byte header, a little-endian uint32 triangle count, then per triangle a normal and three
// corners (12 little-endian floats) and a 16-bit attribute word.
constexpr std::size_t stl_header_bytes = 84, stl_triangle_bytes = 50;

bool is_binary_stl(const std::string& bytes) {
  if (bytes.size() < stl_header_bytes)
    return false;
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  return bytes.size() == stl_header_bytes + stl_triangle_bytes * std::size_t(count);
}

float float_at(const std::string& bytes, std::size_t offset) {
  float value = 0;
  std::memcpy(&value, bytes.data() + offset, 4);
  return value;
}

std::vector<Point> binary_stl_corners(const std::string& path, const std::string& bytes) {
  std::vector<Point> corners;
  const std::size_t count = (bytes.size() - stl_header_bytes) / stl_triangle_bytes;
  corners.reserve(3 * count);
  for (std::size_t t = 0; t < count; ++t)
    for (int v = 0; v < 3; ++v) {
      const std::size_t offset = stl_header_bytes + stl_triangle_bytes * t + 12 * (v + 1);
      Point p{float_at(bytes, offset), float_at(bytes, offset + 4), float_at(bytes, offset + 8)};
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        refuse(path, "triangle " + std::to_string(t + 1) +
                         " has a corner coordinate that is not a finite number");
      corners.push_back(p);
    }
  return corners;
}

// ------------------------------------------------------------------------------- ASCII STL
// Keywords solid, facet normal, outer loop, vertex x y z (three per facet), endloop, endfacet,
// endsolid; several solids in one file are read one after another.
bool read_number(std::istringstream& words, double& value) {
  std::string word;
  if (!(words >> word))
    return false;
  const char* start = word.c_str();
  char* end = nullptr;
  value = std::strtod(start, &end);
  return end != start && *end == '\0' && std::isfinite(value);
}

std::vector<Point> ascii_stl_corners(const std::string& path, const std::string& text) {
  std::vector<Point> corners;
  std::istringstream lines(text);
  std::string line;
  int line_number = 0, corners_in_facet = 0;
  bool in_facet = false;
  while (std::getline(lines, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword))
      continue;
    if (keyword == "facet") {
      if (in_facet)
        refuse_line(path, line_number, "facet inside a facet (endfacet missing)");
      in_facet = true;
      corners_in_facet = 0;
    } else if (keyword == "vertex") {
      if (!in_facet)
        refuse_line(path, line_number, "vertex outside a facet");
      Point p;
      for (double& x : p)
        if (!read_number(words, x))
          refuse_line(path, line_number, "expected 'vertex x y z' with three finite numbers");
      if (++corners_in_facet > 3)
        refuse_line(path, line_number, "a facet with more than three vertices");
      corners.push_back(p);
    } else if (keyword == "endfacet") {
      if (!in_facet || corners_in_facet != 3)
        refuse_line(path, line_number, "expected a facet of three vertices before endfacet");
      in_facet = false;
    } else if (keyword != "solid" && keyword != "outer" && keyword != "endloop" &&
               keyword != "endsolid") {
      refuse_line(path, line_number,
                  "expected an STL keyword (solid, facet, outer, vertex, endloop, endfacet, "
                  "endsolid), got '" +
                      keyword.substr(0, 40) + "'");
    }
  }
  if (in_facet)
    refuse(path, "the file ends inside a facet (endfacet missing)");
  return corners;
}

// ------------------------------------------------------------------------------------- OBJ
// 'v x y z [w]' vertices and 'f a b c ...' faces (corners as i, i/t, i//n or i/t/n, 1-based, or
// negative: counted back from the last vertex so far); a face of n corners becomes the fan of
// n - 2 triangles from its first corner. Texture coordinates, normals, groups, objects,
// materials, smoothing, lines and points are skipped.
bool parse_whole_int(const std::string& word, long& value) {
  const char* start = word.c_str();
  char* end = nullptr;
  errno = 0;
  value = std::strtol(start, &end, 10);
  return end != start && *end == '\0' && errno == 0;
}

int obj_corner_index(const std::string& path, int line_number, const std::string& corner,
                     std::size_t vertex_count) {
  long index = 0;
  if (!parse_whole_int(corner.substr(0, corner.find('/')), index) || index == 0)
    refuse_line(path, line_number,
                "expected a face corner as a vertex number (1, 2, ... or -1, -2, ...), got '" +
                    corner.substr(0, 40) + "'");
  const long count = long(vertex_count);
  const long zero_based = index > 0 ? index - 1 : count + index;
  if (zero_based < 0 || zero_based >= count)
    refuse_line(path, line_number,
                "face corner " + std::to_string(index) + " refers to a vertex not defined yet (" +
                    std::to_string(count) + " so far)");
  return int(zero_based);
}

TriangleMesh obj_mesh(const std::string& path, const std::string& text) {
  TriangleMesh mesh;
  std::istringstream lines(text);
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword) || keyword[0] == '#')
      continue;
    if (keyword == "v") {
      Point p;
      for (double& x : p)
        if (!read_number(words, x))
          refuse_line(path, line_number, "expected 'v x y z' with three finite numbers");
      if (mesh.points.size() >= std::size_t(std::numeric_limits<int>::max()))
        refuse_line(path, line_number, "more vertices than kdem can number");
      mesh.points.push_back(p);
    } else if (keyword == "f") {
      std::vector<int> corners;
      for (std::string corner; words >> corner;)
        corners.push_back(obj_corner_index(path, line_number, corner, mesh.points.size()));
      if (corners.size() < 3)
        refuse_line(path, line_number, "a face needs at least three corners");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
    }
  }
  return mesh;
}

} // namespace

TriangleMesh read_stl_unwelded(const std::string& path) {
  const std::string bytes = file_contents(path, "STL");
  const TriangleMesh mesh = mesh_of_corners(is_binary_stl(bytes) ? binary_stl_corners(path, bytes)
                                                                 : ascii_stl_corners(path, bytes));
  require_triangles(path, "STL", mesh);
  return mesh;
}

TriangleMesh read_obj_unwelded(const std::string& path) {
  const TriangleMesh mesh = obj_mesh(path, file_contents(path, "OBJ"));
  require_triangles(path, "OBJ", mesh);
  return mesh;
}

} // namespace kdem
