#!/usr/bin/env python3
"""Draws the final state of a packing run (its checkpoint: positions and orientations; the
shapes' cores from the run's first frame) with every particle's true dilated surface (the level r
of the distance to its core, dilated_bodies.py), coloured by shape, in the container (floor and the
two far walls), seen obliquely from above. The picture is made by a z-buffer over all triangles
(numpy, orthographic projection, Lambert shading, particle outlines where the particle in front
changes), so that the packing is drawn with correct occlusion however many triangles it has.

usage: render_packing.py RUN_DIR MESH_DIR PNG [--triangles 1200] [--spacing 0.0005]
                         [--width 1500] [--azimuth -55] [--elevation 28] [--box-width 0.6]
                         [--state CHECKPOINT.h5]
  MESH_DIR holds calibration.json and the OBJ cores (run.sh writes both)."""
import argparse
import json
import math
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import dilated_bodies as db  # noqa: E402
import make_scene as ms  # noqa: E402

COLOURS = {"sphere": "#d62728", "super_ellipsoid": "#ff7f0e", "harmonic": "#bcbd22",
           "tetrahedron": "#2ca02c", "hexahedron": "#1f77b4", "concave_tetrahedron": "#17becf",
           "l_prism": "#9467bd", "holed_block": "#8c564b", "ring": "#e377c2"}
WALL_COLOUR = (0.86, 0.86, 0.84)
FLOOR_COLOUR = (0.70, 0.70, 0.67)


def camera(azimuth, elevation):
    """Orthonormal right, up and towards-the-viewer vectors of a view from azimuth/elevation
    (degrees; azimuth from +x towards +y, as matplotlib's)."""
    a, e = math.radians(azimuth), math.radians(elevation)
    back = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.cross([0, 0, 1.0], back)
    right /= np.linalg.norm(right)
    up = np.cross(back, right)
    return right, up, back


class ZBuffer:
    def __init__(self, width, height):
        self.w, self.h = width, height
        self.depth = np.full(width * height, np.inf)
        self.colour = np.ones((width * height, 3))
        self.owner = np.full(width * height, -1, np.int64)

    def draw(self, xy, depth, colours, owners, chunk=60000):
        """Triangles given by screen corners xy (T x 3 x 2, pixels), depth (T x 3, smaller is
        nearer), flat colours (T x 3) and owner ids (T)."""
        lo = np.floor(xy.min(axis=1)).astype(int)
        hi = np.ceil(xy.max(axis=1)).astype(int)
        size = np.maximum(hi - lo + 1, 1).max(axis=1)
        keep = (hi[:, 0] >= 0) & (lo[:, 0] < self.w) & (hi[:, 1] >= 0) & (lo[:, 1] < self.h)
        for cap in (2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 4096):
            sel = np.nonzero(keep & (size <= cap) & (size > cap // 2 if cap > 2 else True))[0]
            step = max(1, chunk // (cap * cap))
            offs = np.stack(np.meshgrid(np.arange(cap), np.arange(cap), indexing="xy"), -1)
            offs = offs.reshape(-1, 2)
            for s0 in range(0, len(sel), step):
                t = sel[s0:s0 + step]
                self._raster(xy[t], depth[t], colours[t], owners[t], lo[t], offs)

    def _raster(self, xy, depth, colours, owners, lo, offs):
        px = lo[:, None, 0] + offs[None, :, 0]
        py = lo[:, None, 1] + offs[None, :, 1]
        cx, cy = px + 0.5, py + 0.5
        x0, y0 = xy[:, 0, 0][:, None], xy[:, 0, 1][:, None]
        x1, y1 = xy[:, 1, 0][:, None], xy[:, 1, 1][:, None]
        x2, y2 = xy[:, 2, 0][:, None], xy[:, 2, 1][:, None]
        area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        area = np.where(np.abs(area) < 1e-12, np.nan, area)
        w1 = ((cx - x0) * (y2 - y0) - (x2 - x0) * (cy - y0)) / area
        w2 = ((x1 - x0) * (cy - y0) - (cx - x0) * (y1 - y0)) / area
        w0 = 1 - w1 - w2
        inside = (w0 >= -1e-9) & (w1 >= -1e-9) & (w2 >= -1e-9)
        inside &= (px >= 0) & (px < self.w) & (py >= 0) & (py < self.h)
        z = w0 * depth[:, 0, None] + w1 * depth[:, 1, None] + w2 * depth[:, 2, None]
        tri, pix = np.nonzero(inside)
        if len(tri) == 0:
            return
        flat = py[tri, pix] * self.w + px[tri, pix]
        zz = z[tri, pix]
        order = np.lexsort((zz, flat))
        flat, zz, tri = flat[order], zz[order], tri[order]
        first = np.ones(len(flat), bool)
        first[1:] = flat[1:] != flat[:-1]
        flat, zz, tri = flat[first], zz[first], tri[first]
        nearer = zz < self.depth[flat]
        flat, zz, tri = flat[nearer], zz[nearer], tri[nearer]
        self.depth[flat] = zz
        self.colour[flat] = colours[tri]
        self.owner[flat] = owners[tri]

    def image(self, outline=0.55):
        img = self.colour.reshape(self.h, self.w, 3).copy()
        owner = self.owner.reshape(self.h, self.w)
        edge = np.zeros_like(owner, bool)
        edge[:, 1:] |= owner[:, 1:] != owner[:, :-1]
        edge[1:, :] |= owner[1:, :] != owner[:-1, :]
        edge &= owner >= 0
        img[edge] *= outline
        return img[::-1]  # row 0 at the top


def shaded(normals, base, light, view):
    n = normals / np.maximum(np.linalg.norm(normals, axis=1)[:, None], 1e-300)
    n = np.where((n @ view)[:, None] < 0, -n, n)  # two-sided: the face seen
    diffuse = np.clip(n @ light, 0, 1)
    half = light + view
    half /= np.linalg.norm(half)
    spec = np.clip(n @ half, 0, 1) ** 40
    return np.clip(base * (0.35 + 0.65 * diffuse)[:, None] + 0.25 * spec[:, None], 0, 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir")
    parser.add_argument("mesh_dir")
    parser.add_argument("png")
    parser.add_argument("--triangles", type=int, default=1200)
    parser.add_argument("--spacing", type=float, default=0.0005)
    parser.add_argument("--width", type=int, default=1500)
    parser.add_argument("--azimuth", type=float, default=-55)
    parser.add_argument("--elevation", type=float, default=28)
    parser.add_argument("--title", default=None)
    parser.add_argument("--state", default=None, help="checkpoint to draw (default the final one)")
    parser.add_argument("--box-width", type=float, default=ms.BOX[0], help="container side (m)")
    args = parser.parse_args()

    with open(os.path.join(args.mesh_dir, "calibration.json")) as f:
        scales = {n: s["scale"] for n, s in json.load(f)["shapes"].items()}
    vtu, vtp, _ = db.first_frame(args.run_dir)
    templates = db.body_templates(db.read_particles(vtu), db.read_surfaces(vtp), args.mesh_dir,
                                  scales, ms.MESH_SHAPES, ms.DILATION)
    particles = db.read_state(args.state or os.path.join(args.run_dir, "checkpoint.h5"))
    step = particles["step"]
    bodies = {}
    for shape_id, t in templates.items():
        t.build_field(args.spacing)
        bodies[shape_id] = t.surface(args.triangles)
        print(f"{t.name}: {len(bodies[shape_id][1])} triangles drawn, volume on the grid "
              f"{t.grid_volume:.5e} m3, core fit residual {t.fit_residual:.1e} m")

    right, up, back = camera(args.azimuth, args.elevation)
    light = 0.35 * back + 0.45 * up + 0.25 * right
    light /= np.linalg.norm(light)
    hx = hy = args.box_width / 2
    top = max(0.05, float((particles["position"][:, 2] + particles["radius"]).max()))
    wall_top = top + 0.05
    # The scene's extent on the screen: the container up to wall_top.
    corners = np.array([[x, y, z] for x in (-hx, hx) for y in (-hy, hy) for z in (0, wall_top)])
    u, v = corners @ right, corners @ up
    margin = 0.02
    umin, umax, vmin, vmax = u.min() - margin, u.max() + margin, v.min() - margin, v.max() + margin
    scale = args.width / (umax - umin)
    height = int(math.ceil((vmax - vmin) * scale))
    zb = ZBuffer(args.width, height)

    def project(points):
        return np.stack([(points @ right - umin) * scale, (points @ up - vmin) * scale], -1)

    # Floor and the two walls facing the viewer from behind (normals towards the camera).
    walls = [np.array([[-hx, -hy, 0], [hx, -hy, 0], [hx, hy, 0], [-hx, hy, 0]])]
    for normal, quad in (((1, 0, 0), [[-hx, -hy, 0], [-hx, hy, 0], [-hx, hy, wall_top], [-hx, -hy, wall_top]]),
                         ((-1, 0, 0), [[hx, -hy, 0], [hx, hy, 0], [hx, hy, wall_top], [hx, -hy, wall_top]]),
                         ((0, 1, 0), [[-hx, -hy, 0], [hx, -hy, 0], [hx, -hy, wall_top], [-hx, -hy, wall_top]]),
                         ((0, -1, 0), [[-hx, hy, 0], [hx, hy, 0], [hx, hy, wall_top], [-hx, hy, wall_top]])):
        if np.dot(normal, back) > 0:  # its inner face looks at the viewer: a far wall
            walls.append(np.array(quad, float))
    for k, quad in enumerate(walls):
        tris = np.stack([quad[[0, 1, 2]], quad[[0, 2, 3]]])
        n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        base = np.array(FLOOR_COLOUR if k == 0 else WALL_COLOUR)
        col = shaded(n, np.array([base] * 2), light, back) * 0.4 + 0.6 * base
        zb.draw(project(tris.reshape(-1, 3)).reshape(-1, 3, 2), -(tris @ back),
                col, np.full(2, -2 - k))

    rot = db.rotation_matrices(particles["quaternion"])
    shape_ids = particles["shape"]
    batch_v, batch_c, batch_o = [], [], []
    pending = 0

    def flush():
        nonlocal batch_v, batch_c, batch_o, pending
        if not batch_v:
            return
        tri = np.concatenate(batch_v)
        zb.draw(project(tri.reshape(-1, 3)).reshape(-1, 3, 2), -(tri @ back),
                np.concatenate(batch_c), np.concatenate(batch_o))
        batch_v, batch_c, batch_o, pending = [], [], [], 0

    for i in range(len(shape_ids)):
        t = templates[int(shape_ids[i])]
        v, f = bodies[int(shape_ids[i])]
        world = v @ rot[i].T + particles["position"][i]
        tri = world[f]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        base = np.array(matplotlib.colors.to_rgb(COLOURS[t.name]))
        batch_v.append(tri)
        batch_c.append(shaded(n, np.tile(base, (len(f), 1)), light, back))
        batch_o.append(np.full(len(f), i))
        pending += len(f)
        if pending > 400000:
            flush()
    flush()

    image = zb.image()
    fig_w = 9.0
    fig = plt.figure(figsize=(fig_w, fig_w * height / args.width + 0.6))
    ax = fig.add_axes([0, 0, 1, 1 - 0.6 / (fig_w * height / args.width + 0.6)])
    ax.imshow(image, interpolation="lanczos")
    # The container's edges.
    edges = [((-hx, -hy, 0), (hx, -hy, 0)), ((hx, -hy, 0), (hx, hy, 0)), ((hx, hy, 0), (-hx, hy, 0)),
             ((-hx, hy, 0), (-hx, -hy, 0))]
    edges += [((x, y, 0), (x, y, wall_top)) for x in (-hx, hx) for y in (-hy, hy)]
    for a, b in edges:
        p = project(np.array([a, b], float))
        ax.plot(p[:, 0], height - p[:, 1], color="0.35", lw=0.6)
    ax.set_axis_off()
    names = [templates[k].name for k in sorted(templates)]
    counts = {n: int(sum(templates[int(s)].name == n for s in shape_ids)) for n in names}
    ax.legend(handles=[Patch(color=COLOURS[n], label=f"{ms.LABELS[n]} ({counts[n]})")
                       for n in ms.SHAPES if n in counts],
              loc="upper right", fontsize=7, frameon=True)
    title = args.title or (f"{len(shape_ids)} dilated polyhedra (r = {ms.DILATION * 1e3:g} mm) "
                           f"in the {args.box_width:g} x {args.box_width:g} m container, t = {particles['time']:.2f} s")
    fig.suptitle(title, fontsize=10, y=0.995)
    tmp = args.png + ".tmp.png"
    fig.savefig(tmp, dpi=args.width / fig_w)
    plt.close(fig)
    os.replace(tmp, args.png)
    print(f"wrote {args.png} ({args.width} x {height} px image, step {step})")


if __name__ == "__main__":
    main()
