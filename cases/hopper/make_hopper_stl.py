#!/usr/bin/env python3
"""Writes hopper.stl: the hopper of the book's section 6.4.4 as a triangle mesh, in metres.

A square bin of side 40 mm above a pyramidal hopper whose walls make 60 degrees with the
horizontal and end in a 16 x 16 mm orifice at z = 0. The bin is `bin_height` tall above the
hopper's top edge (the book does not give it; it only has to hold the fill).

`hopper_triangles` and `write_stl` take any square hopper (the chapter 3 hoppers use them).
"""
import math
import sys

TOP_HALF = 0.020      # m, half side of the bin
ORIFICE_HALF = 0.008  # m, half side of the orifice
ANGLE_DEGREES = 60.0  # wall against the horizontal
BIN_HEIGHT = 0.130    # m


def quad(a, b, c, d):
    return [(a, b, c), (a, c, d)]


def hopper_triangles(top_half=TOP_HALF, orifice_half=ORIFICE_HALF, angle_degrees=ANGLE_DEGREES,
                     bin_height=BIN_HEIGHT):
    """Triangles of the pyramid (orifice at z = 0) and the bin above it, with the heights of
    the pyramid's top edge and of the bin's top."""
    cone_top = (top_half - orifice_half) * math.tan(math.radians(angle_degrees))
    top = cone_top + bin_height
    o, t = orifice_half, top_half
    low = [(-o, -o, 0.0), (o, -o, 0.0), (o, o, 0.0), (-o, o, 0.0)]
    mid = [(-t, -t, cone_top), (t, -t, cone_top), (t, t, cone_top), (-t, t, cone_top)]
    high = [(-t, -t, top), (t, -t, top), (t, t, top), (-t, t, top)]
    triangles = []
    for k in range(4):
        n = (k + 1) % 4
        triangles += quad(low[k], low[n], mid[n], mid[k])
        triangles += quad(mid[k], mid[n], high[n], high[k])
    return triangles, cone_top, top


def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = math.sqrt(sum(x * x for x in n))
    return [x / length for x in n]


def write_stl(path, triangles):
    lines = ["solid hopper"]
    for a, b, c in triangles:
        lines.append("  facet normal %.9g %.9g %.9g" % tuple(normal(a, b, c)))
        lines.append("    outer loop")
        for p in (a, b, c):
            lines.append("      vertex %.9g %.9g %.9g" % p)
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid hopper")
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    triangles, cone_top, top = hopper_triangles()
    write_stl(sys.argv[1] if len(sys.argv) > 1 else "hopper.stl", triangles)
    print("hopper: cone top at z = %.6f m, bin top at z = %.6f m" % (cone_top, top))
