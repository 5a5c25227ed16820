#!/usr/bin/env python3
"""Discharge of cubes and of equal-volume spheres through the same small orifice: discharged
fraction against time, whether the flow stopped (an arch) before the bin emptied, and a picture
of the final state of both.

usage: plot_arch.py RUN_DIR [--png docs/img/cube_arch.png] [--gate-open 0.2]

RUN_DIR holds cubes/ and spheres/ (kdem outputs of the scenes of make_case.py). The flow counts
as arrested when the discharged mass did not change over the last 0.1 s of the run while
particles were left in the bin.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def read_series(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return ([float(r["time"]) for r in rows], [float(r["discharged_mass"]) for r in rows],
            [int(float(r["particles"])) for r in rows])


def summary(run_dir):
    time, mass, left = read_series(os.path.join(run_dir, "series.csv"))
    with open(os.path.join(run_dir, "run.json")) as f:
        run = json.load(f)
    start_count = left[0]
    late = [m for t, m in zip(time, mass) if t >= time[-1] - 0.1]
    arrested = left[-1] > 0 and max(late) - min(late) == 0.0
    return {"time": time, "fraction": [1 - n / start_count for n in left], "left": left[-1],
            "start": start_count, "arrested": arrested,
            "failures": run["narrow_phase_failures"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir")
    parser.add_argument("--png", default=os.path.join(HERE, "..", "..", "docs", "img", "cube_arch.png"))
    parser.add_argument("--gate-open", type=float, default=0.2)
    args = parser.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    results = {kind: summary(os.path.join(args.run_dir, kind)) for kind in ("spheres", "cubes")}
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for kind, r in results.items():
        ax.plot(r["time"], r["fraction"], label="%s (%s)" % (kind, "arch: flow stopped" if r["arrested"] else "flowing"))
        print("%s: %d of %d discharged, %d left, flow %s, narrow-phase failures %d"
              % (kind, r["start"] - r["left"], r["start"], r["left"],
                 "stopped (arch)" if r["arrested"] else "not stopped", r["failures"]))
    ax.axvline(args.gate_open, color="grey", ls=":", lw=0.8, label="gate opens")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("fraction discharged")
    ax.legend(fontsize=8)
    fig.tight_layout()
    tmp = args.png + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, args.png)
    print("plot: %s" % args.png)
    picture = os.path.splitext(args.png)[0] + "_state.png"
    checkpoints = [os.path.join(args.run_dir, kind, "checkpoint.h5") for kind in ("spheres", "cubes")]
    subprocess.run([sys.executable, os.path.join(HERE, "..", "hopper_shapes", "render_shapes.py"),
                    *checkpoints, "--png", picture, "--titles", "spheres,cubes", "--no-hopper",
                    "--limits=-12,12,-8,30", "--slice", "0.0015"], check=True)


if __name__ == "__main__":
    main()
