"""Writes the scene of the packing case (book Sect. 4.3.3, Figs. 4.19-4.20): COUNT dilated
polyhedra of the book's nine shapes in equal numbers, placed at random positions and orientations
without overlap in a 0.6 x 0.6 x 2 m container (a floor and four side planes, open at the top), fall
under gravity and settle. Every body has the volume of a 40 mm sphere (its core scaled by
calibrate.py), dilation radius 5 mm, E = 1e7 Pa, nu = 0.3, rho = 2500 kg/m3, restitution 0.3,
friction 0.3, rolling friction 0.001 (book Table A6.1 row 4b).

usage: make_scene.py CALIBRATION.json OUTPUT.yaml [--count N] [--duration T] [--height H]
                     [--width W]
  CALIBRATION.json: the core scales (calibrate.py). The meshes (make_meshes.py) must lie beside
  OUTPUT.yaml. --height: the top of the region the particles are placed in (default the
  container's 2 m). --width: the container's side (default the book's 0.6 m; a narrower
  container with fewer particles keeps the bed as deep as the book's).
The module also serves calibrate.py and analyse.py (the constants)."""
import argparse
import json
import math
import os

SHAPES = ["sphere", "super_ellipsoid", "harmonic", "tetrahedron", "hexahedron",
          "concave_tetrahedron", "l_prism", "holed_block", "ring"]
LABELS = {"sphere": "sphere", "super_ellipsoid": "super-ellipsoid", "harmonic": "spherical harmonic",
          "tetrahedron": "tetrahedron", "hexahedron": "hexahedron",
          "concave_tetrahedron": "concave tetrahedron", "l_prism": "concave hexahedron (L prism)",
          "holed_block": "concave hexahedron with cavity", "ring": "ring (torus)"}
MESH_SHAPES = ["tetrahedron", "hexahedron", "concave_tetrahedron", "l_prism", "holed_block", "ring"]

EQUIVALENT_DIAMETER = 0.040  # m (book Table A6.1 row 4b: volume-equivalent diameter 40 mm)
TARGET_VOLUME = math.pi / 6.0 * EQUIVALENT_DIAMETER ** 3
DILATION = 0.005             # m
DENSITY = 2500.0
YOUNGS_MODULUS = 1.0e7
POISSON = 0.3
RESTITUTION = 0.3
FRICTION = 0.3
ROLLING_FRICTION = 0.001
BOX = (0.6, 0.6, 2.0)        # m: the container (x, y centred on 0; floor at z = 0)
COUNT = 2000
SEED = 4319                  # first source's seed; source k uses SEED + k

# The super-ellipsoid and the spherical-harmonic body (the book gives no parameters): the same
# as in the elastic pair collision case (book Sect. 4.3.1). Super-ellipsoid semi-axes 1.4 : 1 :
# 0.8 with n1 = n2 = 3; the harmonic body a unit sphere (A_00 = 2 sqrt(pi)) made irregular by
# five low-degree terms (radius 0.62 to 1.41 of the base, star-shaped, a little concave). Both
# sampled at the book's 200 Fibonacci nodes (396 triangles), as is the sphere.
SUPER_ELLIPSOID = {"a": 1.4, "b": 1.0, "c": 0.8, "n1": 3, "n2": 3}
HARMONICS = [[0, 0, 2.0 * math.sqrt(math.pi), 0.0], [2, 0, -0.30, 0.0], [2, 2, 0.22, 0.12],
             [3, 1, 0.18, -0.12], [3, 2, -0.08, 0.10], [4, 3, 0.08, -0.06]]
NODES = 200

# Time step: 1/50 of the Hertz contact time of two of these bodies (equivalent spheres of 20 mm,
# E* = E / (2 (1 - nu^2)), m* = m / 2, R* = R / 2) meeting at the fastest impact speed of the pour,
# sqrt(2 g H) for the top of the placement region H (2 m: 6.3 m/s, t_c = 2.8e-3 s, dt = 5.6e-5 s),
# rounded down; slower impacts last longer (t_c ~ v^-1/5). `kdem check` prints the engine's Hertz
# time at its own fastest speed and its advice (at most 10 % of it, 20 % of the Rayleigh time).
STEP_FRACTION = 50.0


def hertz_time(speed):
    mass = DENSITY * TARGET_VOLUME
    e_star = YOUNGS_MODULUS / (2 * (1 - POISSON ** 2))
    m_star, r_star = mass / 2, EQUIVALENT_DIAMETER / 4
    return 2.868 * (m_star ** 2 / (r_star * e_star ** 2 * speed)) ** 0.2


def time_step(height):
    dt = hertz_time(math.sqrt(2 * 9.81 * height)) / STEP_FRACTION
    digits = 10 ** math.floor(math.log10(dt) - 1)
    return math.floor(dt / digits) * digits


DURATION = 4.0               # s (default; run.sh sets it)
FRAME_INTERVAL = 0.25        # s
SERIES_INTERVAL = 0.005      # s
CHECKPOINT_INTERVAL = 0.1    # s (a long run can be continued with --restart)
# At 6 m/s two of these soft bodies overlap by about 6 mm (Hertz), 0.2-0.25 of their bounding
# radii, near the default stop at 0.25: the stop is raised to 0.5 (half a bounding radius; the
# cores themselves meet only at an overlap of 2 r = 10 mm). README.md gives the largest overlap.
MAX_OVERLAP_RATIO = 0.5


def shape_mapping(name, scale):
    """The `dilated_polyhedron` mapping of a shape whose core is scaled by `scale`."""
    if name == "sphere":
        core = f"superquadric: {{a: 1, b: 1, c: 1, n1: 2, n2: 2}}, nodes: {NODES}"
    elif name == "super_ellipsoid":
        core = ("superquadric: {" + ", ".join(f"{k}: {v}" for k, v in SUPER_ELLIPSOID.items())
                + f"}}, nodes: {NODES}")
    elif name == "harmonic":
        core = ("harmonics: {coefficients: ["
                + ", ".join(f"[{n}, {m}, {re:.17g}, {im:.17g}]" for n, m, re, im in HARMONICS)
                + f"]}}, nodes: {NODES}")
    elif name in MESH_SHAPES:
        core = f"mesh: {name}.obj"
    else:
        raise ValueError(name)
    return f"{{{core}, scale: {scale:.17g}, dilation_radius: {DILATION}}}"


MATERIAL = (f"  - {{name: grain, density: {DENSITY}, youngs_modulus: {YOUNGS_MODULUS}, "
            f"poisson_ratio: {POISSON},\n     restitution: {RESTITUTION}, friction: {FRICTION}, "
            f"rolling_friction: {ROLLING_FRICTION}}}\n")


def shapes_text(scales):
    return "".join(f"  - name: {n}\n    dilated_polyhedron: {shape_mapping(n, scales[n])}\n"
                   for n in SHAPES)


def counts(total):
    """Equal numbers of the nine shapes; the first total % 9 shapes get one more."""
    base, extra = divmod(total, len(SHAPES))
    return {n: base + (1 if k < extra else 0) for k, n in enumerate(SHAPES)}


def walls_text(width):
    hx, hy = width / 2, width / 2
    planes = [("floor", (0, 0, 0), (0, 0, 1)), ("x_min", (-hx, 0, 0), (1, 0, 0)),
              ("x_max", (hx, 0, 0), (-1, 0, 0)), ("y_min", (0, -hy, 0), (0, 1, 0)),
              ("y_max", (0, hy, 0), (0, -1, 0))]
    return "".join(f"  - {{name: {n}, material: grain, plane: {{point: [{p[0]}, {p[1]}, {p[2]}], "
                   f"normal: [{d[0]}, {d[1]}, {d[2]}]}}}}\n" for n, p, d in planes)


def scene_text(scales, total, duration, height, width):
    hx, hy = width / 2, width / 2
    sources = ""
    for k, (name, n) in enumerate(counts(total).items()):
        sources += (f"  - {{name: {name}, material: grain, shape: {name}, count: {n}, "
                    f"seed: {SEED + k}, tag: {name},\n"
                    f"     region: {{box: {{min: [{-hx}, {-hy}, 0], max: [{hx}, {hy}, {height}]}}}}}}\n")
    return f"""# Generated by make_scene.py: the packing of the book's mixed dilated polyhedra (Sect. 4.3.3,
# Figs. 4.19-4.20): {total} bodies of nine shapes, volume-equivalent diameter {EQUIVALENT_DIAMETER} m,
# dilation radius {DILATION} m, random positions and orientations in a {width} x {width} x {BOX[2]} m
# container (placed up to {height} m), falling under gravity until at rest.
time_step: {time_step(height):.3g}
duration: {duration}
gravity: [0, 0, -9.81]
materials:
{MATERIAL}shapes:
{shapes_text(scales)}particles:
{sources}walls:
{walls_text(width)}domain: {{min: [{-hx - 0.1}, {-hy - 0.1}, -0.1], max: [{hx + 0.1}, {hy + 0.1}, {BOX[2] + 0.1}]}}
checks: {{max_overlap_ratio: {MAX_OVERLAP_RATIO}}}
output: {{frame_interval: {FRAME_INTERVAL}, series_interval: {SERIES_INTERVAL}, checkpoint_interval: {CHECKPOINT_INTERVAL}}}
"""


def write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("calibration")
    parser.add_argument("output")
    parser.add_argument("--count", type=int, default=COUNT)
    parser.add_argument("--duration", type=float, default=DURATION)
    parser.add_argument("--height", type=float, default=BOX[2])
    parser.add_argument("--width", type=float, default=BOX[0])
    args = parser.parse_args()
    with open(args.calibration) as f:
        calibration = json.load(f)
    scales = {n: calibration["shapes"][n]["scale"] for n in SHAPES}
    write(args.output, scene_text(scales, args.count, args.duration, args.height, args.width))


if __name__ == "__main__":
    main()
