"""Plots perf/results/level_set_accuracy.json (kdem_bench_level_set_accuracy): overlap and normal
error of level-set superquadric pairs against the exact superquadric pair, against the surface
points per body (what a pair's cost grows with: every point is placed and tested) and the grid's
memory, one curve per mesh node count and grid resolution (points along a curve: point spacings
of 2, 1 and 1/2 grid spacings).

usage: plot_level_set_accuracy.py [RESULTS.json] [OUTPUT.png]"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    source = sys.argv[1] if len(sys.argv) > 1 else "perf/results/level_set_accuracy.json"
    target = sys.argv[2] if len(sys.argv) > 2 else "perf/results/level_set_accuracy.png"
    with open(source) as f:
        data = json.load(f)
    shapes = data["shapes"]
    fig, axes = plt.subplots(2, len(shapes), figsize=(6 * len(shapes), 8), squeeze=False)
    for column, shape in enumerate(shapes):
        for nodes in sorted({run["nodes"] for run in shape["runs"]}):
            for cells in sorted({run["cells_across"] for run in shape["runs"]}):
                runs = [run for run in shape["runs"]
                        if run["nodes"] == nodes and run["cells_across"] == cells]
                points = [run["surface_points"] for run in runs]
                memory = runs[0]["grid_bytes"] / 2 ** 20
                label = f"{nodes} nodes, {cells:g} cells ({memory:.2g} MiB)"
                for row, key in ((0, "overlap_error_median"), (1, "normal_error_median_rad")):
                    ax = axes[row][column]
                    ax.loglog(points, [max(run[key], 1e-4) for run in runs],
                              "o-" if nodes > 2000 else "s--", ms=3, label=label)
        for row, ylabel in ((0, "median overlap error / (a/100)"), (1, "median normal error (rad)")):
            ax = axes[row][column]
            ax.set_xlabel("surface points per body")
            ax.set_ylabel(ylabel)
            ax.set_title(f"{shape['name']}: pairs overlapping by a/100", fontsize=9)
            ax.grid(True, which="both", lw=0.3)
            ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(target, dpi=120)
    print("wrote", target)


if __name__ == "__main__":
    main()
