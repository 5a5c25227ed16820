# The packing of packing.py in Yade's level-set DEM: the same bodies, poses and box (five walls),
# each shape Yade's superellipsoid on a grid of kdem's default spacing (a fortieth of 2c) with
# about as many surface nodes as kdem's default points, one grid per shape (yade_common).
# Contact law: Yade's Hertz-Mindlin (Ip2_FrictMat_FrictMat_MindlinPhys) with its restitution
# damping at the scene's restitution, normal and tangential (en = es), and friction; no numerical
# damping; one thread.
#
#   yade -j1 -n -x perf/level_set_peer/yade_packing.py packing_case.json OUT.json [FACTOR]
#
# FACTOR (default 1) multiplies the case's time step (packing.py runs 1, 0.9 and 0.8).
# OUT.json: per body its final state (as yade_impact.py), every level-set pair in contact at the
# end (penetration depth, normal from the second body towards the first, by name), the run's
# wall time and steps.
import json
import math
import os
import sys
import time

from yade import *  # noqa: F401,F403  (inside yade: O, utils, the functors)

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # inside yade: the script
from yade_common import SURFACE_NODES, body_like, prototype, quaternion_of, state_of  # noqa: E402


def build(case, step_factor):
    O.reset()
    material = FrictMat(young=case["youngs_modulus"], poisson=case["poisson_ratio"],
                        density=case["density"], frictionAngle=math.atan(case["friction"]))
    O.materials.append(material)
    protos = {name: prototype(s["half_axes"], s["n1"], s["n2"], SURFACE_NODES[name], material)
              for name, s in case["shapes"].items()}
    names = []
    for b in case["bodies"]:
        O.bodies.append(body_like(protos[b["shape"]], b["centre"], quaternion_of(b["rotation"]),
                                  material))
        names.append(b["name"])
    side = case["box_side"]
    for position, axis in ((0, 2), (0, 0), (side, 0), (0, 1), (side, 1)):
        O.bodies.append(utils.wall(position, axis=axis, sense=0, material=material))
    e = case["restitution"]
    O.engines = [ForceResetter(),
                 InsertionSortCollider([Bo1_LevelSet_Aabb(), Bo1_Wall_Aabb()], verletDist=0),
                 InteractionLoop([Ig2_LevelSet_LevelSet_ScGeom(), Ig2_Wall_LevelSet_ScGeom()],
                                 [Ip2_FrictMat_FrictMat_MindlinPhys(
                                     en=MatchMaker(algo="val", val=e),
                                     es=MatchMaker(algo="val", val=e))],
                                 [Law2_ScGeom_MindlinPhys_Mindlin()]),
                 NewtonIntegrator(damping=0, gravity=(0, 0, -9.81))]
    O.dt = case["time_step"] * step_factor
    return names


def contacts(names):
    """Level-set pairs touching at the end, keyed "first second" (names in order)."""
    out = {}
    for i in O.interactions:
        if not i.isReal or i.id1 >= len(names) or i.id2 >= len(names):
            continue
        depth = i.geom.penetrationDepth
        if depth <= 0:
            continue
        first, second = sorted((i.id1, i.id2), key=lambda k: names[k])
        # Yade's normal points from id1 to id2: from `second` towards `first` is -normal when
        # id1 is `first`.
        normal = -i.geom.normal if i.id1 == first else i.geom.normal
        out[f"{names[first]} {names[second]}"] = {"overlap": depth, "normal_j_to_i": list(normal)}
    return out


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: yade -j1 -n -x perf/level_set_peer/yade_packing.py CASE.json OUT.json "
                 "[FACTOR]")
    step_factor = float(sys.argv[3]) if len(sys.argv) == 4 else 1.0
    with open(sys.argv[1]) as f:
        case = json.load(f)
    start = time.perf_counter()
    names = build(case, step_factor)
    set_up = time.perf_counter() - start
    steps = int(round(case["duration"] / O.dt))
    start = time.perf_counter()
    O.run(steps, True)
    seconds = time.perf_counter() - start
    result = {"peer": "yade " + version, "threads": O.numThreads, "steps": steps,
              "set_up_seconds": set_up, "wall_seconds": seconds,
              "particle_steps_per_second": steps * len(names) / seconds,
              "surface_nodes": SURFACE_NODES,
              "bodies": [state_of(n, O.bodies[i]) for i, n in enumerate(names)],
              "contacts": contacts(names)}
    with open(sys.argv[2] + ".tmp", "w") as f:
        json.dump(result, f, indent=1)
    os.replace(sys.argv[2] + ".tmp", sys.argv[2])


main()
