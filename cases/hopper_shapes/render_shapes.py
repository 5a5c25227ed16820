#!/usr/bin/env python3
"""Draws the particles of a kdem checkpoint with their true shapes: the particles whose centre
lies in a slab |y| < slice, each as its silhouette seen along y (the convex hull of its
superquadric surface, posed by its quaternion), coloured by speed, with the hopper outline.

usage: render_shapes.py CHECKPOINT.h5 [CHECKPOINT.h5 ...] [--png FILE] [--slice 0.002]
                        [--titles "spheres,cylinders,cubes"] [--no-hopper]
                        [--limits XMIN,XMAX,ZMIN,ZMAX]  (mm; default the hopper's)
                        [--templates "a,b,c,n1,n2;..."]  (m; one per checkpoint, for files
                                                           written without shapes/)

Several checkpoints are drawn side by side. Shape templates are read from the checkpoint
(shapes/half_axes, shapes/blockiness; shape id k > 0 is row k - 1, 0 a sphere of its radius).
"""
import argparse
import math
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PatchCollection
from matplotlib.patches import Polygon

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "hopper"))
from render_frame import hopper_outline  # noqa: E402


def signed_power(t, exponent):
    return np.sign(t) * np.abs(t) ** exponent


def surface_points(a, b, c, n1, n2, samples=24):
    eta = np.linspace(-0.5 * math.pi, 0.5 * math.pi, samples // 2 + 1)[:, None]
    omega = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)[None, :]
    e1, e2 = 2.0 / n1, 2.0 / n2
    x = a * signed_power(np.cos(eta), e1) * signed_power(np.cos(omega), e2)
    y = b * signed_power(np.cos(eta), e1) * signed_power(np.sin(omega), e2)
    z = c * signed_power(np.sin(eta), e1) * np.ones_like(omega)
    return np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)


def rotation_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def convex_hull(points):
    """Andrew's monotone chain; points as (x, y) tuples, hull counter-clockwise."""
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def silhouettes(path, slab, fallback_template=None):
    with h5py.File(path, "r") as f:
        position = f["particles/position"][()]
        velocity = f["particles/velocity"][()]
        orientation = f["particles/orientation"][()]
        radius = f["particles/radius"][()]
        shape = f["particles/shape"][()].ravel()
        if "shapes/half_axes" in f:
            half_axes, blockiness = f["shapes/half_axes"][()], f["shapes/blockiness"][()]
        elif fallback_template:
            half_axes, blockiness = [fallback_template[:3]], [fallback_template[3:]]
        else:
            half_axes, blockiness = np.zeros((0, 3)), np.zeros((0, 2))
        time = float(f["time"][()])
    templates = {}
    polygons, speeds = [], []
    for i in range(len(radius)):
        if abs(position[i][1]) >= slab:
            continue
        s = int(shape[i])
        if s == 0:
            key = ("sphere", float(radius[i]))
            local = templates.get(key)
            if local is None:
                local = templates[key] = surface_points(radius[i], radius[i], radius[i], 2, 2)
        else:
            local = templates.get(s)
            if local is None:
                a, b, c = half_axes[s - 1]
                local = templates[s] = surface_points(a, b, c, *blockiness[s - 1])
        world = local @ rotation_matrix(orientation[i]).T + position[i]
        hull = convex_hull([(1e3 * p[0], 1e3 * p[2]) for p in world])
        polygons.append(Polygon(hull, closed=True))
        speeds.append(float(np.linalg.norm(velocity[i])))
    return polygons, speeds, time, len(radius)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("checkpoints", nargs="+")
    parser.add_argument("--png", default=None)
    parser.add_argument("--slice", type=float, default=0.002)
    parser.add_argument("--titles", default=None)
    parser.add_argument("--no-hopper", action="store_true", help="do not draw the hopper outline")
    parser.add_argument("--limits", default="-25,25,-30,100")
    parser.add_argument("--templates", default=None)
    args = parser.parse_args()
    fallbacks = [None] * len(args.checkpoints)
    if args.templates:
        fallbacks = [[float(v) for v in t.split(",")] if t.strip() else None
                     for t in args.templates.split(";")]
    x_min, x_max, z_min, z_max = (float(v) for v in args.limits.split(","))
    titles = args.titles.split(",") if args.titles else [None] * len(args.checkpoints)
    height = 3.6 * (z_max - z_min) / (x_max - x_min) + 1.0
    fig, axes = plt.subplots(1, len(args.checkpoints), figsize=(3.6 * len(args.checkpoints), height),
                             squeeze=False)
    collection = None
    for ax, path, title, fallback in zip(axes[0], args.checkpoints, titles, fallbacks):
        polygons, speeds, time, count = silhouettes(path, args.slice, fallback)
        collection = PatchCollection(polygons, cmap="viridis", edgecolor="black", linewidth=0.2)
        collection.set_array(np.array(speeds))
        collection.set_clim(0, 0.5)
        ax.add_collection(collection)
        if not args.no_hopper:
            hopper_outline(ax)
        ax.set_xlim(x_min, x_max)
        ax.set_ylim(z_min, z_max)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_title("%s\nt = %.3f s, %d particles" % (title or os.path.basename(path), time, count),
                     fontsize=9)
    axes[0][0].set_ylabel("z (mm)")
    fig.colorbar(collection, ax=list(axes[0]), label="speed (m/s)", shrink=0.6)
    png = args.png or os.path.splitext(args.checkpoints[0])[0] + "_shapes.png"
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=130, bbox_inches="tight")
    os.replace(tmp, png)
    print("picture: %s" % png)


if __name__ == "__main__":
    main()
