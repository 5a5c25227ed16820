#!/usr/bin/env python3
"""Instructions and FP64 operations per particle-step, per stage of the time step, counted with
valgrind's callgrind on fixed small scenes (perf/callgrind/*.yaml): a measure of the engine's
cost that does not depend on the machine's load, for a baseline and `make perf-check`.

Each scene is settled natively (--settle-steps, the OpenMP program: bit-identical to Serial),
then the Serial program runs --steps more steps from that checkpoint under callgrind, collecting
only inside kdem::Engine::step. The step's cost is split into stages by the functions its call
tree passes through (perf/stages.py, perf/callgrind_profile.py). The same steps also run
natively with --kernel-times, for the kernel launches per step and the time per stage.

  perf/callgrind_stages.py --bin build/openmp/bin --out perf/results/callgrind_stages.json
  perf/callgrind_stages.py --bin build/openmp/bin --check perf/baseline/callgrind_stages.json
  perf/callgrind_stages.py --bin build/openmp/bin --write-baseline perf/baseline/callgrind_stages.json
  perf/callgrind_stages.py --bin OLD/bin --settle-with build/openmp/bin/kdem --out before.json

--check fails (exit 1) when a scene's instructions per particle-step, or those of a stage that
holds at least 5 % of them, exceed the baseline by more than --limit (5 %).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import callgrind_profile  # noqa: E402
import run_bench  # noqa: E402
import stages as step_stages  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent

SCENES = {
    "spheres": {"scene": "perf/callgrind/spheres.yaml", "settle_steps": 40000, "steps": 300},
    "cubes": {"scene": "perf/callgrind/cubes.yaml", "settle_steps": 40000, "steps": 100},
    "ellipsoids": {"scene": "perf/callgrind/ellipsoids.yaml", "settle_steps": 50000, "steps": 100},
    "cylinders": {"scene": "perf/callgrind/cylinders.yaml", "settle_steps": 40000, "steps": 100},
}
# `make perf-check`: spheres and one superquadric scene.
CHECK_SCENES = "spheres,cubes"


def host_arch(bin_dir):
    """The instruction-set flags the build was made with (written by CMake beside its bin/)."""
    path = bin_dir.parent / "host_arch.txt"
    return path.read_text().strip() if path.exists() else "unknown"


def machine(bin_dir):
    info = run_bench.machine_info()
    valgrind = subprocess.run(["valgrind", "--version"], capture_output=True, text=True).stdout
    return {"cpu": info["cpu_model"], "compiler": info["compiler"], "valgrind": valgrind.strip(),
            "host_arch": host_arch(bin_dir)}


def run(command, **kwargs):
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if result.returncode != 0:
        sys.exit(f"callgrind_stages: command failed ({result.returncode}): {' '.join(command)}\n"
                 f"{result.stderr[-3000:]}")
    return result


def measure_scene(name, spec, bin_dir, work, settler=None):
    serial = bin_dir / "kdem-serial"
    if settler is None:
        settler = bin_dir / "kdem" if (bin_dir / "kdem").exists() else serial
    scene = ROOT / spec["scene"]
    settled = work / f"{name}_settled"
    run([str(settler), "run", str(scene), "--out", str(settled), "--steps",
         str(spec["settle_steps"]), "--quiet", "--kokkos-threads=2"])
    measured = work / f"{name}_measured"
    profile_path = work / f"{name}.callgrind"
    run(["valgrind", "--tool=callgrind", "--dump-instr=yes", "--collect-atstart=no",
         "--toggle-collect=kdem::Engine::step()", f"--callgrind-out-file={profile_path}",
         str(serial), "run", str(scene), "--out", str(measured), "--restart",
         str(settled / "checkpoint.h5"), "--steps", str(spec["steps"]), "--quiet"])
    timed = work / f"{name}_timed"
    run([str(serial), "run", str(scene), "--out", str(timed), "--restart",
         str(settled / "checkpoint.h5"), "--steps", str(spec["steps"]), "--quiet",
         "--kernel-times"])
    kernel_times = json.loads((timed / "kernel_times.json").read_text())
    summary = json.loads((measured / "run.json").read_text())
    particle_steps = summary["particle_steps_per_second"] * summary["wall_seconds"]
    particle_steps = round(particle_steps)
    profile = callgrind_profile.Profile(profile_path)
    root = callgrind_profile.find_function(profile, r"^kdem::Engine::step\(\)")
    costs = callgrind_profile.stage_costs(profile, root, step_stages.stage_of_function,
                                         callgrind_profile.Disassembly())
    total = sum(c["instructions"] for c in costs.values())
    stages = {}
    for stage, c in sorted(costs.items(), key=lambda item: -item[1]["instructions"]):
        stages[stage] = {
            "instructions_per_particle_step": c["instructions"] / particle_steps,
            "fp64_per_particle_step": c["fp64"] / particle_steps,
            "share": c["instructions"] / total if total else 0.0,
        }
    extra = summary.get("extra", {})
    return {
        "scene": spec["scene"],
        "particles": kernel_times["particles"],
        "pair_candidates": extra.get("pair_candidates", 0),
        "pair_contacts": extra.get("pair_contacts", 0),
        "wall_candidates": extra.get("wall_candidates", 0),
        "bytes_per_particle": kernel_times["memory"]["bytes_per_particle"],
        "kernel_launches_per_step": sum(k["launches"] for k in kernel_times["kernels"].values())
        / spec["steps"],
        "serial_stage_seconds_per_step": {
            stage: t["seconds"] / spec["steps"]
            for stage, t in step_stages.kernel_stages(kernel_times).items()},
        "kernel_times": kernel_times["kernels"],
        "settle_steps": spec["settle_steps"],
        "steps": spec["steps"],
        "particle_steps": particle_steps,
        "narrow_phase_evaluations": extra.get("narrow_phase_evaluations", 0),
        "narrow_phase_mean_iterations": extra.get("narrow_phase_mean_iterations", 0),
        "contacts": summary.get("contacts", 0),
        "instructions_per_particle_step": total / particle_steps,
        "fp64_per_particle_step": sum(c["fp64"] for c in costs.values()) / particle_steps,
        "stages": stages,
    }


def compare(current, baseline, limit):
    """Lines of the report and whether it passes."""
    lines, passed = [], True
    if baseline.get("machine", {}).get("cpu") != current["machine"]["cpu"]:
        lines.append(f"note: baseline from '{baseline.get('machine', {}).get('cpu')}', "
                     f"this machine is '{current['machine']['cpu']}' (libm variants differ)")
    same_arch = baseline.get("machine", {}).get("host_arch") == current["machine"]["host_arch"]
    if not same_arch:
        lines.append(f"note: baseline built with '{baseline.get('machine', {}).get('host_arch')}', "
                     f"this build with '{current['machine']['host_arch']}' (KDEM_HOST_ARCH): "
                     "the counts are shown, not checked")
    for name, scene in current["scenes"].items():
        base = baseline["scenes"].get(name)
        if base is None:
            lines.append(f"{name}: not in the baseline")
            continue
        rows = [("total", scene["instructions_per_particle_step"],
                 base["instructions_per_particle_step"], 1.0)]
        for stage, s in scene["stages"].items():
            b = base["stages"].get(stage, {}).get("instructions_per_particle_step", 0.0)
            rows.append((stage, s["instructions_per_particle_step"], b, s["share"]))
        for stage, now, before, share in rows:
            change = (now / before - 1.0) if before > 0 else float("inf")
            failing = same_arch and change > limit and share >= 0.05
            passed = passed and not failing
            lines.append(f"{name:8s} {stage:24s} {now:12.1f} {before:12.1f} {100 * change:+7.2f} %"
                         f"{'  REGRESSION' if failing else ''}")
    return lines, passed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bin", default="build/openmp/bin", help="folder of kdem and kdem-serial")
    parser.add_argument("--scenes", default=",".join(SCENES),
                        help=f"comma-separated, of {list(SCENES)} (perf-check: {CHECK_SCENES})")
    parser.add_argument("--out", help="write the counts (JSON) here")
    parser.add_argument("--check", help="compare with this baseline; exit 1 on a regression")
    parser.add_argument("--write-baseline", help="write the counts as the new baseline")
    parser.add_argument("--limit", type=float, default=0.05)
    parser.add_argument("--work", help="keep the runs and profiles in this folder")
    parser.add_argument("--settle-with", help="settle the scenes with this kdem program (default: "
                        "the one in --bin), so that two builds are counted from the same state")
    args = parser.parse_args()
    if shutil.which("valgrind") is None:
        sys.exit("callgrind_stages: valgrind not found (apt install valgrind)")
    bin_dir = (ROOT / args.bin).resolve() if not os.path.isabs(args.bin) else Path(args.bin)
    if not (bin_dir / "kdem-serial").exists():
        sys.exit(f"callgrind_stages: {bin_dir}/kdem-serial not found (build the openmp preset)")
    names = [n for n in args.scenes.split(",") if n]
    unknown = [n for n in names if n not in SCENES]
    if unknown:
        sys.exit(f"callgrind_stages: unknown scene(s) {unknown}; known: {list(SCENES)}")
    with tempfile.TemporaryDirectory(prefix="kdem-callgrind-") as tmp:
        work = Path(args.work) if args.work else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        current = {"machine": machine(bin_dir), "stages": step_stages.FUNCTION_STAGES,
                   "scenes": {n: measure_scene(n, SCENES[n], bin_dir, work.resolve(),
                                               args.settle_with and Path(args.settle_with).resolve())
                              for n in names}}
    text = json.dumps(current, indent=2) + "\n"
    for target in (args.out, args.write_baseline):
        if target:
            path = Path(target)
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp_path = path.with_suffix(path.suffix + ".tmp")
            tmp_path.write_text(text)
            tmp_path.replace(path)
    for name, scene in current["scenes"].items():
        print(f"{name}: {scene['instructions_per_particle_step']:.0f} instructions and "
              f"{scene['fp64_per_particle_step']:.0f} FP64 operations per particle-step")
    if args.check:
        baseline = json.loads(Path(args.check).read_text())
        lines, passed = compare(current, baseline, args.limit)
        print(f"{'scene':8s} {'stage':24s} {'now':>12s} {'baseline':>12s}  change "
              "(instructions per particle-step)")
        print("\n".join(lines))
        if not passed:
            print(f"perf-check: FAILED (more than {100 * args.limit:.0f} % above the baseline)")
            return 1
        print("perf-check: passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
