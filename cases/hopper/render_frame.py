#!/usr/bin/env python3
"""Draws a hopper state from a kdem checkpoint: a 4 mm thick slice through the middle (|y| < 2 mm),
particles as true-size circles coloured by speed, with the hopper outline.

usage: render_frame.py CHECKPOINT.h5 [--png FILE] [--slice 0.002]
"""
import argparse
import math
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle


def hopper_outline(ax):
    top_half, orifice_half = 0.020, 0.008
    cone_top = (top_half - orifice_half) * math.tan(math.radians(60))
    top = cone_top + 0.130
    for side in (-1, 1):
        xs = [side * orifice_half, side * top_half, side * top_half]
        zs = [0.0, cone_top, top]
        ax.plot([1e3 * x for x in xs], [1e3 * z for z in zs], color="black", lw=1.5)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("checkpoint")
    parser.add_argument("--png", default=None)
    parser.add_argument("--slice", type=float, default=0.002)
    args = parser.parse_args()
    with h5py.File(args.checkpoint, "r") as f:
        position = f["particles/position"][()]
        velocity = f["particles/velocity"][()]
        radius = f["particles/radius"][()]
        time = float(f["time"][()])
    circles, speeds = [], []
    for p, v, r in zip(position, velocity, radius):
        if abs(p[1]) < args.slice:
            circles.append(Circle((1e3 * p[0], 1e3 * p[2]), 1e3 * r))
            speeds.append(math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2))
    fig, ax = plt.subplots(figsize=(4, 7))
    collection = PatchCollection(circles, cmap="viridis", edgecolor="none")
    collection.set_array(speeds)
    ax.add_collection(collection)
    hopper_outline(ax)
    ax.set_xlim(-25, 25)
    ax.set_ylim(-30, 155)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title("t = %.3f s, %d spheres in all" % (time, len(radius)))
    fig.colorbar(collection, ax=ax, label="speed (m/s)", shrink=0.6)
    fig.tight_layout()
    png = args.png or os.path.splitext(args.checkpoint)[0] + ".png"
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=130)
    os.replace(tmp, png)
    print("picture: %s" % png)


if __name__ == "__main__":
    main()
