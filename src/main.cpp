// kdem command-line program.
#include <Kokkos_Core.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "../kernels/types.hpp"
#include "build_info.hpp"
#include "runner.hpp"

namespace {

const char* usage =
    "usage: kdem run SCENE.yaml [--out DIR] [--restart CHECKPOINT.h5] [--steps N] [--quiet]\n"
    "                [--kernel-times]\n"
    "       kdem check SCENE.yaml\n"
    "       kdem --version\n"
    "Kokkos options (e.g. --kokkos-threads=2) are passed to Kokkos.\n";

struct Arguments {
  std::string command;
  kdem::RunOptions run;
  bool ok = true;
};

Arguments parse(int argc, char** argv) {
  Arguments args;
  std::vector<std::string> words;
  for (int k = 1; k < argc; ++k)
    if (std::strncmp(argv[k], "--kokkos", 8) != 0)
      words.emplace_back(argv[k]);
  if (words.empty()) {
    args.ok = false;
    return args;
  }
  args.command = words[0];
  for (std::size_t k = 1; k < words.size(); ++k) {
    const std::string& w = words[k];
    auto value = [&]() -> std::string {
      if (k + 1 >= words.size()) {
        args.ok = false;
        return "";
      }
      return words[++k];
    };
    if (w == "--out")
      args.run.output_directory = value();
    else if (w == "--restart")
      args.run.restart_path = value();
    else if (w == "--steps")
      args.run.max_steps = std::stoll(value());
    else if (w == "--quiet")
      args.run.quiet = true;
    else if (w == "--kernel-times")
      args.run.kernel_times = true;
    else if (args.run.scene_path.empty() && w.rfind("--", 0) != 0)
      args.run.scene_path = w;
    else
      args.ok = false;
  }
  return args;
}

} // namespace

int main(int argc, char** argv) {
  Arguments args;
  try {
    args = parse(argc, argv);
  } catch (const std::exception&) {
    args.ok = false;
  }
  if (args.ok && args.command == "--version") {
    std::printf("kdem %s (%s)\n", KDEM_VERSION, kdem::git_hash());
    return 0;
  }
  if (!args.ok || (args.command != "run" && args.command != "check") ||
      args.run.scene_path.empty()) {
    std::fputs(usage, stderr);
    return 2;
  }
  // Threads pinned to cores unless the user chose otherwise (Kokkos warns when unset).
  setenv("OMP_PROC_BIND", "spread", 0);
  setenv("OMP_PLACES", "threads", 0);
  Kokkos::ScopeGuard kokkos(argc, argv);
  kdem::install_memory_space_check<kdem::MemSpace>();
  if (args.command == "check")
    return kdem::check_scene(args.run.scene_path);
  return kdem::run_scene(args.run);
}
