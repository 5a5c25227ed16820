// libFuzzer target: the checkpoint reader on checkpoints that differ from a real one. The input
// is a list of edits (checkpoint_edits.hpp) applied to every dataset kdem reads: values set to
// extremes, NaN or an index just out of range; rows added or cut; columns, element types and
// scalars changed; datasets removed or swapped. The edited checkpoint is written as a valid HDF5
// file and read back by Engine::read_checkpoint, which must either refuse it with a
// std::runtime_error, leaving the engine as it was, or take it, after which the engine runs a few
// steps (every kernel then follows the indices the file gave). A crash, a sanitizer report,
// another exception type or a refusal that changed the engine is a defect.
//
// The bytes of the HDF5 file itself are not mutated: HDF5's own parser is not kdem's code (see
// docs/fuzzing.md). The scene is tests/fuzz/scene_files/checkpoint.yaml, found through
// KDEM_FUZZ_BASE_DIR (default: the working directory).
//
// When the checkpoint gains datasets, inputs written before choose other datasets (edits choose
// by index). With KDEM_FUZZ_RETARGET_WITHOUT (the new datasets, comma-separated) and
// KDEM_FUZZ_RETARGET_TO (a file), the input is not run but rewritten into that file so that it
// edits what it edited in the checkpoint without them (docs/fuzzing.md, "Regression inputs").
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <hdf5.h>

#include "checkpoint_edits.hpp"
#include "engine.hpp"
#include "kernels/types.hpp"
#include "scene_loader.hpp"

namespace {

using kdem::fuzz::CheckpointImage;

struct Base {
  std::unique_ptr<kdem::Engine> engine;
  std::string checkpoint_path; // the real checkpoint
  std::string edited_path;     // where each input's edited checkpoint is written
  CheckpointImage image;
  kdem::ParticleSnapshot particles; // the engine's state after reading the real checkpoint
};

// A folder of this process for the checkpoints, removed when the process exits normally (a
// crash leaves it, with the edited checkpoint that caused it).
const std::filesystem::path& scratch_folder() {
  // Never destroyed: the exit handler below runs after static destructors.
  static const auto* folder = [] {
    const char* tmp = std::getenv("TMPDIR");
    auto* made = new std::filesystem::path(std::filesystem::path(tmp ? tmp : "/tmp") /
                                           ("kdem-fuzz-checkpoint-" + std::to_string(::getpid())));
    std::filesystem::create_directories(*made);
    return made;
  }();
  static const bool removed_at_exit = std::atexit([] {
                                        std::error_code ignored;
                                        std::filesystem::remove_all(*folder, ignored);
                                      }) == 0;
  (void)removed_at_exit;
  return *folder;
}

// Runs the scene until particles touch each other and both walls, so that the checkpoint's
// contact lists carry history.
void run_until_contacts(kdem::Engine& engine) {
  for (int chunk = 0; chunk < 400; ++chunk) {
    const kdem::Diagnostics d = engine.diagnostics();
    if (d.pair_contacts >= 3 && d.wall_contacts >= 3)
      return;
    engine.advance(50);
  }
  throw std::runtime_error("the fuzz scene made no contacts");
}

Base& base() {
  static Base* made = [] {
    if (!Kokkos::is_initialized()) {
      Kokkos::initialize();
      kdem::install_memory_space_check<kdem::MemSpace>();
    }
    // HDF5 keeps freed blocks for reuse up to limits that its file-cache block (half a megabyte,
    // one per open file) exceeds; unlimited, an open reuses the block instead of mapping fresh
    // pages (with the sanitizers' allocator, half the time of an input went to that).
    H5set_free_list_limits(-1, -1, -1, -1, -1, -1);
    const char* dir = std::getenv("KDEM_FUZZ_BASE_DIR");
    const std::string scene_path = std::string(dir ? dir : ".") + "/checkpoint.yaml";
    auto* b = new Base;
    b->engine = std::make_unique<kdem::Engine>(kdem::load_scene(scene_path));
    run_until_contacts(*b->engine);
    const auto folder = scratch_folder();
    b->checkpoint_path = (folder / "base.h5").string();
    b->edited_path = (folder / "edited.h5").string();
    b->engine->write_checkpoint(b->checkpoint_path);
    b->image = kdem::fuzz::read_image(b->checkpoint_path);
    b->particles = b->engine->snapshot();
    return b;
  }();
  return *made;
}

void require(bool ok, const char* what) {
  if (!ok) {
    std::cerr << "checkpoint_reader: " << what << "\n";
    std::abort();
  }
}

bool retargeted(const Base& b, const std::uint8_t* data, std::size_t size) {
  const char* added = std::getenv("KDEM_FUZZ_RETARGET_WITHOUT");
  const char* output_path = std::getenv("KDEM_FUZZ_RETARGET_TO");
  if (!added || !output_path)
    return false;
  CheckpointImage before = b.image;
  std::stringstream names(added);
  auto& datasets = before.datasets;
  for (std::string name; std::getline(names, name, ',');)
    datasets.erase(std::remove_if(datasets.begin(), datasets.end(),
                                  [&](const auto& d) { return d.name == name; }),
                   datasets.end());
  const auto output =
      kdem::fuzz::retarget_edits(before, b.image, std::vector<std::uint8_t>(data, data + size));
  std::ofstream(output_path, std::ios::binary)
      .write(reinterpret_cast<const char*>(output.data()), std::streamsize(output.size()));
  return true;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Base& b = base();
  if (retargeted(b, data, size))
    return 0;
  CheckpointImage edited = b.image;
  const auto touched = kdem::fuzz::apply_edits(edited, data, size);
  kdem::fuzz::write_edited(b.checkpoint_path, edited, touched, b.edited_path);
  bool taken = true;
  try {
    b.engine->read_checkpoint(b.edited_path);
  } catch (const std::runtime_error&) {
    taken = false;
  }
  if (!taken) {
    const kdem::ParticleSnapshot now = b.engine->snapshot();
    require(now.id == b.particles.id && now.position == b.particles.position &&
                now.velocity == b.particles.velocity,
            "a refused checkpoint changed the engine");
    return 0;
  }
  b.engine->advance(3);
  b.engine->check_health();
  b.engine->read_checkpoint(b.checkpoint_path);
  return 0;
}
