"""Writes the scenes of the elastic pair collision (book Sect. 4.3.1, Figs. 4.11-4.12): two
identical dilated polyhedra of one of four shapes (a dilated sphere, a super-ellipsoid, a
spherical-harmonic body and a polyhedron, all of the volume of a 20 mm sphere, dilation radius
2 mm) collide elastically and without friction, without gravity, each body moving at 0.5 m/s
towards the other with a fixed random orientation and a lateral offset. One scene per shape, so
that each run's series.csv holds one pair's energies.

usage: make_scene.py CALIBRATION.json OUTPUT_DIR [TIME_STEP]
  CALIBRATION.json (written by calibrate.py) gives each shape's core scale and the bounding
  radius the engine computed for it; OUTPUT_DIR receives <shape>.yaml for the four shapes, the
  finer sphere, and polyhedron.obj. TIME_STEP (default 1e-6 s) for the time-step check.
The module also serves calibrate.py (the shapes) and analyse.py (the constants)."""
import json
import math
import os
import sys

import numpy as np

SHAPES = ["sphere", "super_ellipsoid", "harmonic", "polyhedron"]
# A check beside the four: the dilated sphere with a ten times finer core (2000 nodes), to show
# how much of the sphere pair's spin comes from the facets of the 200-node core.
FINE_SPHERE = "sphere_2000_nodes"
ALL_SHAPES = SHAPES + [FINE_SPHERE]
EQUIVALENT_RADIUS = 0.020  # m: the volume-equivalent radius of every body (book Table A6.1 #1)
TARGET_VOLUME = 4.0 / 3.0 * math.pi * EQUIVALENT_RADIUS ** 3
DILATION = 0.002  # m
DENSITY = 2500.0
YOUNGS_MODULUS = 5.0e9
POISSON = 0.3
SPEED = 0.5  # m/s: each body moves at this speed towards the other (relative speed 1 m/s)
OFFSET = 0.010  # m: lateral (y) distance between the two centres' lines of approach
GAP = 0.001  # m: between the two bounding spheres at the start
TIME_STEP = 1.0e-6  # s: 1/340 of the Hertz duration of the central sphere impact (3.4e-4 s)
DURATION = 0.100  # s: analyse.py checks that the bodies are apart for good by then
SERIES_INTERVAL = TIME_STEP  # every step, so that no contact episode is missed
SEED = 20260431  # of the orientations
BOX_SLACK = 1e-3

# The super-ellipsoid's semi-axes ratio and exponents (the book does not give them).
SUPER_ELLIPSOID = {"a": 1.4, "b": 1.0, "c": 0.8, "n1": 3, "n2": 3}
# The harmonic body: a unit sphere (A_00 = 2 sqrt(pi)) made irregular by five low-degree terms;
# its radius lies between 0.62 and 1.41 (sampled finely), star-shaped, a little concave in places.
HARMONICS = [[0, 0, 2.0 * math.sqrt(math.pi), 0.0], [2, 0, -0.30, 0.0], [2, 2, 0.22, 0.12],
             [3, 1, 0.18, -0.12], [3, 2, -0.08, 0.10], [4, 3, 0.08, -0.06]]
POLYHEDRON_POINTS = 12  # the convex hull of this many random points, radius 0.8 to 1.2
POLYHEDRON_SEED = 7


def polyhedron_points():
    rng = np.random.default_rng(POLYHEDRON_SEED)
    directions = rng.normal(size=(POLYHEDRON_POINTS, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    return directions * rng.uniform(0.8, 1.2, size=(POLYHEDRON_POINTS, 1))


def write_polyhedron_obj(path):
    """The convex hull of the random points as an OBJ mesh (outward triangles); returns its
    vertex and triangle counts and its volume at unit scale."""
    from scipy.spatial import ConvexHull
    points = polyhedron_points()
    hull = ConvexHull(points)
    used = sorted(set(hull.simplices.ravel()))
    index = {old: new for new, old in enumerate(used)}
    centre = points[used].mean(axis=0)
    lines = [f"# the convex hull of {POLYHEDRON_POINTS} random points (seed {POLYHEDRON_SEED}), "
             "unit scale\n"]
    lines += [f"v {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n" for p in points[used]]
    for tri in hull.simplices:
        a, b, c = points[tri]
        if np.dot(np.cross(b - a, c - a), a - centre) < 0:
            tri = tri[[0, 2, 1]]
        lines.append("f " + " ".join(str(index[t] + 1) for t in tri) + "\n")
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.writelines(lines)
    os.replace(tmp, path)
    return len(used), len(hull.simplices), hull.volume


def shape_mapping(name, scale):
    """The `dilated_polyhedron` mapping of a shape at a core scale (200 nodes for the sampled
    cores: the book's 200 nodes and 396 triangles)."""
    if name == "sphere":
        core = "superquadric: {a: 1, b: 1, c: 1, n1: 2, n2: 2}, nodes: 200"
    elif name == FINE_SPHERE:
        core = "superquadric: {a: 1, b: 1, c: 1, n1: 2, n2: 2}, nodes: 2000"
    elif name == "super_ellipsoid":
        core = ("superquadric: {" + ", ".join(f"{k}: {v}" for k, v in SUPER_ELLIPSOID.items())
                + "}, nodes: 200")
    elif name == "harmonic":
        core = ("harmonics: {coefficients: ["
                + ", ".join(f"[{n}, {m}, {re:.17g}, {im:.17g}]" for n, m, re, im in HARMONICS)
                + "]}, nodes: 200")
    elif name == "polyhedron":
        core = "mesh: polyhedron.obj"
    else:
        raise ValueError(name)
    return f"{{{core}, scale: {scale:.17g}, dilation_radius: {DILATION}}}"


MATERIAL = (f"  - {{name: elastic, density: {DENSITY}, youngs_modulus: {YOUNGS_MODULUS}, "
            f"poisson_ratio: {POISSON},\n     restitution: 1.0, friction: 0.0, "
            f"rolling_friction: 0.0}}\n")


def random_quaternion(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def orientations(name):
    """Two fixed random orientations per shape (uniform on the rotations)."""
    rng = np.random.default_rng([SEED, ALL_SHAPES.index(name)])
    return random_quaternion(rng), random_quaternion(rng)


def source(label, shape, centre, half, velocity, quaternion):
    lo = ", ".join(f"{v - half:.12g}" for v in centre)
    hi = ", ".join(f"{v + half:.12g}" for v in centre)
    return (f"  - name: {label}\n"
            f"    material: elastic\n"
            f"    shape: {shape}\n"
            f"    orientation: [{', '.join(f'{q:.17g}' for q in quaternion)}]\n"
            f"    velocity: [{velocity}, 0, 0]\n"
            f"    count: 1\n"
            f"    region: {{box: {{min: [{lo}], max: [{hi}]}}}}\n")


def initial_centres(bounding_radius):
    """Body a on the left moving +x, body b on the right moving -x, their lines of approach
    OFFSET apart in y, their bounding spheres GAP apart."""
    x = bounding_radius + GAP / 2
    return (-x, -OFFSET / 2, 0.0), (x, OFFSET / 2, 0.0)


def pair_scene(name, scale, bounding_radius, time_step=TIME_STEP):
    qa, qb = orientations(name)
    ca, cb = initial_centres(bounding_radius)
    half = bounding_radius * (1 + BOX_SLACK)
    return f"""# Generated by make_scene.py: the book's elastic collision of two identical dilated
# polyhedra (Sect. 4.3.1, Figs. 4.11-4.12), shape '{name}', volume-equivalent radius
# {EQUIVALENT_RADIUS} m, dilation {DILATION} m, each body at {SPEED} m/s towards the other, lateral
# offset {OFFSET} m, fixed random orientations, no friction, no gravity. See README.md.
time_step: {time_step}
duration: {DURATION}
gravity: [0, 0, 0]
materials:
{MATERIAL}shapes:
  - name: {name}
    dilated_polyhedron: {shape_mapping(name, scale)}
particles:
{source("a", name, ca, half, SPEED, qa)}{source("b", name, cb, half, -SPEED, qb)}output:
  series_interval: {SERIES_INTERVAL}
"""


def write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    time_step = float(sys.argv[3]) if len(sys.argv) == 4 else TIME_STEP
    with open(sys.argv[1]) as f:
        calibration = json.load(f)
    out = sys.argv[2]
    os.makedirs(out, exist_ok=True)
    write_polyhedron_obj(os.path.join(out, "polyhedron.obj"))
    for name in ALL_SHAPES:
        shape = calibration["shapes"][name]
        write(os.path.join(out, f"{name}.yaml"),
              pair_scene(name, shape["scale"], shape["bounding_radius_m"], time_step))


if __name__ == "__main__":
    main()
