"""Moves the bodies of a step-0 checkpoint of stack.yaml into their stacks: each body's centroid
to its target position of make_scene.stack_layout() (the bodies of a stack aligned and centred on
one vertical axis, make_scene.GAP apart and above the plane), at rest, with a neighbour-list
rebuild due. The engine places particles as their bounding spheres, which cannot stack flat
bodies closely; this puts them where the case needs them, and the run restarts from it.

Only positions (and the list build's reference positions), velocities, forces and the rebuild flag
change; masses, inertias, orientations, shapes and the energy budget stay as the engine wrote them
(moving bodies down only lowers their potential energy, so the energy check's bound stays valid).

usage: place_stack.py STEP0_CHECKPOINT.h5 OUTPUT_CHECKPOINT.h5"""
import os
import shutil
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scene  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    source_path, out_path = sys.argv[1:]
    shutil.copyfile(source_path, out_path)
    targets = {f"{stack}_{level}": target
               for stack, level, _, _, target in make_scene.stack_layout()}
    with h5py.File(out_path, "r+") as f:
        if int(f["step"][()]) != 0:
            sys.exit(f"{source_path}: expected a checkpoint at step 0, found step {f['step'][()]}")
        names = f["source_names"][()].decode().split()
        source = f["particles/source"][:, 0]
        if sorted(names[s] for s in source) != sorted(targets):
            sys.exit(f"{source_path}: the particles' sources differ from make_scene.py's bodies")
        position = np.array([targets[names[s]] for s in source], dtype=float)
        f["particles/position"][...] = position
        f["particles/position_at_build"][...] = position
        for key in ("velocity", "angular_velocity", "force", "torque"):
            f["particles/" + key][...] = 0.0
        f["needs_rebuild"][()] = 1


if __name__ == "__main__":
    main()
