#!/usr/bin/env python3
"""Plots of the superquadric narrow-phase benchmark (perf/bench_narrow_phase.cpp).

    /usr/bin/python3 perf/plot_narrow_phase.py [--sweep perf/results/narrow_phase_sweep.json]
        [--hard perf/results/narrow_phase_hard.json] [--img docs/img] [--time cpu|wall]
        [--tables] [--failures perf/results/narrow_phase_failures*.json]

Writes docs/img/narrow_phase_overlap_error.png and docs/img/narrow_phase_normal_error.png (time
per contact evaluation against the error, one marker per tolerance and iteration cap) and
docs/img/narrow_phase_iterations.png (iteration histograms at one setting). --tables prints the
sweep, hard-case and failure-count tables as Markdown.

The time axis is the CPU time per evaluation summed over the threads (--time cpu, the default):
on cores shared with other processes the wall time (--time wall) says more about the other
processes than about the solver.
"""
import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CAP_MARKERS = {5: "v", 10: "s", 20: "D", 40: "o"}
ERROR_FLOOR = 1e-17  # errors of exactly zero (the same iterate as the reference) drawn here


def load(path):
    return json.loads(Path(path).read_text())


def label_of(controls):
    if not controls["use_fallback"]:
        return f"tol {controls['tolerance']:.0e}, cap {controls['max_iterations']}, no fallback"
    return f"tol {controls['tolerance']:.0e}, cap {controls['max_iterations']}"


def sets_by_name(run):
    return {s["name"]: s for s in run["sets"]}


def machine_note(data):
    return (f"measured on {data['cpu_model']}, {data['backend']}, {data['threads']} threads, "
            f"load average {data['load_average_start']:.1f}-{data['load_average_end']:.1f}")


def tolerance_colours(runs):
    tolerances = sorted({r["controls"]["tolerance"] for r in runs}, reverse=True)
    cmap = plt.get_cmap("viridis")
    return {t: cmap(k / max(1, len(tolerances) - 1)) for k, t in enumerate(tolerances)}


TIME_KEYS = {"cpu": ("cpu_ns_per_evaluation", "CPU time per contact evaluation (ns, all threads)"),
             "wall": ("ns_per_evaluation", "wall time per contact evaluation (ns)")}


def draw_marker(ax, run, stats, error_key, statistic, colours, time_key):
    controls = run["controls"]
    error = max(stats[error_key][statistic], ERROR_FLOOR)
    fallback = controls["use_fallback"]
    ax.scatter(error, stats[time_key], s=60 if fallback else 140,
               marker=CAP_MARKERS.get(controls["max_iterations"], "o") if fallback else "*",
               color=colours[controls["tolerance"]],
               edgecolors="red" if stats["failures"] > 0 else "black", linewidths=1.5 if
               stats["failures"] > 0 else 0.5, zorder=3)


def legend_handles(colours):
    handles = [plt.Line2D([], [], ls="", marker="o", color=c, label=f"tol {t:.0e}")
               for t, c in colours.items()]
    handles += [plt.Line2D([], [], ls="", marker=m, color="grey", label=f"cap {cap}")
                for cap, m in CAP_MARKERS.items()]
    handles.append(plt.Line2D([], [], ls="", marker="*", color="grey", markersize=12,
                              label="no fallback (cap 40)"))
    handles.append(plt.Line2D([], [], ls="", marker="o", markerfacecolor="white",
                              markeredgecolor="red", markeredgewidth=1.5,
                              label="red edge: failures (status 2)"))
    return handles


def error_figure(data, error_key, title, path, time):
    runs = data["runs"]
    colours = tolerance_colours(runs)
    set_names = [s["name"] for s in runs[0]["sets"]]
    fig, axes = plt.subplots(2, len(set_names), figsize=(5.5 * len(set_names) + 2, 8.5), squeeze=False)
    for column, name in enumerate(set_names):
        for row, statistic in enumerate(["p99", "max"]):
            ax = axes[row][column]
            for run in runs:
                draw_marker(ax, run, sets_by_name(run)[name], error_key, statistic, colours,
                            TIME_KEYS[time][0])
            ax.set_xscale("log")
            ax.set_xlabel(f"{title}, {'99th percentile' if statistic == 'p99' else 'maximum'}")
            ax.set_ylabel(TIME_KEYS[time][1])
            ax.set_title(f"{name} ({runs[0]['sets'][column]['evaluations']} evaluations)")
            ax.grid(True, which="both", alpha=0.3)
            ax.set_ylim(bottom=0)
    fig.legend(handles=legend_handles(colours), fontsize=8, loc="center right")
    fig.suptitle(f"Midway-point Newton: time against {title}\n{machine_note(data)}", fontsize=10)
    fig.tight_layout(rect=(0, 0, 0.84, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"wrote {path}")


def iteration_figure(data, path):
    run = data["runs"][0]
    sets = sets_by_name(run)
    hard = [s for s in run["sets"] if s["name"] not in ("random", "moving", "moving, cold start")]
    combined = {}
    for s in hard:
        histogram = s["iteration_histogram"]
        for k, count in zip(histogram["iterations"], histogram["counts"]):
            combined[k] = combined.get(k, 0) + count
    panels = [("random", sets["random"]["iteration_histogram"]),
              ("moving, warm start", sets["moving"]["iteration_histogram"]),
              ("moving, cold start", sets["moving, cold start"]["iteration_histogram"]),
              ("hard cases (all sets)", {"iterations": sorted(combined),
                                         "counts": [combined[k] for k in sorted(combined)]})]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 3.8))
    for ax, (name, histogram) in zip(axes, panels):
        total = sum(histogram["counts"])
        ax.bar(histogram["iterations"], [c / total for c in histogram["counts"]], width=0.9)
        ax.set_yscale("log")
        ax.set_xlabel("Newton iterations (fallback included)")
        ax.set_ylabel("fraction of evaluations")
        ax.set_title(f"{name}, {total} evaluations", fontsize=10)
        ax.grid(True, axis="y", alpha=0.3)
    fig.suptitle(f"Iterations at {label_of(run['controls'])}; {machine_note(data)}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"wrote {path}")


def sweep_table(data):
    for name in [s["name"] for s in data["runs"][0]["sets"]]:
        print(f"\n{name}:\n")
        print("| setting | wall ns / eval | CPU ns / eval | mean it. | fallbacks | failures "
              "| touching mismatches | overlap err p99 / max | normal err p99 / max (rad) |")
        print("|---" * 9 + "|")
        for run in data["runs"]:
            s = sets_by_name(run)[name]
            o, n = s["overlap_error"], s["normal_error_rad"]
            print(f"| {label_of(run['controls'])} | {s['ns_per_evaluation']:.0f} "
                  f"| {s['cpu_ns_per_evaluation']:.0f} | {s['mean_iterations']:.2f} "
                  f"| {s['fallbacks']} | {s['failures']} | {s['touching_mismatches']} "
                  f"| {o['p99']:.1e} / {o['max']:.1e} | {n['p99']:.1e} / {n['max']:.1e} |")


def failure_table(paths):
    print("| setting | set | evaluations | touching | fallbacks | failures | mean it. | max it. |")
    print("|---" * 8 + "|")
    for path in paths:
        data = load(path)
        for s in data["sets"]:
            print(f"| {label_of(data['controls'])} | {s['name']} | {s['evaluations']} "
                  f"| {s['touching']} | {s['fallbacks']} | {s['failures']} "
                  f"| {s['mean_iterations']:.2f} | {max(s['iteration_histogram']['iterations'])} |")


def hard_table(data):
    print("| set | evaluations | ns/eval (CPU ns) | mean it. | max it. | direct | fallback | failed "
          "| overlap err median / p99 / max | normal err median / p99 / max (rad) "
          "| chord excess |")
    print("|---" * 11 + "|")
    for s in data["runs"][0]["sets"]:
        o, n = s["overlap_error"], s["normal_error_rad"]
        direct = s["evaluations"] - s["fallbacks"] - s["failures"]
        print(f"| {s['name']} | {s['evaluations']} | {s['ns_per_evaluation']:.0f} "
              f"({s['cpu_ns_per_evaluation']:.0f}) | {s['mean_iterations']:.2f} "
              f"| {max(s['iteration_histogram']['iterations'])} | {direct} | {s['fallbacks']} "
              f"| {s['failures']} | {o['median']:.1e} / {o['p99']:.1e} / {o['max']:.1e} "
              f"| {n['median']:.1e} / {n['p99']:.1e} / {n['max']:.1e} "
              f"| {s['worst_chord_excess']:.1e} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sweep", default=ROOT / "perf/results/narrow_phase_sweep.json")
    parser.add_argument("--hard", default=ROOT / "perf/results/narrow_phase_hard.json")
    parser.add_argument("--img", default=ROOT / "docs/img")
    parser.add_argument("--failures", nargs="*", default=sorted(
        str(p) for p in (ROOT / "perf/results").glob("narrow_phase_failures*.json")))
    parser.add_argument("--time", choices=sorted(TIME_KEYS), default="cpu")
    parser.add_argument("--tables", action="store_true", help="print Markdown tables")
    args = parser.parse_args()
    img = Path(args.img)
    img.mkdir(parents=True, exist_ok=True)
    sweep = load(args.sweep)
    error_figure(sweep, "overlap_error", "relative overlap error",
                 img / "narrow_phase_overlap_error.png", args.time)
    error_figure(sweep, "normal_error_rad", "normal error (rad)",
                 img / "narrow_phase_normal_error.png", args.time)
    hard = load(args.hard)
    iteration_figure(hard, img / "narrow_phase_iterations.png")
    if args.tables:
        sweep_table(sweep)
        print()
        hard_table(hard)
        print()
        failure_table(args.failures)


if __name__ == "__main__":
    main()
