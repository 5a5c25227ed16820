#!/usr/bin/env python3
"""Superquadric separation certificates, measured with and without in one run: the hopper of
cases/hopper_shapes (1000 cubes or cylinders, Table 6.4 set-up) is run to t = 0.3 s (discharge
under way), then the same restart segment is run alternately with
`superquadric_contact.separation_certificates` true and false.

usage: bench_certificates.py [--kdem build/openmp/bin/kdem] [--threads 2] [--repeat 3]
                             [--steps 4000] [--shapes cube,cylinder] [--out out/certificates]
                             [--json perf/results/separation_certificates.json]

Reports per shape and setting the median engine wall time (run.json, without start-up and
output), narrow-phase evaluations and mean Newton iterations, contacts and discharged mass at
the end (the last two must agree closely: the certificates skip only pairs that cannot touch).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, ".."))
SETTLE_STEPS = 60000  # 0.3 s at dt = 5 us: gate open since 0.25 s


def run(kdem, scene, out_dir, threads, extra):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    subprocess.run([kdem, "run", scene, "--out", out_dir, "--quiet"] + extra, check=True, env=env)
    with open(os.path.join(out_dir, "run.json")) as f:
        return json.load(f)


def variant(scene_path, certificates):
    """A copy of the scene with the certificates switched as asked."""
    with open(scene_path) as f:
        text = f.read()
    setting = "true" if certificates else "false"
    path = scene_path.replace(".yaml", "_certificates_%s.yaml" % setting)
    with open(path, "w") as f:
        f.write(text + "superquadric_contact: {separation_certificates: %s}\n" % setting)
    return path


def measure(args, shape, scenes):
    scene = os.path.join(scenes, "%s_1000.yaml" % shape)
    settled = os.path.join(args.out, "%s_settled" % shape)
    run(args.kdem, scene, settled, args.threads, ["--steps", str(SETTLE_STEPS)])
    checkpoint = os.path.join(settled, "checkpoint.h5")
    runs = {True: [], False: []}
    for _ in range(args.repeat):
        for certificates in (True, False):
            out_dir = os.path.join(args.out, "%s_%s" % (shape, "on" if certificates else "off"))
            summary = run(args.kdem, variant(scene, certificates), out_dir, args.threads,
                          ["--restart", checkpoint, "--steps", str(args.steps)])
            runs[certificates].append({
                "wall_seconds": summary["wall_seconds"],
                "narrow_phase_evaluations": summary["extra"]["narrow_phase_evaluations"],
                "narrow_phase_mean_iterations": summary["extra"]["narrow_phase_mean_iterations"],
                "narrow_phase_failures": summary["narrow_phase_failures"],
                "contacts": summary["contacts"],
                "discharged_mass": summary["discharged_mass"],
            })
    return runs


def summarise(shape, runs):
    rows = []
    for certificates in (True, False):
        r = runs[certificates]
        rows.append({
            "shape": shape, "certificates": certificates,
            "median_wall_seconds": statistics.median(x["wall_seconds"] for x in r),
            "wall_seconds": [x["wall_seconds"] for x in r],
            "narrow_phase_evaluations": r[-1]["narrow_phase_evaluations"],
            "narrow_phase_mean_iterations": r[-1]["narrow_phase_mean_iterations"],
            "narrow_phase_failures": r[-1]["narrow_phase_failures"],
            "contacts": r[-1]["contacts"], "discharged_mass": r[-1]["discharged_mass"],
        })
    return rows


def cpu_name():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "unknown"


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kdem", default=os.path.join(ROOT, "build/openmp/bin/kdem"))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--steps", type=int, default=4000)
    parser.add_argument("--shapes", default="cube,cylinder")
    parser.add_argument("--out", default=os.path.join(ROOT, "out/certificates"))
    parser.add_argument("--json", default=os.path.join(ROOT, "perf/results/separation_certificates.json"))
    args = parser.parse_args()

    scenes = os.path.join(args.out, "scenes")
    subprocess.run([sys.executable, os.path.join(ROOT, "cases/hopper_shapes/make_scenes.py"), scenes,
                    "--counts", "1000", "--shapes", args.shapes], check=True,
                   stdout=subprocess.DEVNULL)
    rows = []
    for shape in args.shapes.split(","):
        rows += summarise(shape, measure(args, shape, scenes))
    record = {"machine": cpu_name(), "cores": os.cpu_count(), "threads": args.threads,
              "steps": args.steps, "repeat": args.repeat, "rows": rows}
    tmp = args.json + ".tmp"
    with open(tmp, "w") as f:
        json.dump(record, f, indent=1)
    os.replace(tmp, args.json)
    print("| shape | certificates | median wall time (s) | evaluations | mean iterations | "
          "contacts | discharged mass (g) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %s | %.3f | %d | %.3f | %d | %.4f |" % (
            r["shape"], "on" if r["certificates"] else "off", r["median_wall_seconds"],
            r["narrow_phase_evaluations"], r["narrow_phase_mean_iterations"], r["contacts"],
            1e3 * r["discharged_mass"]))
    for shape in args.shapes.split(","):
        on, off = [r for r in rows if r["shape"] == shape]
        print("%s: with / without = %.3f (time), %.3f (evaluations)" % (
            shape, on["median_wall_seconds"] / off["median_wall_seconds"],
            on["narrow_phase_evaluations"] / off["narrow_phase_evaluations"]))


if __name__ == "__main__":
    main()
