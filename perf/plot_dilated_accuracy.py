"""Plots perf/results/dilated_accuracy.json (kdem_bench_dilated_accuracy): overlap and normal
error of dilated polyhedra standing in for a superquadric against time per contact, one curve
per dilation radius (points: node counts), the exact method's time marked.

usage: plot_dilated_accuracy.py [RESULTS.json] [OUTPUT.png]"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    source = sys.argv[1] if len(sys.argv) > 1 else "perf/results/dilated_accuracy.json"
    target = sys.argv[2] if len(sys.argv) > 2 else "perf/results/dilated_accuracy.png"
    with open(source) as f:
        data = json.load(f)
    shapes = data["shapes"]
    fig, axes = plt.subplots(2, len(shapes), figsize=(6 * len(shapes), 8), squeeze=False)
    for column, shape in enumerate(shapes):
        radii = sorted({run["dilation_over_a"] for run in shape["runs"]})
        for r in radii:
            for matched in (False, True):
                runs = [run for run in shape["runs"]
                        if run["dilation_over_a"] == r and run.get("volume_matched", False) == matched]
                if not runs:
                    continue
                times = [run["ns_per_contact"] for run in runs]
                tag = "volume matched" if matched else "inscribed"
                for row, key, suffix, label in ((0, "overlap_error", "", "overlap error / (a/100)"),
                                                (1, "normal_error", "_rad", "normal error (rad)")):
                    ax = axes[row][column]
                    ax.loglog(times, [run[key + "_median" + suffix] for run in runs],
                              "o-" if matched else "s--", ms=3, label=f"r = {r} a, {tag}, median")
                    if matched:
                        ax.loglog(times, [run[key + "_max" + suffix] for run in runs], "x:",
                                  color=ax.lines[-1].get_color(), label=f"r = {r} a, {tag}, largest")
                        for run in runs:
                            ax.annotate(str(run["faces"]),
                                        (run["ns_per_contact"], run[key + "_median" + suffix]),
                                        fontsize=6, xytext=(2, 2), textcoords="offset points")
                    ax.set_ylabel(label)
        for row in range(2):
            ax = axes[row][column]
            ax.axvline(shape["exact_ns_per_contact"], color="k", lw=0.8, ls="--",
                       label="exact superquadric method")
            ax.set_xlabel("time per contact (ns, one thread)")
            ax.set_title(f"{shape['name']} (labels: core faces)", fontsize=9)
            ax.grid(True, which="both", lw=0.3)
        axes[0][column].legend(fontsize=6)
    fig.suptitle("Dilated polyhedra as a superquadric: error against cost (probe spheres a/5, "
                 "overlap a/100)", fontsize=10)
    fig.tight_layout()
    fig.savefig(target, dpi=120)
    print("wrote", target)


if __name__ == "__main__":
    main()
