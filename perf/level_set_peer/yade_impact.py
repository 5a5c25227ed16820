# The collisions of impact.py in Yade's level-set DEM: the same bodies, poses and velocities,
# each shape Yade's superellipsoid on a grid of kdem's default spacing (a fortieth of 2c) with
# about as many surface nodes as kdem's default points, one grid per shape (yade_common).
# Contact law: Yade's Hertz-Mindlin (Ip2_FrictMat_FrictMat_MindlinPhys, no damping, no
# friction), the law kdem uses; its Hertz radius is the harmonic mean of the contact point's
# distances to the centres (kdem's: from the surfaces' curvatures), so the two stiffnesses
# differ; the outcome of an elastic collision depends on them only at second order (impact.py
# measures that on the exact family at 4 E). No numerical damping, no gravity, one thread.
#
#   yade -j1 -n -x perf/level_set_peer/yade_impact.py impact_case.json OUT.json
#
# OUT.json: per body its final position, velocity, spin (world frame), rotation (9 numbers, row
# by row), mass and principal inertia; the run's wall time and steps; Yade's own total kinetic
# energy at the start and at the end.
import json
import os
import sys
import time

from yade import *  # noqa: F401,F403  (inside yade: O, the functors)

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # inside yade: the script
from yade_common import SURFACE_NODES, body_like, prototype, quaternion_of, state_of  # noqa: E402


def build(case):
    O.reset()
    material = FrictMat(young=case["youngs_modulus"], poisson=case["poisson_ratio"],
                        density=case["density"], frictionAngle=0)
    O.materials.append(material)
    protos = {name: prototype(s["half_axes"], s["n1"], s["n2"], SURFACE_NODES[name], material)
              for name, s in case["shapes"].items()}
    names = []
    for b in case["bodies"]:
        body = body_like(protos[b["shape"]], b["centre"], quaternion_of(b["rotation"]), material)
        body.state.vel = Vector3(*b["velocity"])
        O.bodies.append(body)
        names.append(b["name"])
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_LevelSet_Aabb()], verletDist=0),
                 InteractionLoop([Ig2_LevelSet_LevelSet_ScGeom()],
                                 [Ip2_FrictMat_FrictMat_MindlinPhys()],
                                 [Law2_ScGeom_MindlinPhys_Mindlin()]),
                 NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = case["time_step"]
    return names


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: yade -j1 -n -x perf/level_set_peer/yade_impact.py CASE.json OUT.json")
    with open(sys.argv[1]) as f:
        case = json.load(f)
    start = time.perf_counter()
    names = build(case)
    set_up = time.perf_counter() - start
    steps = int(round(case["duration"] / case["time_step"]))
    kinetic_at_start = utils.kineticEnergy()
    start = time.perf_counter()
    O.run(steps, True)
    seconds = time.perf_counter() - start
    result = {"peer": "yade " + version, "threads": O.numThreads, "steps": steps,
              "set_up_seconds": set_up, "wall_seconds": seconds,
              "kinetic_energy_at_start": kinetic_at_start,
              "kinetic_energy_at_end": utils.kineticEnergy(),
              "particle_steps_per_second": steps * len(names) / seconds,
              "surface_nodes": SURFACE_NODES,
              "bodies": [state_of(n, O.bodies[i]) for i, n in enumerate(names)]}
    with open(sys.argv[2] + ".tmp", "w") as f:
        json.dump(result, f, indent=1)
    os.replace(sys.argv[2] + ".tmp", sys.argv[2])


main()
