#!/usr/bin/env python3
"""Two builds of the shape benchmark side by side: the settled beds of perf/bench_scaling.py
(perf/bench_spheres.cpp --shape S) at one N, OpenMP with a given number of threads, program A
and program B in turn in each round, every shape in the same session. Reports per shape and
program the median particle-steps per second over the rounds (each run itself the median of
--repeat timed runs) and the rate of the fastest timed run (which a disturbance of the machine
can only slow), the cost of a particle-step relative to the sphere bed of the same program, and
B's gain over A (by medians, by fastest runs, and per round).

    /usr/bin/python3 perf/bench_shapes_ab.py --a OLD/bin/kdem_bench_openmp \\
        --b build/openmp/bin/kdem_bench_openmp --label-a before --label-b after \\
        --n 1e5 --rounds 3 --json perf/results/NAME.json

The beds are settled once (the first program to need one) and cached in --cache-dir, so both
programs start from the same bed. One program with and without a setting: --a and --b the same,
--extra-a or --extra-b its options (e.g. --extra-a=--pair-types). --summarize FILE.json
recomputes the summary of an earlier results file.
"""

import argparse
import json
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_scaling  # noqa: E402
import run_bench  # noqa: E402
import stages as step_stages  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def one_run(binary, shape, n, args, extra):
    steps = max(20, int(round(bench_scaling.WORK[shape] / n)))
    record = run_bench.measured_run(
        lambda: run_bench.run_kdem(binary, n, steps, max(20, steps // 2), args.repeat,
                                   args.threads, args.cache_dir,
                                   extra=["--shape", shape, *extra]), args)
    stages = step_stages.kernel_stages({"kernels": record["kernels"]})
    record["stage_ns_per_particle_step"] = {
        s: 1e9 * t["seconds"] / (record["steps"] * record["n"]) for s, t in stages.items()}
    return record


def recorded_name(program):
    """How a results file names a program: its path in the checkout, or its file name (a
    folder outside the checkout says nothing to a reader of the file)."""
    try:
        return str(program.relative_to(ROOT))
    except ValueError:
        return program.name


def fastest_rate(runs):
    """Particle-steps per second of the fastest timed run: a disturbance of the machine can only
    slow a run, so on a noisy machine this scatters less than the median."""
    return max(r["n"] * r["steps"] / min(r["times_s"]) for r in runs)


def summary(runs, labels, shapes):
    def of(label, shape):
        return [r for r in runs if r["label"] == label and r["shape"] == shape]

    medians = {label: {shape: statistics.median(r["particle_steps_per_s"] for r in of(label, shape))
                       for shape in shapes} for label in labels}
    fastest = {label: {shape: fastest_rate(of(label, shape)) for shape in shapes}
               for label in labels}
    rows = []
    for shape in shapes:
        row = {"shape": shape}
        for label in labels:
            row[label] = {"particle_steps_per_s": medians[label][shape],
                          "fastest_particle_steps_per_s": fastest[label][shape]}
            if "sphere" in shapes:
                row[label]["cost_relative_to_sphere"] = (
                    medians[label]["sphere"] / medians[label][shape])
                row[label]["fastest_cost_relative_to_sphere"] = (
                    fastest[label]["sphere"] / fastest[label][shape])
        row["gain_b_over_a"] = medians[labels[1]][shape] / medians[labels[0]][shape]
        row["gain_b_over_a_fastest"] = fastest[labels[1]][shape] / fastest[labels[0]][shape]
        a_rounds = {r["round"]: r["particle_steps_per_s"] for r in of(labels[0], shape)}
        row["gain_b_over_a_per_round"] = [r["particle_steps_per_s"] / a_rounds[r["round"]]
                                          for r in of(labels[1], shape) if r["round"] in a_rounds]
        rows.append(row)
    return rows


def print_summary(result):
    for row in result["summary"]:
        cells = "  ".join(f"{label} {row[label]['particle_steps_per_s']:.3g}/s"
                          + (f" ({row[label]['cost_relative_to_sphere']:.2f} x sphere)"
                             if "cost_relative_to_sphere" in row[label] else "")
                          for label in result["labels"])
        print(f"{row['shape']:9s} {cells}  gain {row['gain_b_over_a']:.3f} "
              f"(fastest runs: {row['gain_b_over_a_fastest']:.3f})")


def write_json(result, path):
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(result, indent=1) + "\n")
    tmp.replace(path)


def summarize_again(path):
    """Recomputes the summary of a results file from its runs (after a change of the summary)."""
    result = json.loads(path.read_text())
    shapes = list(dict.fromkeys(r["shape"] for r in result["runs"]))
    result["summary"] = summary(result["runs"], result["labels"], shapes)
    write_json(result, path)
    print_summary(result)
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--summarize", metavar="FILE.json",
                        help="only recompute the summary of an existing results file")
    parser.add_argument("--a", help="kdem_bench_openmp program A")
    parser.add_argument("--b", help="kdem_bench_openmp program B")
    parser.add_argument("--label-a", default="a")
    parser.add_argument("--label-b", default="b")
    parser.add_argument("--extra-a", default="", help="further options of program A, one string")
    parser.add_argument("--extra-b", default="", help="further options of program B, one string")
    parser.add_argument("--shapes", nargs="+", default=list(bench_scaling.DEFAULT_SIZES))
    parser.add_argument("--n", type=float, default=1e5)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per program run")
    parser.add_argument("--cache-dir", default=str(bench_scaling.CACHE_DIR))
    parser.add_argument("--json", help="write the runs and the summary here")
    run_bench.add_quiet_arguments(parser)
    args = parser.parse_args()
    if args.summarize:
        return summarize_again(Path(args.summarize))
    if not (args.a and args.b and args.json):
        parser.error("--a, --b and --json are required (or --summarize FILE.json)")
    programs = {args.label_a: Path(args.a).resolve(), args.label_b: Path(args.b).resolve()}
    extras = {args.label_a: args.extra_a.split(), args.label_b: args.extra_b.split()}
    n = int(args.n)
    runs = []
    for shape in args.shapes:
        for round_index in range(args.rounds):
            for label, binary in programs.items():
                record = one_run(binary, shape, n, args, extras[label])
                record.update({"label": label, "program": recorded_name(binary), "shape": shape,
                               "round": round_index})
                runs.append(record)
                run_bench.log(f"{shape:9s} {label:8s} round {round_index}: "
                              f"{record['particle_steps_per_s']:.4g} particle-steps/s")
    result = {"benchmark": "bench_shapes_ab", "machine": run_bench.machine_info(), "n": n,
              "threads": args.threads, "rounds": args.rounds, "repeat": args.repeat,
              "labels": [args.label_a, args.label_b],
              "programs": {k: recorded_name(v) for k, v in programs.items()},
              "extra_options": extras,
              "summary": summary(runs, [args.label_a, args.label_b], args.shapes), "runs": runs}
    write_json(result, Path(args.json))
    print_summary(result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
