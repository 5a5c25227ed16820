"""Writes stack.yaml and the plate cores plate_r0.1.obj and plate_r5.obj beside it: the book's
vertical stacks (Sect. 4.3.3, Fig. 4.18) of dilated cylinders (D = 60 mm, H = 10 mm, a core from a
cylinder-like superquadric) and dilated rectangular plates (80 x 80 x 10 mm, a box core), at
dilation radius r = 0.1 mm and 5 mm, and a mixed stack of plates and cylinders alternating at
r = 0.1 mm, all resting under gravity on one plane, each stack far from the others.

The engine places particles as their bounding spheres (docs/scene.md, "shapes"), which for these
flat bodies means 50-110 mm between the bodies of a stack. The scene therefore places every body
at a position of its own, apart from the others, and place_stack.py then moves them in the
checkpoint written at step 0 to their places in the stacks, with GAP between neighbours, before
the run proper restarts from it.

usage: make_scene.py OUTPUT_DIR   (writes OUTPUT_DIR/stack.yaml and the meshes)"""
import math
import os
import sys

# Material (the book gives none for this case: book digest Table A6.1, row 4a).
DENSITY = 2500.0        # kg/m3
YOUNGS_MODULUS = 1.0e8  # Pa
POISSON_RATIO = 0.3
RESTITUTION = 0.2       # low, so that the stacks settle quickly
FRICTION = 0.3

COUNT = 5               # bodies per stack
GAP = 5.0e-5            # m between neighbours (and the lowest body and the plane) at the start
STACK_SPACING = 0.3     # m between stack axes, along x
TIME_STEP = 5.0e-5      # s (half of what kdem check suggests: 1.02e-4 s)
DURATION = 0.25        # s
FRAME_INTERVAL = 0.025  # s
SERIES_INTERVAL = 1.0e-3

CYLINDER_RADIUS = 0.030     # D = 60 mm
CYLINDER_HALF_HEIGHT = 0.005  # H = 10 mm
PLATE_HALF = (0.040, 0.040, 0.005)  # 80 x 80 x 10 mm
# The core's half-thickness where H/2 - r would leave none (r = 5 mm): the body is then
# 2 (CORE_MIN_HALF + r) = 11 mm thick, 1 mm more than the book's 10 mm.
CORE_MIN_HALF = 5.0e-4
SUPERQUADRIC_N1 = 20        # flat ends (the largest exponent the engine accepts)
SUPERQUADRIC_N2 = 2         # round section
NODES = 4000               # lattice directions: 2 % of them reach the rim of the r = 5 mm core
# Triangles kept (the flat ends merged, the rim kept): 160 for r = 0.1 mm; the 1 mm thin core of
# r = 5 mm loses its rim below about 400 (its mass falls from 68 g to 37 g at 160).
SIMPLIFY_TO = {1.0e-4: 160, 5.0e-3: 400}

SHAPES = {
    # name: (kind, dilation radius)
    "cylinder_r0.1": ("cylinder", 1.0e-4),
    "cylinder_r5": ("cylinder", 5.0e-3),
    "plate_r0.1": ("plate", 1.0e-4),
    "plate_r5": ("plate", 5.0e-3),
}
# Stacks, bottom body first.
STACKS = {
    "cylinders_r0.1": ["cylinder_r0.1"] * COUNT,
    "cylinders_r5": ["cylinder_r5"] * COUNT,
    "plates_r0.1": ["plate_r0.1"] * COUNT,
    "plates_r5": ["plate_r5"] * COUNT,
    "mixed_r0.1": ["plate_r0.1", "cylinder_r0.1"] * (COUNT // 2) + ["plate_r0.1"] * (COUNT % 2),
}


def core_half_extents(shape):
    """Half-sizes (x, y, z) of the core of a shape: the body's less r, the thickness at least
    CORE_MIN_HALF."""
    kind, r = SHAPES[shape]
    if kind == "cylinder":
        half = (CYLINDER_RADIUS, CYLINDER_RADIUS, CYLINDER_HALF_HEIGHT)
    else:
        half = PLATE_HALF
    return (half[0] - r, half[1] - r, max(half[2] - r, CORE_MIN_HALF))


def half_thickness(shape):
    """Half of the body's thickness along z: the core's plus r."""
    return core_half_extents(shape)[2] + SHAPES[shape][1]


def bounding_radius_bound(shape):
    """An upper bound of the body's bounding radius: the farthest point of the core's box (of its
    cylinder for a cylinder: the superquadric with n2 = 2 lies within it) plus r."""
    kind, r = SHAPES[shape]
    hx, hy, hz = core_half_extents(shape)
    if kind == "cylinder":
        return math.hypot(hx, hz) + r
    return math.sqrt(hx * hx + hy * hy + hz * hz) + r


def write_box_obj(path, half):
    """A closed, outward box of half-sizes half, centred at the origin, 12 triangles."""
    hx, hy, hz = half
    vertices = [(sx * hx, sy * hy, sz * hz) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
    # vertex index = 1 + ix + 2 iy + 4 iz (OBJ numbers from 1); faces outward (counter-clockwise
    # seen from outside).
    quads = [(1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3), (2, 4, 8, 6)]
    with open(path, "w") as f:
        f.write(f"# box core {2 * hx * 1e3:.6g} x {2 * hy * 1e3:.6g} x {2 * hz * 1e3:.6g} mm\n")
        for v in vertices:
            f.write("v {:.12g} {:.12g} {:.12g}\n".format(*v))
        for a, b, c, d in quads:
            f.write(f"f {a} {b} {c}\nf {a} {c} {d}\n")


def shape_entry(shape):
    kind, r = SHAPES[shape]
    hx, hy, hz = core_half_extents(shape)
    if kind == "cylinder":
        return (f"  - name: {shape}\n"
                f"    dilated_polyhedron:\n"
                f"      superquadric: {{a: {hx:.12g}, b: {hy:.12g}, c: {hz:.12g}, "
                f"n1: {SUPERQUADRIC_N1}, n2: {SUPERQUADRIC_N2}}}\n"
                f"      nodes: {NODES}\n"
                f"      simplify_to: {SIMPLIFY_TO[r]}\n"
                f"      dilation_radius: {r:.12g}\n")
    return (f"  - name: {shape}\n"
            f"    dilated_polyhedron: {{mesh: {shape}.obj, dilation_radius: {r:.12g}}}\n")


def stack_layout():
    """Every body: (stack, level, shape, start position in the scene, target position in the
    stack). Start positions stand on a column of the stack's x at y = 0.15 m, each body's bounding
    sphere clear of its neighbours' and of the plane; targets rest on the plane at y = 0 with GAP
    between neighbours."""
    bodies = []
    for s, (stack, shapes) in enumerate(STACKS.items()):
        x = s * STACK_SPACING
        z_start = 0.0
        z_target = 0.0
        for level, shape in enumerate(shapes):
            radius = bounding_radius_bound(shape) * 1.05
            z_start += radius + 2e-3
            z_target += GAP + half_thickness(shape)
            bodies.append((stack, level, shape, (x, 0.15, z_start), (x, 0.0, z_target)))
            z_start += radius
            z_target += half_thickness(shape)
    return bodies


def scene_text():
    lines = [
        "# The book's vertical stacks (Sect. 4.3.3, Fig. 4.18): written by make_scene.py. The bodies",
        "# are placed apart here and moved into their stacks by place_stack.py (see README.md).",
        f"time_step: {TIME_STEP:g}",
        f"duration: {DURATION:g}",
        "gravity: [0, 0, -9.81]",
        "materials:",
        "  - name: stack_material",
        f"    density: {DENSITY:g}",
        f"    youngs_modulus: {YOUNGS_MODULUS:g}",
        f"    poisson_ratio: {POISSON_RATIO:g}",
        f"    restitution: {RESTITUTION:g}",
        f"    friction: {FRICTION:g}",
        "shapes:",
    ]
    text = "\n".join(lines) + "\n"
    for shape in SHAPES:
        text += shape_entry(shape)
    text += "particles:\n"
    for stack, level, shape, start, _ in stack_layout():
        half = bounding_radius_bound(shape) * 1.05
        lo = ", ".join(f"{v - half:.12g}" for v in start)
        hi = ", ".join(f"{v + half:.12g}" for v in start)
        text += (f"  - name: {stack}_{level}\n"
                 f"    material: stack_material\n"
                 f"    shape: {shape}\n"
                 f"    orientation: [1, 0, 0, 0]\n"
                 f"    tag: {stack}\n"
                 f"    count: 1\n"
                 f"    region: {{box: {{min: [{lo}], max: [{hi}]}}}}\n")
    text += ("walls:\n"
             "  - name: floor\n"
             "    material: stack_material\n"
             "    plane: {point: [0, 0, 0], normal: [0, 0, 1]}\n"
             "output:\n"
             f"  frame_interval: {FRAME_INTERVAL:g}\n"
             f"  series_interval: {SERIES_INTERVAL:g}\n"
             "  contact_forces: true\n")
    return text


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for shape, (kind, _) in SHAPES.items():
        if kind == "plate":
            write_box_obj(os.path.join(out, f"{shape}.obj"), core_half_extents(shape))
    with open(os.path.join(out, "stack.yaml"), "w") as f:
        f.write(scene_text())


if __name__ == "__main__":
    main()
