#!/usr/bin/env python3
"""Draws the true particle surfaces of a kdem frame (frames/shapes_*.vtp, the posed surface of
every particle) in 3-D with matplotlib, coloured by shape, within a box of interest.

usage: render_surfaces.py FRAME.vtp PNG [--box XMIN,XMAX,YMIN,YMAX,ZMIN,ZMAX] (m)
                          [--names "sphere,hemisphere,..."] (one per shape id, for the legend)
                          [--title TEXT]
"""
import argparse
import os

import matplotlib
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_surfaces(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    points = vtk_to_numpy(data.GetPoints().GetData())
    triangles = vtk_to_numpy(data.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    shape = vtk_to_numpy(data.GetPointData().GetArray("shape"))
    return points, triangles, shape


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("frame")
    parser.add_argument("png")
    parser.add_argument("--box", default=None)
    parser.add_argument("--names", default="")
    parser.add_argument("--title", default="")
    args = parser.parse_args()
    points, triangles, shape = read_surfaces(args.frame)
    corners = points[triangles]  # triangle, corner, xyz
    keep = np.ones(len(triangles), bool)
    if args.box:
        lo_hi = np.array([float(v) for v in args.box.split(",")]).reshape(3, 2)
        centres = corners.mean(axis=1)
        keep = np.all((centres >= lo_hi[:, 0]) & (centres <= lo_hi[:, 1]), axis=1)
    corners, ids = corners[keep], shape[triangles[keep, 0]]
    colours = plt.get_cmap("tab10")
    light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1)[:, None], 1e-300)
    shade = 0.45 + 0.55 * np.abs(normals @ light)
    faces = np.array([colours(int(k) % 10)[:3] for k in ids]) * shade[:, None]
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(Poly3DCollection(corners * 1e3, facecolors=faces, edgecolors="none"))
    span = corners.reshape(-1, 3) * 1e3
    for setter, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
        setter(span[:, k].min(), span[:, k].max())
    ax.set_box_aspect(np.ptp(span, axis=0))
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    ax.view_init(elev=25, azim=-60)
    names = [n for n in args.names.split(",") if n]
    if names:
        present = sorted(set(int(k) for k in ids))
        ax.legend(handles=[Patch(color=colours(k % 10), label=names[k]) for k in present
                           if k < len(names)], loc="upper left", fontsize=8)
    if args.title:
        ax.set_title(args.title)
    tmp = args.png + ".tmp.png"
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    os.replace(tmp, args.png)


if __name__ == "__main__":
    main()
