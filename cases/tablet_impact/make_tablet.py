"""Writes the core of the book's tablet (Sect. 4.3.1, Fig. 4.15; Kureck et al. 2019) as a closed,
outward-wound triangle surface of revolution in an OBJ file (millimetres), and holds the tablet's
geometry for make_scene.py and analyse.py.

The tablet: a band cylinder of diameter L3 and thickness L1 between two spherical caps of radius
R2 = (L3^2 / (L2 - L1) + (L2 - L1)) / 4, total thickness L2 (book digest Table A6.1 row 2, A6.4).
The dilated polyhedron is the core swept by a sphere of the dilation radius r, so the core is the
tablet offset inward by r: a cylinder of radius L3/2 - r, caps of radius R2 - r about the same
centres (on the axis, d = R2 - L2/2 from the centroid on the far side). Core plus r is the tablet
with its rim rounded to radius r (the same tablet elsewhere).

Mesh: NODES_PER_RING nodes on every ring, all rings at the same azimuths (a node at azimuth 0, the
body's +x), CAP_RINGS rings per cap at equal polar steps about the cap's centre (the last is the
rim), BAND_INTERVALS equal steps along the band, a pole at each cap's apex. The lower half is the
mirror image of the upper half (z -> -z), so the centroid is at the origin and the inertia is
transversely isotropic (the mesh has 64-fold symmetry about z).

usage: make_tablet.py OUTPUT.obj"""
import math
import os
import sys

import numpy as np

# The tablet (book digest Table A6.1 row 2), metres.
L1 = 4.25e-3     # band thickness
L2 = 6.75e-3     # total thickness
L3 = 10.42e-3    # rim diameter
R_DIL = 1.0e-3   # dilation radius
R1 = 0.5 * math.hypot(L1, L3)                     # centroid to the rim
R2 = 0.25 * (L3 ** 2 / (L2 - L1) + (L2 - L1))     # cap sphere radius
D_CAP = R2 - L2 / 2                               # centroid to a cap's centre
ALPHA = math.asin(0.5 * L1 / R1)                  # rim direction above the mid-plane
BETA = math.asin(0.5 * L3 / R2)                   # the cap's half-angle about its centre

# The core: the tablet offset inward by r.
CORE_RADIUS = L3 / 2 - R_DIL                      # band cylinder
CORE_CAP_RADIUS = R2 - R_DIL                      # cap spheres, centres at -/+ D_CAP
CORE_BETA = math.asin(CORE_RADIUS / CORE_CAP_RADIUS)
CORE_RIM_Z = -D_CAP + CORE_CAP_RADIUS * math.cos(CORE_BETA)   # rim rings at +/- this height
CORE_APEX_Z = -D_CAP + CORE_CAP_RADIUS                         # = L2/2 - r
CORE_R1 = math.hypot(CORE_RADIUS, CORE_RIM_Z)
CORE_ALPHA = math.atan2(CORE_RIM_Z, CORE_RADIUS)

NODES_PER_RING = 64
CAP_RINGS = 10
BAND_INTERVALS = 6   # even: a ring at z = 0


def upper_half():
    """Vertices (mm) and triangles of the upper half: cap pole, cap rings, band rings down to
    z = 0. Rings are listed from the pole down; each triangle wound outward."""
    n = NODES_PER_RING
    mm = 1e3
    vertices = [(0.0, 0.0, CORE_APEX_Z * mm)]
    rings = []
    for k in range(1, CAP_RINGS + 1):
        psi = CORE_BETA * k / CAP_RINGS
        rho, z = CORE_CAP_RADIUS * math.sin(psi), -D_CAP + CORE_CAP_RADIUS * math.cos(psi)
        if k == CAP_RINGS:
            rho, z = CORE_RADIUS, CORE_RIM_Z
        rings.append((rho, z))
    half_band = BAND_INTERVALS // 2
    for k in range(1, half_band + 1):
        rings.append((CORE_RADIUS, CORE_RIM_Z * (1 - k / half_band)))
    ring_start = []
    for rho, z in rings:
        ring_start.append(len(vertices))
        for j in range(n):
            phi = 2 * math.pi * j / n
            vertices.append((rho * math.cos(phi) * mm, rho * math.sin(phi) * mm, z * mm))
    triangles = []
    first = ring_start[0]
    for j in range(n):   # the pole's fan; counter-clockwise seen from +z: outward
        triangles.append((0, first + j, first + (j + 1) % n))
    for a, b in zip(ring_start[:-1], ring_start[1:]):
        for j in range(n):
            j1 = (j + 1) % n
            triangles.append((a + j, b + j, b + j1))
            triangles.append((a + j, b + j1, a + j1))
    return vertices, triangles, ring_start[-1]


def tablet_mesh():
    """The closed core: the upper half and its mirror image, sharing the ring at z = 0.
    Returns vertices (mm, numpy array) and triangles (0-based, numpy array)."""
    vertices, triangles, equator = upper_half()
    n = NODES_PER_RING
    count = len(vertices)
    # Mirror: vertex i < equator gets a twin; the equator ring is shared.
    twin = {}
    for i in range(equator):
        twin[i] = len(vertices)
        x, y, z = vertices[i]
        vertices.append((x, y, -z))
    for i in range(equator, equator + n):
        twin[i] = i
    assert count == equator + n
    mirrored = [(twin[a], twin[c], twin[b]) for a, b, c in triangles]  # reversed: outward
    return np.array(vertices), np.array(triangles + mirrored)


def check_closed(vertices, triangles):
    """Closed, 2-manifold, consistently and outwardly wound, genus 0. Returns the signed volume
    (mm^3) and the Euler characteristic."""
    directed = {}
    for t in triangles:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if (a, b) in directed:
                raise SystemExit(f"edge {a}->{b} used twice in the same direction")
            directed[(a, b)] = True
    for a, b in directed:
        if (b, a) not in directed:
            raise SystemExit(f"the mesh is open at edge {a}-{b}")
    edges = len(directed) // 2
    euler = len(vertices) - edges + len(triangles)
    if euler != 2:
        raise SystemExit(f"Euler characteristic {euler}, not 2")
    p = vertices[triangles]
    volume = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6
    if volume <= 0:
        raise SystemExit("the mesh is wound inward")
    return volume, euler


def write_obj(path, vertices, triangles):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# The core of the book's tablet (Sect. 4.3.1), millimetres, written by make_tablet.py:\n")
        f.write(f"# the tablet L1 = {L1 * 1e3} mm, L2 = {L2 * 1e3} mm, L3 = {L3 * 1e3} mm offset inward by "
                f"r = {R_DIL * 1e3} mm; {len(vertices)} vertices, {len(triangles)} triangles.\n")
        for x, y, z in vertices:
            f.write(f"v {x:.12g} {y:.12g} {z:.12g}\n")
        for a, b, c in triangles:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")
    os.replace(tmp, path)


def lowest_vertex_offset(vertices_m, theta):
    """Horizontal offset (x, m) of the mesh's lowest vertex from the centroid (the origin) when the
    axis makes the angle theta (rad) with the plane, tilted as make_scene.py tilts it, and the
    heights (m) of the lowest and the next lowest vertex above the lowest."""
    psi = math.pi / 2 - theta    # about +y: body z -> (cos theta, 0, sin theta)
    x = vertices_m[:, 0] * math.cos(psi) + vertices_m[:, 2] * math.sin(psi)
    z = -vertices_m[:, 0] * math.sin(psi) + vertices_m[:, 2] * math.cos(psi)
    order = np.argsort(z)
    return x[order[0]], z[order[1]] - z[order[0]]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    vertices, triangles = tablet_mesh()
    volume, _ = check_closed(vertices, triangles)
    write_obj(sys.argv[1], vertices, triangles)
    print(f"make_tablet: {len(vertices)} vertices, {len(triangles)} triangles, closed, outward, "
          f"core volume {volume:.3f} mm^3")


if __name__ == "__main__":
    main()
