// libFuzzer target: the scene loader on arbitrary text. A scene is either loaded, fully
// validated, or refused with a SceneError; anything else (a crash, a sanitizer report, another
// exception type escaping) is a defect. Mesh files named by a scene resolve against the seed
// corpus folder given in KDEM_FUZZ_BASE_DIR (default: the working directory).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "scene_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string base_dir = [] {
    const char* dir = std::getenv("KDEM_FUZZ_BASE_DIR");
    return std::string(dir ? dir : ".");
  }();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    kdem::load_scene_from_string(text, "fuzz.yaml", base_dir);
  } catch (const kdem::SceneError&) {
  }
  return 0;
}
