#!/usr/bin/env python3
"""CPU performance per shape and size: settled beds of spheres, ellipsoids, cylinders and cubes
(perf/bench_spheres.cpp --shape) from N = 1e3 up, on Serial, OpenMP with 1 thread and OpenMP
with 2 threads, in one session on one machine. Records particle-steps per second (median of
the repeats), parallel efficiency, time per stage (the fenced run of each benchmark, grouped by
perf/stages.py), bytes per particle in the engine's memory space (in total and by what they
hold), time per step against N, and at each shape's largest N the gain of the sort by cell
(OpenMP 2 threads, the same bed in shuffled order and never sorted).

    /usr/bin/python3 perf/bench_scaling.py                       # the full set
    /usr/bin/python3 perf/bench_scaling.py --shapes sphere --sizes 1e3 1e4 --repeat 3

Writes perf/results/bench_scaling.json (keeping the runs of shapes not measured this time, when
the file came from this machine) and docs/img/bench_scaling.png.
"""

import argparse
import json
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import run_bench  # noqa: E402
import stages as step_stages  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = [("Serial", "kdem_bench_serial", 1), ("OpenMP", "kdem_bench_openmp", 1),
           ("OpenMP", "kdem_bench_openmp", 2)]
DEFAULT_SIZES = {"sphere": [1e3, 1e4, 1e5, 1e6], "ellipsoid": [1e3, 1e4, 1e5],
                 "cylinder": [1e3, 1e4, 1e5], "cube": [1e3, 1e4, 1e5]}
# Work per timed run (particle-steps): spheres run ~8e6 per second and thread, superquadrics
# ~6e5, so that each timed run lasts a few seconds.
WORK = {"sphere": 2e7, "ellipsoid": 2e6, "cylinder": 2e6, "cube": 2e6, "poly_ellipsoid": 2e6,
        "poly_cube": 2e6, "pebble": 2e6, **{f"clump_{k}": 2e6 for k in range(1, 9)}}
CACHE_DIR = ROOT / "perf" / "cache"


# What the engine's Views hold, by label (the first pattern that matches wins).
MEMORY_GROUPS = [
    ("superquadric pair state", r"^pair_(midway|separat|turned)"),
    ("pair list", r"^(pair_|partner_id|tangential_spring|rolling_torque|reverse_|half_count)"),
    ("wall contacts", r"^wall_"),
    ("cell bins", r"^(bin|cell|slot|particle_in)"),
]


def memory_groups(by_label, particles):
    """Bytes per particle by what they hold; labels without a group count as particle state."""
    groups = {}
    for label, size in by_label.items():
        group = next((g for g, p in MEMORY_GROUPS if re.search(p, label)), "particles and other")
        groups[group] = groups.get(group, 0.0) + size / particles
    return groups


def run_config(bin_dir, backend, binary, threads, shape, n, args, unsorted=False):
    """The median record of one configuration, with its stage split and memory groups."""
    steps = max(20, int(round(WORK[shape] * args.work_scale / n)))
    extra = ["--shape", shape] + (["--unsorted"] if unsorted else [])
    record = run_bench.measured_run(
        lambda: run_bench.run_kdem(bin_dir / binary, int(n), steps, max(20, steps // 2),
                                   args.repeat, threads, CACHE_DIR, extra=extra), args)
    record.update({"backend": backend, "threads": threads})
    record["stage_seconds_per_step"] = stage_split(record)
    record["memory"]["groups_per_particle"] = memory_groups(
        record["memory"].get("bytes_by_label", {}), record["n"])
    return record


def settle_tile(bin_dir, shape):
    """Settles (or loads) the shape's cached tile with OpenMP on 2 threads, so that the first
    timed configuration (Serial) does not settle it on one core; the backends agree bit for bit,
    so the tile is the same."""
    run_bench.run_kdem(bin_dir / "kdem_bench_openmp", 1000, 1, 1, 0, 2, CACHE_DIR,
                       extra=["--shape", shape])


def stage_split(record):
    stages = step_stages.kernel_stages({"kernels": record["kernels"]})
    steps = record["steps"]
    return {s: t["seconds"] / steps for s, t in stages.items()}


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    shapes = sorted({r["shape"] for r in results}, key=list(DEFAULT_SIZES).index)
    results = [r for r in results if r["sorted_by_cell"]]
    fig, axes = plt.subplots(1, 4, figsize=(21, 4.8))
    for shape in shapes:
        for backend, _, threads in CONFIGS:
            rows = sorted((r for r in results if r["shape"] == shape and r["backend"] == backend
                           and r["threads"] == threads), key=lambda r: r["n"])
            if not rows:
                continue
            label = f"{shape}, {backend} {threads}"
            axes[0].loglog([r["n"] for r in rows], [r["particle_steps_per_s"] for r in rows],
                           "o-", label=label)
            axes[1].loglog([r["n"] for r in rows], [r["median_s"] / r["steps"] for r in rows],
                           "o-", label=label)
    axes[0].set(xlabel="particles N", ylabel="particle-steps per second", title="throughput")
    axes[1].set(xlabel="particles N", ylabel="seconds per step", title="time per step")
    largest = {}
    for r in results:
        if r["backend"] == "OpenMP" and r["threads"] == 2:
            if r["shape"] not in largest or r["n"] > largest[r["shape"]]["n"]:
                largest[r["shape"]] = r
    bottom = [0.0] * len(shapes)
    names = sorted({s for r in largest.values() for s in stage_split(r)})
    for stage in names:
        heights = [stage_split(largest[s]).get(stage, 0.0) / largest[s]["n"] * 1e9
                   if s in largest else 0.0 for s in shapes]
        axes[2].bar(shapes, heights, bottom=bottom, label=stage)
        bottom = [b + h for b, h in zip(bottom, heights)]
    axes[2].set(ylabel="ns per particle-step (fenced kernels)",
                title="stages at the largest N, OpenMP 2 threads")
    bottom = [0.0] * len(shapes)
    groups = sorted({g for r in largest.values() for g in r["memory"]["groups_per_particle"]})
    for group in groups:
        heights = [largest[s]["memory"]["groups_per_particle"].get(group, 0.0)
                   if s in largest else 0.0 for s in shapes]
        axes[3].bar(shapes, heights, bottom=bottom, label=group)
        bottom = [b + h for b, h in zip(bottom, heights)]
    axes[3].set(ylabel="bytes per particle", title="memory at the largest N, by what it holds")
    axes[0].legend(fontsize=6)
    axes[2].legend(fontsize=6)
    axes[3].legend(fontsize=6)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--shapes", nargs="+", default=list(DEFAULT_SIZES))
    parser.add_argument("--sizes", type=float, nargs="+", help="instead of the shape's default")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--work-scale", type=float, default=1.0)
    parser.add_argument("--no-sort-check", dest="sort_check", action="store_false",
                        help="skip the unsorted run at each shape's largest N")
    run_bench.add_quiet_arguments(parser)
    parser.add_argument("--bin", default=str(ROOT / "build" / "openmp" / "bin"))
    parser.add_argument("--out", default=str(ROOT / "perf" / "results" / "bench_scaling.json"))
    parser.add_argument("--plot", default=str(ROOT / "docs" / "img" / "bench_scaling.png"))
    args = parser.parse_args()
    bin_dir = Path(args.bin)
    # Runs of other shapes already in the output file are kept (one shape at a time can be
    # measured again); their machine must be this one.
    results, machine = [], run_bench.machine_info()
    if Path(args.out).exists():
        earlier = json.loads(Path(args.out).read_text())
        if earlier.get("machine") == machine:
            results = [r for r in earlier["runs"] if r["shape"] not in args.shapes]
        else:
            run_bench.log(f"{args.out} was measured on another machine: not kept")

    def save():  # after every shape, so that a stopped run keeps what it measured
        document = {"machine": machine, "repeat": args.repeat, "runs": results}
        out = Path(args.out)
        tmp = out.with_suffix(".json.tmp")
        tmp.write_text(json.dumps(document, indent=2) + "\n")
        tmp.replace(out)

    for shape in args.shapes:
        settle_tile(bin_dir, shape)
        for n in sorted(args.sizes or DEFAULT_SIZES[shape]):
            by_config = {}
            for backend, binary, threads in CONFIGS:
                record = run_config(bin_dir, backend, binary, threads, shape, n, args)
                results.append(record)
                by_config[(backend, threads)] = record
                run_bench.log(f"{shape} N={int(n)} {backend} {threads}: "
                              f"{record['particle_steps_per_s']:.3g} particle-steps/s, "
                              f"{record['memory']['bytes_per_particle']:.0f} B/particle")
            one, two = by_config[("OpenMP", 1)], by_config[("OpenMP", 2)]
            two["parallel_efficiency"] = two["particle_steps_per_s"] / (
                2 * one["particle_steps_per_s"])
        if args.sort_check:  # `two` is the sorted run at the largest N
            record = run_config(bin_dir, "OpenMP", "kdem_bench_openmp", 2, shape, n, args,
                                unsorted=True)
            two["sort_speedup"] = two["particle_steps_per_s"] / record["particle_steps_per_s"]
            results.append(record)
            run_bench.log(f"{shape} N={int(n)} unsorted: {record['particle_steps_per_s']:.3g} "
                          f"particle-steps/s; the sort gives {two['sort_speedup']:.2f}x")
        save()
    plot(results, Path(args.plot))
    for r in results:
        if "parallel_efficiency" in r:
            run_bench.log(f"{r['shape']} N={r['n']}: parallel efficiency "
                          f"{r['parallel_efficiency']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
