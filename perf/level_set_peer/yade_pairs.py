# Yade's level-set DEM (Duriez and Galusa 2021; Debian's `yade` package) on the pairs of
# kdem_bench_level_set_accuracy: the same superquadrics at the same poses, overlapping by a / 100
# in the exact narrow phase. Each shape is Yade's predefined superellipsoid (epsilons 2 / n, the
# same surface), on a grid of the same spacing (a fortieth of the smallest extent 2c) with about
# as many surface nodes as kdem's defaults give (Yade wants a square plus 2). All pairs of a shape
# are set up at once, far apart, static, every body holding the shape's one grid (yade_common);
# each step computes every pair's geometry (Ig2_LevelSet_LevelSet_ScGeom); the time per pair is
# the median over steps of the step's time (collider, geometry, the linear contact law) over the
# pair count, one thread.
#
#   yade -j1 -n -x perf/level_set_peer/yade_pairs.py PAIRS.json OUT.json [STEPS]
#
# PAIRS.json: kdem_bench_level_set_accuracy --pairs-out. OUT.json: per shape, the median and
# largest relative overlap error (against the exact overlap; a pair not found counts 1), the
# median and largest normal error (rad), and the time per pair.
import json
import math
import os
import statistics
import sys
import time

from yade import *  # noqa: F401,F403  (inside yade: O, the functors)

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # inside yade: the script
from yade_common import SPACING_CELLS, body_like, prototype, quaternion_of  # noqa: E402

SURFACE_NODES = {"ellipsoid_1_0.7_0.5": 42 * 42 + 2, "blocky_1_0.8_0.6_n4": 45 * 45 + 2}
SEPARATION = 10.0  # between pairs, in units of the shape's largest half-axis


def add_pair(proto, pair, origin):
    ids = []
    for rows, centre in ((pair["rotation_a"], origin),
                         (pair["rotation_b"], origin + Vector3(*pair["offset"]))):
        body = body_like(proto, centre, quaternion_of(rows), O.materials[0], dynamic=False)
        ids.append(O.bodies.append(body))
    return ids


def angle(u, v):
    return math.atan2(u.cross(v).norm(), u.dot(v))


def run_shape(shape, steps):
    O.reset()
    O.materials.append(FrictMat())
    nodes = SURFACE_NODES[shape["name"]]
    a = shape["half_axes"][0]
    proto = prototype(shape["half_axes"], shape["n1"], shape["n2"], nodes, O.materials[0])
    pairs = []
    for k, pair in enumerate(shape["pairs"]):
        pairs.append(add_pair(proto, pair, Vector3(SEPARATION * a * k, 0, 0)))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_LevelSet_Aabb()], verletDist=0),
                 InteractionLoop([Ig2_LevelSet_LevelSet_ScGeom()],
                                 [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack(sphericalBodies=False)]),
                 NewtonIntegrator()]
    O.dt = 1e-12
    O.step()  # the collider finds the pairs
    times = []
    for _ in range(steps):
        start = time.perf_counter()
        O.step()
        times.append((time.perf_counter() - start) / len(pairs))
    overlap_errors, normal_errors, missed = [], [], 0
    for (i, j), pair in zip(pairs, shape["pairs"]):
        exact = pair["exact_overlap"]
        inter = O.interactions[i, j] if O.interactions.has(i, j) else None
        if inter is None or not inter.isReal or inter.geom.penetrationDepth <= 0:
            missed += 1
            overlap_errors.append(1.0)
            continue
        overlap_errors.append(abs(inter.geom.penetrationDepth - exact) / exact)
        # Yade's normal points from the first body (a) to the second (b); the exact one from b
        # towards a.
        normal = inter.geom.normal if inter.id1 == i else -inter.geom.normal
        normal_errors.append(angle(-normal, Vector3(*pair["exact_normal"])))
    return {"name": shape["name"], "pairs": len(pairs), "surface_nodes": nodes,
            "grid_spacing": 2 * shape["half_axes"][2] / SPACING_CELLS,
            "grid_nodes": O.bodies[0].shape.lsGrid.nGP[0] * O.bodies[0].shape.lsGrid.nGP[1]
            * O.bodies[0].shape.lsGrid.nGP[2],
            "overlap_error_median": statistics.median(overlap_errors),
            "overlap_error_max": max(overlap_errors),
            "normal_error_median_rad": statistics.median(normal_errors) if normal_errors else None,
            "normal_error_max_rad": max(normal_errors) if normal_errors else None,
            "missed": missed, "us_per_pair": 1e6 * statistics.median(times),
            "steps_timed": steps}


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: yade -j1 -n -x perf/level_set_peer/yade_pairs.py PAIRS.json OUT.json "
                 "[STEPS]")
    with open(sys.argv[1]) as f:
        given = json.load(f)
    steps = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    result = {"peer": "yade " + version, "kdem_pairs_from": given["git_hash"],
              "threads": O.numThreads, "shapes": [run_shape(s, steps) for s in given["shapes"]]}
    tmp = sys.argv[2] + ".tmp"
    with open(tmp, "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    os.replace(tmp, sys.argv[2])
    print(json.dumps(result, indent=1))


main()
