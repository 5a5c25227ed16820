"""Shared by the scripts that run inside Yade (Debian's `yade`, its level-set DEM): one level-set
shape per superquadric, shared by every body of that shape, as kdem keeps one grid per template.

A `levelSetBody` call builds a grid and its surface nodes; bodies made here from one prototype
hold the same `LevelSet` instance (Yade's shapes are shared pointers), so that a scene of N
bodies builds one grid, not N."""
from yade import Body, Quaternion, Matrix3, Vector3
from yade.utils import _commonBodySetup, levelSetBody

SPACING_CELLS = 40  # grid spacing: the smallest extent 2c over this
# Per shape of perf/level_set_peer: about as many as kdem's default points (1798, 2074); Yade
# asks for a square plus 2.
SURFACE_NODES = {"ellipsoid": 42 * 42 + 2, "blocky": 45 * 45 + 2}


def epsilons_of(n1, n2):
    """Yade's superellipsoid exponents (epsilon_e in the xy section, epsilon_n along z) for kdem's
    (n1 along z, n2 in the xy section): the same surface."""
    return (2.0 / n2, 2.0 / n1)


def prototype(half_axes, n1, n2, surface_nodes, material, cells_across=SPACING_CELLS):
    """A level-set body of the superquadric (at the origin), whose shape the others share."""
    a, b, c = half_axes
    return levelSetBody("superellipsoid", center=Vector3(0, 0, 0), extents=(a, b, c),
                        epsilons=epsilons_of(n1, n2), spacing=2 * c / cells_across,
                        nSurfNodes=surface_nodes, nodesPath=1, dynamic=False, material=material)


def quaternion_of(rows):
    """The rotation given as 9 numbers, row by row."""
    return Quaternion(Matrix3(*rows))


def body_like(proto, centre, orientation, material, dynamic=True):
    """A body holding proto's shape (the same instance), at centre with the given orientation
    (a Quaternion)."""
    body = Body()
    body.shape = proto.shape
    _commonBodySetup(body, proto.shape.volume(), proto.shape.inertia(), material,
                     pos=Vector3(*centre), dynamic=dynamic)
    body.aspherical = True
    body.state.ori = body.state.refOri = orientation
    return body


def state_of(name, body):
    """A body's final state: position, velocity, spin (world), rotation (9 numbers, row by
    row), mass and principal inertia."""
    r = body.state.ori.toRotationMatrix()
    return {"name": name, "position": list(body.state.pos), "velocity": list(body.state.vel),
            "angular_velocity": list(body.state.angVel),
            "rotation": [r[i, j] for i in range(3) for j in range(3)],
            "mass": [body.state.mass], "inertia": list(body.state.inertia)}
