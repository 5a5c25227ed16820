#pragma once
// The run driver behind `kdem run`: loads a scene, runs it, writes frames, series, checkpoints
// and the run summary.
#include <cstdint>
#include <string>

namespace kdem {

struct RunOptions {
  std::string scene_path;
  std::string output_directory; // overrides the scene's output.directory when set
  std::string restart_path;     // continue from this checkpoint
  std::int64_t max_steps = -1;  // stop after this many steps of this invocation (tests)
  bool quiet = false;
  bool kernel_times = false; // write kernel_times.json: time and launches per kernel label
};

// Returns the process exit code; prints errors to stderr. Nothing is written when the scene
// cannot be loaded or set up.
int run_scene(const RunOptions& options);

// `kdem check`: loads and sets up the scene, prints a summary and the time-step advice.
int check_scene(const std::string& scene_path);

} // namespace kdem
