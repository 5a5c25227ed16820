#!/usr/bin/env python3
"""The book's Table 6.4 redone on the CPU: hopper discharge of spheres, cylinders and cubes of
equal volume, wall time per shape and N, cost relative to spheres, and mean discharge rates.

usage: run_table.py [--kdem build/openmp/bin/kdem] [--threads 2] [--counts 1000,3162]
                    [--shapes sphere,cylinder,cube] [--out out/hopper_shapes]
                    [--json perf/results/hopper_shapes.json] [--png docs/img/hopper_shapes.png]
                    [--segment-steps S] [--plot-only]

Each run is one `kdem run` of a scene from make_scenes.py (fill for 0.25 s, then discharge for
0.5 s). The wall time is the run's own (run.json: engine time without start-up and output).
The mean discharge rate is the least-squares slope of the discharged mass between 10 % and
70 % of the particles' total mass (after the start-up transient, before the bed runs dry).

--segment-steps S runs each case as segments of S steps, each restarted from the checkpoint of
the one before (restarts are bit for bit), in OUT/<case>/segment_000, _001, ...; the wall time
is the sum of the segments' engine times. Segments that have finished (their run.json exists)
are kept, so a run stopped between segments continues where it stopped when called again.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
BOOK_GPU = {"sphere": 1.0, "cylinder": 1.56, "cube": 2.69}  # Table 6.4, GV100, N = 31.6k
BOOK_CPU_10K = {"sphere": 27963.0, "cylinder": 87431.0, "cube": 115949.0}  # s, 1 core


def read_series(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [float(r["time"]) for r in rows], [float(r["discharged_mass"]) for r in rows]


def slope(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def discharge_rate(time, mass, total_mass):
    window = [(t, m) for t, m in zip(time, mass) if 0.1 * total_mass <= m <= 0.7 * total_mass]
    if len(window) < 3:
        return float("nan")
    return slope([t for t, _ in window], [m for _, m in window])


def run_case(kdem, scene, out_dir, threads, extra=()):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    subprocess.run([kdem, "run", scene, "--out", out_dir, "--quiet"] + list(extra), check=True,
                   env=env)


def finished(summary, scene):
    """Whether a segment's run.json reached the scene's duration."""
    with open(scene) as f:
        values = dict(line.split(":", 1) for line in f if line.startswith(("time_step:", "duration:")))
    dt, duration = float(values["time_step"]), float(values["duration"])
    return summary["simulated_time"] >= duration - 0.5 * dt


def run_segments(kdem, scene, out_dir, threads, segment_steps):
    """Runs the case in restarted segments; returns their directories in order."""
    segments = []
    while True:
        segment = os.path.join(out_dir, "segment_%03d" % len(segments))
        summary_path = os.path.join(segment, "run.json")
        if not os.path.exists(summary_path):
            extra = ["--steps", str(segment_steps)]
            if segments:
                extra += ["--restart", os.path.join(segments[-1], "checkpoint.h5")]
            run_case(kdem, scene, segment, threads, extra)
        segments.append(segment)
        with open(summary_path) as f:
            if finished(json.load(f), scene):
                return segments


def total_mass(out_dir, summary):
    # Every particle in the scene: those still in plus those discharged.
    import h5py

    with h5py.File(os.path.join(out_dir, "checkpoint.h5"), "r") as f:
        left = float(f["particles/mass"][...].sum()) if f["particles/mass"].size else 0.0
    return left + summary["discharged_mass"]


def collect(shape, count, out_dirs):
    """One record from the run directories of a case (one, or its segments in order)."""
    summaries = []
    time, mass = [], []
    for out_dir in out_dirs:
        with open(os.path.join(out_dir, "run.json")) as f:
            summaries.append(json.load(f))
        t, m = read_series(os.path.join(out_dir, "series.csv"))
        keep = [k for k in range(len(t)) if not time or t[k] > time[-1]]
        time += [t[k] for k in keep]
        mass += [m[k] for k in keep]
    last = summaries[-1]
    everything = total_mass(out_dirs[-1], last)
    wall = sum(s["wall_seconds"] for s in summaries)
    steps = sum(s["steps"] for s in summaries)
    particle_steps = sum(s["particle_steps_per_second"] * s["wall_seconds"] for s in summaries)
    return {
        "shape": shape, "count": count, "wall_seconds": wall, "steps": steps,
        "segments": len(summaries), "threads": last["threads"], "backend": last["backend"],
        "particle_steps_per_second": particle_steps / wall if wall > 0 else 0.0,
        "narrow_phase_failures": sum(s["narrow_phase_failures"] for s in summaries),
        "narrow_phase_evaluations": sum(s["extra"].get("narrow_phase_evaluations", 0)
                                        for s in summaries),
        "narrow_phase_fallbacks": sum(s["extra"].get("narrow_phase_fallbacks", 0)
                                      for s in summaries),
        "discharged_fraction": last["discharged_mass"] / everything,
        "discharge_rate": discharge_rate(time, mass, everything),
        "series_time": time, "series_mass": mass,
    }


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def print_table(results):
    by_key = {(r["shape"], r["count"]): r for r in results}
    counts = sorted({r["count"] for r in results})
    print("| N | shape | wall time (s) | cost / spheres | particle-steps/s | mean rate (g/s) | "
          "discharged | narrow-phase evaluations | fallbacks | failures |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for n in counts:
        sphere = by_key.get(("sphere", n))
        for shape in ("sphere", "cylinder", "cube"):
            r = by_key.get((shape, n))
            if not r:
                continue
            ratio = r["wall_seconds"] / sphere["wall_seconds"] if sphere else float("nan")
            print("| %d | %s | %.1f | %.2f | %.3g | %.1f | %.0f %% | %d | %d | %d |" % (
                n, shape, r["wall_seconds"], ratio, r["particle_steps_per_second"],
                1e3 * r["discharge_rate"], 100 * r["discharged_fraction"],
                r["narrow_phase_evaluations"], r["narrow_phase_fallbacks"],
                r["narrow_phase_failures"]))


def plot(results, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    largest = max(r["count"] for r in results)
    for r in results:
        if r["count"] == largest:
            left.plot(r["series_time"], [1e3 * m for m in r["series_mass"]], label=r["shape"])
    left.axvline(0.25, color="grey", ls=":", lw=0.8)
    left.set_xlabel("time (s)")
    left.set_ylabel("discharged mass (g)")
    left.set_title("discharge, N = %d (gate opens at 0.25 s)" % largest)
    left.legend()
    counts = sorted({r["count"] for r in results})
    shapes = ("cylinder", "cube")
    width = 0.35
    by_key = {(r["shape"], r["count"]): r for r in results}
    for k, shape in enumerate(shapes):
        ratios = [by_key[(shape, n)]["wall_seconds"] / by_key[("sphere", n)]["wall_seconds"]
                  if (shape, n) in by_key and ("sphere", n) in by_key else float("nan")
                  for n in counts]
        right.bar([i + (k - 0.5) * width for i in range(len(counts))], ratios, width,
                  label="kdem (measured, CPU): " + shape)
        right.axhline(BOOK_CPU_10K[shape] / BOOK_CPU_10K["sphere"], ls="--", lw=0.8,
                      color="C%d" % k, label="book CPU, N = 10k: %s" % shape)
        right.axhline(BOOK_GPU[shape], ls=":", lw=0.8, color="C%d" % k,
                      label="book GPU, N = 31.6k: %s" % shape)
    right.set_xticks(range(len(counts)))
    right.set_xticklabels([str(n) for n in counts])
    right.set_xlabel("N")
    right.set_ylabel("wall time / spheres' wall time")
    right.set_title("cost relative to spheres")
    right.legend(fontsize=7)
    fig.tight_layout()
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, png)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kdem", default=os.path.join(ROOT, "build/openmp/bin/kdem"))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--counts", default="1000,3162")
    parser.add_argument("--shapes", default="sphere,cylinder,cube")
    parser.add_argument("--out", default=os.path.join(ROOT, "out/hopper_shapes"))
    parser.add_argument("--json", default=os.path.join(ROOT, "perf/results/hopper_shapes.json"))
    parser.add_argument("--png", default=os.path.join(ROOT, "docs/img/hopper_shapes.png"))
    parser.add_argument("--segment-steps", type=int, default=0,
                        help="run each case in restarted segments of this many steps")
    parser.add_argument("--plot-only", action="store_true", help="re-plot the JSON file")
    args = parser.parse_args()

    if args.plot_only:
        with open(args.json) as f:
            results = json.load(f)["runs"]
    else:
        scenes = os.path.join(args.out, "scenes")
        subprocess.run([sys.executable, os.path.join(HERE, "make_scenes.py"), scenes,
                        "--counts", args.counts, "--shapes", args.shapes], check=True,
                       stdout=subprocess.DEVNULL)
        results = []
        for count in (int(c) for c in args.counts.split(",")):
            for shape in args.shapes.split(","):
                out_dir = os.path.join(args.out, "%s_%d" % (shape, count))
                scene = os.path.join(scenes, "%s_%d.yaml" % (shape, count))
                if args.segment_steps > 0:
                    out_dirs = run_segments(args.kdem, scene, out_dir, args.threads,
                                            args.segment_steps)
                else:
                    run_case(args.kdem, scene, out_dir, args.threads)
                    out_dirs = [out_dir]
                results.append(collect(shape, count, out_dirs))
                print("done: %s N = %d in %.1f s" % (shape, count, results[-1]["wall_seconds"]),
                      flush=True)
        record = {"machine": cpu_name(), "cores": os.cpu_count(), "runs": results}
        tmp = args.json + ".tmp"
        with open(tmp, "w") as f:
            json.dump(record, f, indent=1)
        os.replace(tmp, args.json)
    print_table(results)
    plot(results, args.png)


if __name__ == "__main__":
    main()
