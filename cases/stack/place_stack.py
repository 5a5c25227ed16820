"""Moves the bodies of a step-0 checkpoint of stack.yaml into their stacks: each body centred on its
stack's vertical axis (make_scene.stack_layout()), at rest, with a neighbour-list rebuild due, and
make_scene.GAP between its lowest point and the highest point of the body below (or the plane).
The engine places particles as their bounding spheres, which cannot stack flat bodies closely;
this puts them where the case needs them, and the run restarts from it.

Each body's extent below and above its centroid is the larger of its nominal half-thickness
(make_scene.half_thickness) and what the drawn surface of step 0 shows (frames/
shapes_00000000.vtp: the core's vertices moved out by the dilation radius along their normals,
which lies within the body, and on a flat end with upright normals is its surface). A lattice
core reduced by simplification is not exactly the superquadric it samples (the r = 5 mm
cylinder's drawn surface is 0.196 mm thicker than the nominal 11 mm), so the nominal thickness
alone would start that stack overlapped; a box core's drawn surface (normals along the corners'
diagonals) falls short of the body, so the drawn surface alone would.

Only positions (and the list build's reference positions), velocities, forces and the rebuild flag
change; masses, inertias, orientations, shapes and the energy budget stay as the engine wrote them
(moving bodies down only lowers their potential energy, so the energy check's bound stays valid).

usage: place_stack.py STEP0_DIR OUTPUT_CHECKPOINT.h5   (STEP0_DIR: the output of the step-0 run)"""
import os
import shutil
import sys

import h5py
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scene  # noqa: E402


def vertical_extents(vtp_path, ids, heights):
    """Per particle (in the order of `ids`, centroid heights `heights`): how far its drawn surface
    reaches below and above its centroid."""
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(vtp_path)
    reader.Update()
    data = reader.GetOutput()
    if data.GetNumberOfPoints() == 0:
        sys.exit(f"{vtp_path}: no surface points")
    z = vtk_to_numpy(data.GetPoints().GetData())[:, 2]
    point_ids = vtk_to_numpy(data.GetPointData().GetArray("id"))
    below, above = np.empty(len(ids)), np.empty(len(ids))
    for k, (pid, height) in enumerate(zip(ids, heights)):
        mine = z[point_ids == pid]
        if mine.size == 0:
            sys.exit(f"{vtp_path}: no surface drawn for particle {pid}")
        below[k], above[k] = height - mine.min(), mine.max() - height
    return below, above


def stacked_positions(names, source, below, above):
    """Centroids of the bodies in their stacks: on the stack's axis, bottom first, GAP apart."""
    layout = {f"{stack}_{level}": (stack, level, shape, target)
              for stack, level, shape, _, target in make_scene.stack_layout()}
    position = np.empty((len(source), 3))
    order = sorted(range(len(source)), key=lambda k: layout[names[source[k]]][:2])
    top = {}
    for k in order:
        stack, _, shape, target = layout[names[source[k]]]
        nominal = make_scene.half_thickness(shape)
        centroid = top.get(stack, 0.0) + make_scene.GAP + max(below[k], nominal)
        position[k] = (target[0], target[1], centroid)
        top[stack] = centroid + max(above[k], nominal)
    return position


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    step0, out_path = sys.argv[1:]
    source_path = os.path.join(step0, "checkpoint.h5")
    shutil.copyfile(source_path, out_path)
    targets = {f"{stack}_{level}" for stack, level, _, _, _ in make_scene.stack_layout()}
    with h5py.File(out_path, "r+") as f:
        if int(f["step"][()]) != 0:
            sys.exit(f"{source_path}: expected a checkpoint at step 0, found step {f['step'][()]}")
        names = f["source_names"][()].decode().split()
        source = f["particles/source"][:, 0]
        if sorted(names[s] for s in source) != sorted(targets):
            sys.exit(f"{source_path}: the particles' sources differ from make_scene.py's bodies")
        below, above = vertical_extents(os.path.join(step0, "frames", "shapes_00000000.vtp"),
                                        f["particles/id"][:].ravel(),
                                        f["particles/position"][:, 2])
        position = stacked_positions(names, source, below, above)
        f["particles/position"][...] = position
        f["particles/position_at_build"][...] = position
        for key in ("velocity", "angular_velocity", "force", "torque"):
            f["particles/" + key][...] = 0.0
        f["needs_rebuild"][()] = 1


if __name__ == "__main__":
    main()
