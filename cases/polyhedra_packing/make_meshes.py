"""Writes the cores of the six mesh shapes of the packing case (book Sect. 4.3.3, Fig. 4.19) as
closed, outward-wound OBJ triangle meshes at unit scale (the scene scales each core so that the
dilated body has the volume of a 40 mm sphere; calibrate.py finds the factors):

  tetrahedron          4 vertices /  4 triangles  regular, edge 2 sqrt(2)
  hexahedron           8 vertices / 12 triangles  cube of side 2
  concave_tetrahedron  5 vertices /  6 triangles  the tetrahedron with one face dented: that
                                                   face's centre moved inward along the axis
                                                   to DENT of the height (from the face)
  l_prism             12 vertices / 20 triangles  concave hexahedron without cavity: an L-shaped
                                                   hexagon (2 x 2 less a 1 x 1 corner) extruded
                                                   by 1
  holed_block         16 vertices / 32 triangles  concave hexahedron with an internal cavity: a
                                                   2 x 2 x HOLED_HEIGHT block with a square hole
                                                   of side HOLE through it (genus 1)
  ring                192 vertices / 384 triangles a closed torus, 24 segments round the axis x 8
                                                   round the tube, major radius RING_MAJOR, tube 1

The book's ring has 192 nodes and 368 triangles, which is not a closed surface (V - E + F = 8); a
closed torus of 192 nodes has 384 triangles. Each mesh is checked here: every edge in exactly two
triangles, once in each direction (closed, consistently oriented), positive volume (outward), and
its Euler characteristic (2, or 0 for the holed block and the ring).

usage: make_meshes.py OUTPUT_DIR"""
import math
import os
import sys

import numpy as np

DENT = 0.40          # concave tetrahedron: dent depth as a fraction of the height over the face
HOLE = 1.2           # holed block: side of the square hole (the block's side is 2)
HOLED_HEIGHT = 0.6   # holed block: thickness
RING_MAJOR = 5.0     # ring: major radius over the core tube's radius
RING_SEGMENTS = 24   # ring: nodes round the axis
RING_TUBE = 8        # ring: nodes round the tube

MESHES = ["tetrahedron", "hexahedron", "concave_tetrahedron", "l_prism", "holed_block", "ring"]
EXPECTED = {"tetrahedron": (4, 4, 2), "hexahedron": (8, 12, 2), "concave_tetrahedron": (5, 6, 2),
            "l_prism": (12, 20, 2), "holed_block": (16, 32, 0), "ring": (192, 384, 0)}


def tetrahedron():
    v = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
    f = [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]
    return v, f


def hexahedron():
    v = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], float)
    # vertex index = 4 z + 2 y + x (0/1 for -1/+1)
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    f = []
    for a, b, c, d in quads:
        f += [[a, b, c], [a, c, d]]
    return v, f


def concave_tetrahedron():
    """The regular tetrahedron's face opposite vertex 0 ((1,1,1)) replaced by three triangles to
    its centre, moved inward along the axis by DENT of the height."""
    v, _ = tetrahedron()
    face_centre = v[1:].mean(axis=0)              # (-1/3, -1/3, -1/3)
    height = np.linalg.norm(v[0] - face_centre)   # 4 / sqrt(3)
    axis = (v[0] - face_centre) / height
    dent = face_centre + DENT * height * axis
    v = np.vstack([v, dent])
    f = [[0, 1, 2], [0, 2, 3], [0, 3, 1], [4, 2, 1], [4, 3, 2], [4, 1, 3]]
    return v, f


def prism(outline, height):
    """A polygon (counter-clockwise in xy, star-shaped from its first corner) extruded along z:
    bottom corners 0..n-1, top n..2n-1; the caps as fans from the first corner."""
    n = len(outline)
    v = np.array([[x, y, 0.0] for x, y in outline] + [[x, y, height] for x, y in outline])
    f = []
    for k in range(1, n - 1):
        f.append([0, k + 1, k])              # bottom, seen from below: clockwise in xy
        f.append([n, n + k, n + k + 1])      # top
    for k in range(n):
        a, b = k, (k + 1) % n
        f += [[a, b, n + b], [a, n + b, n + a]]
    return v, f


def l_prism():
    return prism([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)], 1.0)


def holed_block():
    """Outer square side 2, hole side HOLE, thickness HOLED_HEIGHT: corners outer bottom 0-3,
    inner bottom 4-7, outer top 8-11, inner top 12-15 (counter-clockwise in xy)."""
    o, i, h = 1.0, HOLE / 2, HOLED_HEIGHT / 2
    square = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    v = np.array([[o * x, o * y, -h] for x, y in square] + [[i * x, i * y, -h] for x, y in square]
                 + [[o * x, o * y, h] for x, y in square] + [[i * x, i * y, h] for x, y in square])
    f = []
    for k in range(4):
        n = (k + 1) % 4
        ob, ib, ot, it = k, 4 + k, 8 + k, 12 + k
        obn, ibn, otn, itn = n, 4 + n, 8 + n, 12 + n
        f += [[ob, obn, otn], [ob, otn, ot]]        # outer side, facing out
        f += [[ib, it, itn], [ib, itn, ibn]]        # hole side, facing the hole's axis
        f += [[ot, otn, itn], [ot, itn, it]]        # top annulus, facing +z
        f += [[ob, ib, ibn], [ob, ibn, obn]]        # bottom annulus, facing -z
    return v, f


def ring():
    n, m = RING_SEGMENTS, RING_TUBE
    v = []
    for i in range(n):
        u = 2 * math.pi * i / n
        for j in range(m):
            w = 2 * math.pi * j / m
            rho = RING_MAJOR + math.cos(w)
            v.append([rho * math.cos(u), rho * math.sin(u), math.sin(w)])
    f = []
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, ((i + 1) % n) * m + j
            c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
            f += [[a, b, c], [a, c, d]]
    return np.array(v), f


BUILDERS = {"tetrahedron": tetrahedron, "hexahedron": hexahedron,
            "concave_tetrahedron": concave_tetrahedron, "l_prism": l_prism,
            "holed_block": holed_block, "ring": ring}


def signed_volume(v, f):
    a, b, c = (v[np.array(f)[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def check(name, v, f):
    """Closed and consistently oriented (every directed edge once, its reverse once), outward,
    the expected counts and Euler characteristic."""
    directed = {}
    for t in f:
        for k in range(3):
            e = (t[k], t[(k + 1) % 3])
            if e in directed:
                sys.exit(f"{name}: edge {e} twice in one direction")
            directed[e] = True
    for a, b in directed:
        if (b, a) not in directed:
            sys.exit(f"{name}: edge {a}-{b} has no partner (open or inconsistently wound)")
    edges = len(directed) // 2
    euler = len(v) - edges + len(f)
    if (len(v), len(f), euler) != EXPECTED[name]:
        sys.exit(f"{name}: {len(v)} vertices, {len(f)} triangles, Euler {euler}; "
                 f"expected {EXPECTED[name]}")
    volume = signed_volume(v, f)
    if volume <= 0:
        sys.exit(f"{name}: volume {volume} (wound inward)")
    return volume, euler


def write_obj(path, name, v, f, note):
    lines = [f"# {name}: {note}\n", f"# {len(v)} vertices, {len(f)} triangles, unit scale, "
             "outward winding (written by make_meshes.py)\n"]
    lines += [f"v {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n" for p in v]
    lines += [f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f]
    tmp = path + ".tmp"
    with open(tmp, "w") as out:
        out.writelines(lines)
    os.replace(tmp, path)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name in MESHES:
        v, f = BUILDERS[name]()
        volume, euler = check(name, v, f)
        write_obj(os.path.join(out, name + ".obj"), name,
                  v, f, f"core volume {volume:.6g}, Euler characteristic {euler}")
        print(f"{name}: {len(v)} vertices, {len(f)} triangles, Euler {euler}, volume {volume:.6g}")


if __name__ == "__main__":
    main()
