"""Writes the bounding radius of each shape (the engine's, from the checkpoints of make_scene.py's
first, one-step runs) as JSON: {shape: radius in m}.

usage: bounding_radii.py RUNS_FOLDER OUTPUT.json"""
import json
import os
import sys

import h5py


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    runs, target = sys.argv[1:]
    radii = {}
    for run in ("levelset_wall_impact", "superquadric_reference"):
        with h5py.File(os.path.join(runs, run, "checkpoint.h5"), "r") as f:
            names = f["source_names"][()].decode().split()
            for s, r in zip(f["particles/source"][:, 0], f["particles/radius"][:, 0]):
                radii[names[s].rsplit("_", 1)[0]] = float(r)
    with open(target + ".tmp", "w") as f:
        json.dump(radii, f, indent=1)
    os.replace(target + ".tmp", target)


if __name__ == "__main__":
    main()
