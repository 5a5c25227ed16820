#pragma once
// Triangle meshes for the tests: small vector helpers, STL files in a folder of the test's own,
// mesh walls.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "src/scene.hpp"

namespace kdem::testing {

using Triangle = std::array<Vec3d, 3>;

inline Vec3d sub(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline double dot(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline Vec3d unit(const Vec3d& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}
inline Vec3d along(const Vec3d& origin, const Vec3d& direction, double distance) {
  return {origin[0] + distance * direction[0], origin[1] + distance * direction[1],
          origin[2] + distance * direction[2]};
}

// A folder of its own for each test's STL files, removed afterwards.
class MeshFolder {
public:
  MeshFolder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    // The process id keeps the Serial and OpenMP runs of one test apart under `ctest -j`.
    std::string name = std::string("kdem_mesh_") + std::to_string(::getpid()) + "_" +
                       info->test_suite_name() + "_" + info->name();
    for (char& c : name)
      if (c == '/')
        c = '_';
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~MeshFolder() { std::filesystem::remove_all(path_); }
  // Writes an ASCII STL file and returns its path.
  std::string write(const std::string& name, const std::vector<Triangle>& triangles) const {
    const std::string file = (path_ / (name + ".stl")).string();
    std::ofstream out(file);
    out.precision(17);
    out << "solid " << name << "\n";
    for (const Triangle& t : triangles) {
      const Vec3d n = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])));
      out << "  facet normal " << n[0] << " " << n[1] << " " << n[2] << "\n    outer loop\n";
      for (const Vec3d& v : t)
        out << "      vertex " << v[0] << " " << v[1] << " " << v[2] << "\n";
      out << "    endloop\n  endfacet\n";
    }
    out << "endsolid " << name << "\n";
    return file;
  }

private:
  std::filesystem::path path_;
};

inline WallConfig mesh_wall(const std::string& material, const std::string& file) {
  WallConfig w;
  w.kind = WallConfig::Kind::Mesh;
  w.name = "mesh";
  w.material = material;
  w.file = file;
  return w;
}

// Flat square [-h, h]^2 at height z, cut into n x n squares of two triangles each.
inline std::vector<Triangle> flat_grid(double h, double z, int n) {
  std::vector<Triangle> t;
  auto corner = [&](int i, int j) { return Vec3d{-h + 2 * h * i / n, -h + 2 * h * j / n, z}; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      t.push_back(Triangle{corner(i, j), corner(i + 1, j), corner(i + 1, j + 1)});
      t.push_back(Triangle{corner(i, j), corner(i + 1, j + 1), corner(i, j + 1)});
    }
  return t;
}

} // namespace kdem::testing
