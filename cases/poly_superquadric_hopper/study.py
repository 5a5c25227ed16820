#!/usr/bin/env python3
"""The book's poly-superquadric hopper discharge (Sect. 3.3.3, Figs. 3.18-3.20, 3.22): spheres,
poly-superquadric pebbles and cube-like superquadrics of equal volume (volume-equivalent
diameter 5 mm) in the 75 mm square hopper with a 25 mm orifice, its walls 15 to 75 degrees from
the horizontal, discharged into the container below. See README.md.

usage: study.py scenes|run|analyse OUT_DIR [--jobs 2] [--cases pebble_30,cube_30]
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "square_hopper"))
import hopper_study as hs  # noqa: E402

TITLE = "book 3.3.3: hopper discharge of poly-superquadrics"
PLOT = "poly_superquadric_hopper.png"
D0 = 0.005  # m, volume-equivalent diameter (book: 5 mm)
COUNT = 1000  # book: 6000 (see README.md: fewer, for the run time here)
TIME_STEP = 2.0e-5
DISCHARGE_TIME = 2.0  # s after the gate opens
# Book Fig. 3.22 compares 30 and 60 degrees; the sweep 15-75 (Fig. 3.18) in 15 degree steps.
ANGLES = [30, 60, 15, 45, 75]
PEBBLE_PLUS = (0.7, 0.4, 0.5)  # book: r+ : r- per axis, with r- = 1 on every axis (the axes'
PEBBLE_MINUS = (1.0, 1.0, 1.0)  # ratios to one another are not given)
CUBE_BLOCKINESS = (6, 6)  # book: n1 = n2 = 6, a = b = c


def pebble():
    unit = hs.poly_superquadric_volume(PEBBLE_PLUS, PEBBLE_MINUS, (2, 2))
    scale = (hs.sphere_volume(D0) / unit) ** (1 / 3)
    plus = [scale * r for r in PEBBLE_PLUS]
    minus = [scale * r for r in PEBBLE_MINUS]
    # Farthest point from the centroid, estimated (only the rain's batch size uses it): every
    # octant piece is an ellipsoid, within its largest semi-axis of the origin, and the
    # centroid lies less than half the difference of the two sides of each axis from it.
    offset = math.sqrt(sum(((p - m) / 2) ** 2 for p, m in zip(plus, minus)))
    bound = max(plus + minus) + offset
    lines = ["- name: pebble", "  poly_superquadric:",
             f"    half_axes_plus: {hs.fmt(plus)}", f"    half_axes_minus: {hs.fmt(minus)}",
             "    blockiness: [2, 2]"]
    return hs.Shape("pebble", "pebble (poly-SQ)", lines, bound, D0)


def cube():
    a = (hs.sphere_volume(D0) / hs.superquadric_volume((1, 1, 1), CUBE_BLOCKINESS)) ** (1 / 3)
    lines = ["- name: cube", f"  superquadric: {{half_axes: {hs.fmt([a, a, a])}, "
             f"blockiness: {hs.fmt(CUBE_BLOCKINESS)}}}"]
    return hs.Shape("cube", "cube (n = 6)", lines, math.sqrt(3) * a, D0)


SHAPES = [pebble(), cube(), hs.Shape("sphere", "sphere", [], D0 / 2, D0, sphere=True)]


def hopper(angle):
    return hs.Hopper(top_half=0.0375, orifice_half=0.0125, angle_degrees=angle, bin_height=0.15)


# The longest runs first: two run at once.
CASES = [hs.Case(f"{s.name}_{a}", s, hopper(a), COUNT, DISCHARGE_TIME) for a in ANGLES
         for s in SHAPES]
# The 30 degree cases again from other random positions and orientations (result.json,
# "replicates"): how far the rates of one shape differ between two fills.
CASES += [hs.Case(f"{s.name}_30_seed12", s, hopper(30), COUNT, DISCHARGE_TIME, seed=12)
          for s in SHAPES]


def claims(records):
    """The book's statements (Sect. 3.3.3), checked at every hopper angle run for all shapes."""
    angles = sorted({r["hopper_angle_degrees"] for r in records})
    out = []
    for angle in angles:
        by = {r["shape"]: r for r in records if r["hopper_angle_degrees"] == angle}
        if len(by) < len(SHAPES):
            continue
        rate = {k: r["mean_rate_kg_per_s"] for k, r in by.items()}
        out.append(hs.claim(f"spheres discharge fastest ({angle:g} degree hopper)",
                            all(rate["sphere"] > rate[k] for k in rate if k != "sphere"),
                            hopper_angle_degrees=angle, mean_rate_kg_per_s=rate))
        out.append(hs.claim(f"shape changes the discharge rate strongly ({angle:g} degrees: "
                            "slowest below 80 % of the fastest)",
                            min(rate.values()) < 0.8 * max(rate.values()),
                            hopper_angle_degrees=angle, mean_rate_kg_per_s=rate))
    return out


def plot(records, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    angles = sorted({r["hopper_angle_degrees"] for r in records})
    columns = 4
    rows = math.ceil((len(angles) + 2) / columns)
    fig, grid = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.9 * rows), squeeze=False)
    axes = list(grid.flat)
    for axis in axes[len(angles) + 2:]:
        axis.set_visible(False)
    for axis, angle in zip(axes, angles):
        hs.plot_discharge(axis, [r for r in records if r["hopper_angle_degrees"] == angle])
        axis.set_title("walls %g degrees from the horizontal" % angle)
        axis.legend(fontsize=8)
    rates, repose = axes[len(angles)], axes[len(angles) + 1]
    for shape in SHAPES:
        mine = sorted((r for r in records if r["shape"] == shape.name),
                      key=lambda r: r["hopper_angle_degrees"])
        xs = [r["hopper_angle_degrees"] for r in mine]
        rates.plot(xs, [1e3 * r["mean_rate_kg_per_s"] for r in mine], "o-",
                   label=shape.label)
        repose.errorbar(xs, [r["angle_of_repose_degrees"] for r in mine],
                        yerr=[r.get("angle_standard_error_degrees", 0) for r in mine], fmt="o-",
                        label=shape.label)
    rates.set_xlabel("hopper wall angle (degrees from the horizontal)")
    rates.set_ylabel("mean rate over the first %g s (g/s)" % hs.MEAN_RATE_TIME)
    rates.set_title("discharge rate")
    repose.set_xlabel("hopper wall angle (degrees from the horizontal)")
    repose.set_ylabel("angle of repose in the container (degrees)")
    repose.set_title("angle of repose")
    for axis in (rates, repose):
        axis.grid(alpha=0.3)
        axis.legend(fontsize=8)
    fig.suptitle("%d particles, D0 = 5 mm, 25 mm orifice" % records[0]["count"])
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=100)
    os.replace(path + ".tmp.png", path)


if __name__ == "__main__":
    hs.main(sys.modules[__name__])
