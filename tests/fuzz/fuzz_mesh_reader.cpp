// libFuzzer target: the mesh readers and the wall set-up of a mesh on arbitrary bytes. The first
// byte picks the reader (even: STL, odd: OBJ); the rest is written to a file of that extension
// and built into wall elements as a scene's mesh wall is (read, weld, order, manifold check,
// topology). A file is either built or refused with std::runtime_error; anything else is a
// defect.
#include <unistd.h>
#include <vtkObject.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "wall_builder.hpp"

namespace {

std::string scratch_file(const char* extension) {
  const auto folder = std::filesystem::temp_directory_path();
  return (folder / ("kdem-fuzz-mesh-" + std::to_string(getpid()) + extension)).string();
}

void write_file(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file)
    std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size)
    std::abort();
  std::fclose(file);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  // VTK's readers print every problem they meet; the fuzzer's log keeps only kdem's verdicts.
  static const bool quiet = (vtkObject::GlobalWarningDisplayOff(), true);
  (void)quiet;
  static const std::string stl = scratch_file(".stl"), obj = scratch_file(".obj");
  const std::string& path = data[0] % 2 == 0 ? stl : obj;
  write_file(path, data + 1, size - 1);
  kdem::WallConfig wall;
  wall.kind = kdem::WallConfig::Kind::Mesh;
  wall.name = "fuzzed";
  wall.material = "steel";
  wall.file = path;
  try {
    const kdem::Vec3d lo{-1, -1, -1}, hi{1, 1, 1};
    kdem::build_wall_elements({wall}, lo, hi, 0.05);
    kdem::Vec3d box_lo, box_hi;
    kdem::walls_bounding_box({wall}, box_lo, box_hi);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
