#!/usr/bin/env python3
"""Two kdem programs, or one program with two scene settings (a change measured with and
without), side by side on the settled scenes of perf/callgrind/: each scene is settled once
with program A, then both variants run the same restart segment alternately, --repeat times;
reports the median engine wall time (run.json, without start-up and output) and whether the
two end states are bit-identical.

  perf/bench_ab.py --a OLD/kdem --b build/openmp/bin/kdem --label-a before --label-b after \\
      --scenes cubes,spheres --steps 2000 --repeat 5 --json perf/results/NAME.json
  perf/bench_ab.py --a build/openmp/bin/kdem --b build/openmp/bin/kdem \\
      --append-b "superquadric_contact: {compact_candidates: false}" ...

--append-a/--append-b add YAML lines to the scene of that variant (top-level keys the scene
does not have yet). A --scenes entry ending in .yaml is a scene file, settled --settle steps.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SETTLE_STEPS = {"spheres": 40000, "cubes": 40000, "cylinders": 40000, "ellipsoids": 50000}


def run(program, scene, out_dir, threads, extra):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    subprocess.run([str(program), "run", str(scene), "--out", str(out_dir), "--quiet", *extra],
                   check=True, env=env)
    return json.loads((Path(out_dir) / "run.json").read_text())


def same_end_state(compare, a, b):
    result = subprocess.run([str(compare), str(a), str(b)], capture_output=True, text=True)
    return result.returncode == 0, result.stdout.strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--a", required=True)
    parser.add_argument("--b", required=True)
    parser.add_argument("--label-a", default="A")
    parser.add_argument("--label-b", default="B")
    parser.add_argument("--append-a", default="")
    parser.add_argument("--append-b", default="")
    parser.add_argument("--scenes", default="cubes")
    parser.add_argument("--settle", type=int, default=10000,
                        help="steps that settle a scene given as a file")
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", default="out/bench_ab")
    parser.add_argument("--json")
    args = parser.parse_args()
    compare = ROOT / "build/openmp/bin/compare_checkpoints"
    out = Path(args.out)
    record = {"a": {"label": args.label_a, "program": args.a, "scene_lines": args.append_a},
              "b": {"label": args.label_b, "program": args.b, "scene_lines": args.append_b},
              "threads": args.threads, "steps": args.steps, "repeat": args.repeat,
              "started": time.strftime("%Y-%m-%d %H:%M:%S %Z"),
              "load_average_start": os.getloadavg()[0], "scenes": {}}
    for entry in [n for n in args.scenes.split(",") if n]:
        from_file = entry.endswith(".yaml")
        scene = Path(entry).resolve() if from_file else ROOT / "perf/callgrind" / f"{entry}.yaml"
        name = scene.stem
        settled = out / f"{name}_settled"
        settle = args.settle if from_file else SETTLE_STEPS[name]
        run(args.a, scene, settled, args.threads, ["--steps", str(settle)])
        start = settled / "checkpoint.h5"
        variants = {}
        for key, extra in (("a", args.append_a), ("b", args.append_b)):
            variants[key] = scene
            if extra:
                variants[key] = out / f"{name}_{key}.yaml"
                variants[key].write_text(scene.read_text() + extra + "\n")
        times = {"a": [], "b": []}
        for _ in range(args.repeat):
            for key, program in (("a", args.a), ("b", args.b)):
                summary = run(program, variants[key], out / f"{name}_{key}", args.threads,
                              ["--restart", str(start), "--steps", str(args.steps)])
                times[key].append(summary["wall_seconds"])
        identical, detail = same_end_state(compare, out / f"{name}_a" / "checkpoint.h5",
                                           out / f"{name}_b" / "checkpoint.h5")
        median_a, median_b = statistics.median(times["a"]), statistics.median(times["b"])
        record["scenes"][name] = {"seconds_a": times["a"], "seconds_b": times["b"],
                                  "median_a": median_a, "median_b": median_b,
                                  "ratio_b_over_a": median_b / median_a,
                                  "bit_identical": identical, "compare": detail}
        print(f"{name}: {args.label_a} {median_a:.3f} s, {args.label_b} {median_b:.3f} s "
              f"(ratio {median_b / median_a:.3f}); end states "
              f"{'bit-identical' if identical else 'differ: ' + detail}")
    record["load_average_end"] = os.getloadavg()[0]
    if args.json:
        path = Path(args.json)
        tmp = path.with_suffix(".json.tmp")
        tmp.write_text(json.dumps(record, indent=2) + "\n")
        tmp.replace(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
