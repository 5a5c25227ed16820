#!/usr/bin/env python3
"""Mesh walls against their size: the settled sphere bed of perf/bench_spheres.cpp in its open
box given as the box's five planes, as a coarse mesh (about ten triangles) and as a fine mesh
(about 1e5 triangles), OpenMP with 2 threads, in rounds (planes, coarse, fine, planes, ...) so
that the configurations are measured side by side. Each run: W untimed warm-up steps, then R
timed runs of M steps (median); then the same bed with the lists rebuilt at every step, which
times the wall broad phase (the candidate list: kernels kdem::wall_candidate_*) at every step.

    /usr/bin/python3 perf/bench_mesh_walls.py                 # 1e5 spheres, 3 rounds
    /usr/bin/python3 perf/bench_mesh_walls.py --n 1e4 --rounds 1

Writes perf/results/bench_mesh_walls.json (per configuration the median over the rounds of
particle-steps per second, seconds per step by stage, broad-phase nanoseconds per particle and
the ratios fine / coarse) and docs/img/bench_mesh_walls.png.
"""

import argparse
import json
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import run_bench  # noqa: E402
import stages as step_stages  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CACHE_DIR = ROOT / "perf" / "cache"
BROAD_PHASE = ("kdem::wall_candidate_count", "kdem::wall_candidate_fill")


def configurations(args):
    return [("planes", []), ("coarse mesh", ["--mesh-walls", str(int(args.coarse))]),
            ("fine mesh", ["--mesh-walls", str(int(args.fine))])]


def broad_phase_ns_per_particle(record):
    seconds = sum(record["kernels"].get(k, {}).get("seconds", 0.0) for k in BROAD_PHASE)
    return seconds / (record["steps"] * record["n"]) * 1e9


def stage_seconds_per_step(record):
    stages = step_stages.kernel_stages({"kernels": record["kernels"]})
    return {s: t["seconds"] / record["steps"] for s, t in stages.items()}


def measure(args, binary, extra, rebuild):
    steps = args.rebuild_steps if rebuild else args.steps
    return run_bench.measured_run(
        lambda: run_bench.run_kdem(binary, int(args.n), steps, args.warmup, args.repeat, 2,
                                   CACHE_DIR, rebuild=rebuild, extra=extra), args)


def summary(runs):
    """Medians over the rounds of one configuration."""
    stages = sorted({s for r in runs for s in r["stage_seconds_per_step"]})
    return {
        "wall_triangles": runs[0]["wall_triangles"],
        "wall_candidates_per_wall_contact": statistics.median(
            r["memory"]["bytes_by_label"].get("wall_candidate_element", 0) / 4
            / max(1, r["wall_contacts"]) for r in runs),
        "particle_steps_per_s": statistics.median(r["particle_steps_per_s"] for r in runs),
        "stage_seconds_per_step": {
            s: statistics.median(r["stage_seconds_per_step"].get(s, 0.0) for r in runs)
            for s in stages},
        "broad_phase_ns_per_particle": statistics.median(
            r["broad_phase_ns_per_particle"] for r in runs),
        "rounds": len(runs),
    }


def plot(result, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = list(result["configurations"])
    configs = [result["configurations"][k] for k in names]
    labels = [f"{k}\n{c['wall_triangles']} triangles" if c["wall_triangles"] else k
              for k, c in zip(names, configs)]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    axes[0].bar(labels, [c["particle_steps_per_s"] for c in configs])
    axes[0].set(ylabel="particle-steps per second", title="throughput (lists as needed)")
    bottom = [0.0] * len(configs)
    for stage in sorted({s for c in configs for s in c["stage_seconds_per_step"]}):
        heights = [c["stage_seconds_per_step"].get(stage, 0.0) / result["n"] * 1e9
                   for c in configs]
        axes[1].bar(labels, heights, bottom=bottom, label=stage)
        bottom = [b + h for b, h in zip(bottom, heights)]
    axes[1].set(ylabel="ns per particle-step (fenced kernels)", title="stages")
    axes[1].legend(fontsize=6)
    axes[2].bar(labels, [c["broad_phase_ns_per_particle"] for c in configs])
    axes[2].set(ylabel="ns per particle and build", title="wall broad phase (rebuilt every step)")
    fig.suptitle(f"{int(result['n'])} spheres, OpenMP 2 threads, {result['machine']['cpu_model']}",
                 fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=float, default=1e5)
    parser.add_argument("--fine", type=float, default=1e5, help="triangles of the fine mesh")
    parser.add_argument("--coarse", type=float, default=10, help="triangles of the coarse mesh")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--rebuild-steps", type=int, default=20)
    parser.add_argument("--warmup", type=int, default=100)
    parser.add_argument("--repeat", type=int, default=3)
    run_bench.add_quiet_arguments(parser)
    parser.add_argument("--bin", default=str(ROOT / "build" / "openmp" / "bin"))
    parser.add_argument("--out", default=str(ROOT / "perf" / "results" / "bench_mesh_walls.json"))
    parser.add_argument("--plot", default=str(ROOT / "docs" / "img" / "bench_mesh_walls.png"))
    args = parser.parse_args()
    binary = Path(args.bin) / "kdem_bench_openmp"
    runs = {name: [] for name, _ in configurations(args)}
    for round_index in range(args.rounds):
        for name, extra in configurations(args):
            record = measure(args, binary, extra, rebuild=False)
            rebuilt = measure(args, binary, extra, rebuild=True)
            record["stage_seconds_per_step"] = stage_seconds_per_step(record)
            record["broad_phase_ns_per_particle"] = broad_phase_ns_per_particle(rebuilt)
            record["rebuild_every_step_run"] = rebuilt
            runs[name].append(record)
            run_bench.log(f"round {round_index + 1}, {name} ({record['wall_triangles']} "
                          f"triangles): {record['particle_steps_per_s']:.3g} particle-steps/s, "
                          f"broad phase {record['broad_phase_ns_per_particle']:.1f} ns/particle")
    result = {"machine": run_bench.machine_info(), "n": args.n, "threads": 2,
              "steps": args.steps, "repeat": args.repeat, "warmup": args.warmup,
              "configurations": {name: summary(r) for name, r in runs.items()}, "runs": runs}
    c = result["configurations"]
    result["throughput_ratio_coarse_over_fine"] = (c["coarse mesh"]["particle_steps_per_s"]
                                                   / c["fine mesh"]["particle_steps_per_s"])
    result["throughput_ratio_planes_over_fine"] = (c["planes"]["particle_steps_per_s"]
                                                   / c["fine mesh"]["particle_steps_per_s"])
    result["broad_phase_ratio_fine_over_coarse"] = (c["fine mesh"]["broad_phase_ns_per_particle"]
                                                    / c["coarse mesh"]["broad_phase_ns_per_particle"])
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    tmp.replace(out)
    plot(result, Path(args.plot))
    run_bench.log(f"throughput coarse / fine {result['throughput_ratio_coarse_over_fine']:.2f}, "
                  f"broad phase fine / coarse {result['broad_phase_ratio_fine_over_coarse']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
