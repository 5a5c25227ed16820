"""The true dilated bodies of a kdem frame: each shape's core in its body frame, the body (every
point within the dilation radius r of the core) as a signed-distance grid, and its surface.

A frame (frames/particles_<step>.vtu and shapes_<step>.vtp) holds every particle's position and
quaternion (body to world) and, per particle, the engine's drawn surface: the core's vertices moved
out by r along their angle-weighted pseudonormals, with the core's triangles (flat between the
vertices, so inside the dilated surface there, and sharp where the core is). The core in the body
frame is recovered from it:
  - a mesh core (an OBJ file of make_meshes.py, scaled by the scene's `scale`): the engine moves it
    to its principal frame (a rotation and the centroid), so the mesh's own vertices plus r times
    their pseudonormals are fitted to the drawn points by a rigid motion (Kabsch); the fit's
    residual (rounding, 1e-17 m) shows that the vertex order and the pseudonormals agree;
  - a lattice core (superquadric or harmonic, 200 nodes): the drawn points less r times the drawn
    surface's own pseudonormals (the offset surface's normals at the nodes are the core's, up to
    the difference between the two polyhedra's angle weights).
The body is then {x : d(x, core) <= r}: the unsigned distance to the core triangles (VTK) on a grid,
signed by the generalised winding number (inside the core: negative), and its surface the level r
(flying edges), decimated for drawing."""
import glob
import math
import os
import re

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy


def last_frame(run_dir):
    """(vtu path, vtp path, step) of the last frame of a run."""
    files = glob.glob(os.path.join(run_dir, "frames", "particles_*.vtu"))
    if not files:
        raise SystemExit(f"{run_dir}: no frames/particles_*.vtu")
    by_step = {int(re.search(r"particles_(\d+)\.vtu$", f).group(1)): f for f in files}
    step = max(by_step)
    vtu = by_step[step]
    vtp = os.path.join(os.path.dirname(vtu), os.path.basename(vtu).replace("particles_", "shapes_")
                       .replace(".vtu", ".vtp"))
    return vtu, vtp, step


def first_frame(run_dir):
    """(vtu path, vtp path, step) of the first frame of a run (the shapes' surfaces are the same in
    every frame; the templates are taken from it)."""
    files = glob.glob(os.path.join(run_dir, "frames", "particles_*.vtu"))
    if not files:
        raise SystemExit(f"{run_dir}: no frames/particles_*.vtu")
    by_step = {int(re.search(r"particles_(\d+)\.vtu$", f).group(1)): f for f in files}
    step = min(by_step)
    vtu = by_step[step]
    return vtu, vtu.replace("particles_", "shapes_").replace(".vtu", ".vtp"), step


def read_state(checkpoint):
    """A checkpoint's particles, as read_particles gives a frame's."""
    import h5py
    with h5py.File(checkpoint, "r") as f:
        out = {"position": f["particles/position"][()], "quaternion": f["particles/orientation"][()],
               "velocity": f["particles/velocity"][()], "shape": f["particles/shape"][:, 0],
               "source": f["particles/source"][:, 0], "id": f["particles/id"][:, 0],
               "radius": f["particles/radius"][:, 0], "mass": f["particles/mass"][:, 0],
               "source_names": f["source_names"][()].decode().split(),
               "time": float(f["time"][()]), "step": int(f["step"][()])}
    return out


def read_particles(vtu):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    grid = reader.GetOutput()
    pd = grid.GetPointData()
    out = {"position": vtk_to_numpy(grid.GetPoints().GetData()).astype(float)}
    for name in ("quaternion", "velocity", "shape", "source", "id", "radius"):
        out[name] = vtk_to_numpy(pd.GetArray(name))
    names = grid.GetFieldData().GetAbstractArray("source_names")
    out["source_names"] = [names.GetValue(k) for k in range(names.GetNumberOfValues())]
    time = grid.GetFieldData().GetArray("TimeValue")
    out["time"] = float(time.GetValue(0)) if time is not None else float("nan")
    return out


def read_surfaces(vtp):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(vtp)
    reader.Update()
    data = reader.GetOutput()
    points = vtk_to_numpy(data.GetPoints().GetData()).astype(float)
    triangles = vtk_to_numpy(data.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    ids = vtk_to_numpy(data.GetPointData().GetArray("id"))
    return points, triangles, ids


def rotation_matrices(q):
    """Body-to-world rotation matrices of quaternions [w, x, y, z] (N x 4) -> N x 3 x 3."""
    q = np.asarray(q, float).reshape(-1, 4)
    q = q / np.linalg.norm(q, axis=1)[:, None]
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], 1)


def pseudonormals(v, f):
    """Angle-weighted vertex normals (Baerentzen and Aanaes), not normalised."""
    f = np.asarray(f)
    n = np.zeros_like(v)
    face_n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    face_n /= np.linalg.norm(face_n, axis=1)[:, None]
    for k in range(3):
        a, b, c = v[f[:, k]], v[f[:, (k + 1) % 3]], v[f[:, (k + 2) % 3]]
        u, w = b - a, c - a
        cos = np.einsum("ij,ij->i", u, w) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        angle = np.arccos(np.clip(cos, -1, 1))
        np.add.at(n, f[:, k], angle[:, None] * face_n)
    return n


def unit_rows(n):
    return n / np.linalg.norm(n, axis=1)[:, None]


def read_obj(path):
    v, f = [], []
    with open(path) as src:
        for line in src:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                v.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                f.append([int(c.split("/")[0]) - 1 for c in parts[1:4]])
    return np.array(v), np.array(f)


def kabsch(p, s):
    """Rotation R and translation t with R p + t closest to s (rows are points)."""
    pc, sc = p.mean(axis=0), s.mean(axis=0)
    h = (p - pc).T @ (s - sc)
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    r = vt.T @ np.diag([1, 1, d]) @ u.T
    return r, sc - r @ pc


def rigid_match(p, s):
    """The rigid motion (R, t) and the one-to-one matching that bring the point set p onto the
    point set s, the same points in another order and turned arbitrarily (the engine keeps the
    mesh's vertices, not necessarily their order, and a body with equal principal inertias, such
    as the cube, may be turned by any rotation). The point means correspond; the rotation follows
    from two points of p (the farthest from the mean, and the one most nearly perpendicular to it
    seen from the mean) and every pair of points of s at the same distances, checked on all points.
    Returns R, t, index (s[index[k]] matches p[k]), residual (largest distance), or None."""
    from scipy.spatial import cKDTree
    tree = cKDTree(s)
    pc, sc = p.mean(axis=0), s.mean(axis=0)
    dp, ds = p - pc, s - sc
    rp, rs = np.linalg.norm(dp, axis=1), np.linalg.norm(ds, axis=1)
    scale = rp.max()
    tol = 1e-9 * scale
    a = int(np.argmax(rp))
    sine = np.linalg.norm(np.cross(dp, dp[a]), axis=1) / np.maximum(rp * rp[a], 1e-300)
    b = int(np.argmax(sine))
    ab = np.linalg.norm(dp[a] - dp[b])
    best = None
    for i in np.nonzero(np.abs(rs - rp[a]) < tol)[0]:
        for j in np.nonzero((np.abs(rs - rp[b]) < tol)
                            & (np.abs(np.linalg.norm(ds - ds[i], axis=1) - ab) < tol))[0]:
            src = np.array([dp[a], dp[b], np.cross(dp[a], dp[b]) / scale])
            dst = np.array([ds[i], ds[j], np.cross(ds[i], ds[j]) / scale])
            r, _ = kabsch(np.vstack([src, -src]), np.vstack([dst, -dst]))
            t = sc - r @ pc
            dist, index = tree.query(p @ r.T + t)
            residual = float(dist.max())
            if len(set(index.tolist())) == len(p) and (best is None or residual < best[3]):
                r, t = kabsch(p, s[index])  # refined on all points
                residual = float(np.abs(p @ r.T + t - s[index]).max())
                best = (r, t, index, residual)
                if residual < tol:
                    return best
    return best


class Template:
    """One shape: core (body frame) and r, the distance grid, the surface."""

    def __init__(self, name, core_v, core_f, r, fit_residual):
        self.name, self.core_v, self.core_f, self.r = name, core_v, np.asarray(core_f), r
        self.fit_residual = fit_residual
        self.bounding_radius = float(np.linalg.norm(core_v, axis=1).max() + r)
        self.field = None

    def build_field(self, spacing):
        """Signed distance to the core on a grid covering the body (negative inside the core)."""
        # (shifted by fractions of a spacing, so that flat faces along the axes do not lie on the
        # grid's planes)
        lo = self.core_v.min(axis=0) - self.r - (2 + np.array([0.318, 0.427, 0.263])) * spacing
        hi = self.core_v.max(axis=0) + self.r + 2 * spacing
        dims = np.ceil((hi - lo) / spacing).astype(int) + 1
        poly = polydata(self.core_v, self.core_f)
        distance = vtk.vtkImplicitPolyDataDistance()
        distance.SetInput(poly)
        zz, yy, xx = np.meshgrid(*[lo[k] + spacing * np.arange(dims[k]) for k in (2, 1, 0)],
                                 indexing="ij")
        points = np.stack([xx, yy, zz], axis=-1).reshape(-1, 3)
        values = vtk.vtkDoubleArray()
        # Serially: vtkSampleFunction evaluates in threads, which this function does not support.
        distance.FunctionValue(numpy_to_vtk(points, deep=True), values)
        d = np.abs(vtk_to_numpy(values))
        d = d.reshape(dims[2], dims[1], dims[0]).copy()  # z, y, x
        # Sign where it matters (|d| >= r / 2) inside the core's box, by winding numbers.
        flat = d.reshape(-1)
        cmin, cmax = self.core_v.min(axis=0), self.core_v.max(axis=0)
        candidates = np.nonzero((flat >= 0.5 * self.r)
                                & np.all((points >= cmin) & (points <= cmax), axis=1))[0]
        inside = winding_numbers(points[candidates], self.core_v, self.core_f) > 0.5
        flat[candidates[inside]] *= -1
        self.field = flat.reshape(d.shape)
        self.origin, self.spacing, self.dims = lo, spacing, dims
        # The body's volume from the field interpolated at 2e6 random points of the grid's box (a
        # regular lattice of samples can alias with a symmetric body lying along the grid).
        rng = np.random.default_rng(12345)
        extent = (dims - 1) * spacing
        samples = 2_000_000
        hits = sum(int(self.inside(lo + extent * rng.random((samples // 10, 3))).sum())
                   for _ in range(10))
        self.grid_volume = float(hits / samples * np.prod(extent))
        return self

    def field_at(self, body_points):
        """The field interpolated (trilinear) at body-frame points; +inf outside the grid."""
        g = (body_points - self.origin) / self.spacing
        i0 = np.floor(g).astype(int)
        ok = np.all((i0 >= 0) & (i0 < self.dims - 1), axis=1)
        out = np.full(len(body_points), np.inf)
        i0, w = i0[ok], g[ok] - i0[ok]
        value = np.zeros(len(i0))
        for dx in (0, 1):
            for dy in (0, 1):
                for dz in (0, 1):
                    weight = ((w[:, 0] if dx else 1 - w[:, 0]) * (w[:, 1] if dy else 1 - w[:, 1])
                              * (w[:, 2] if dz else 1 - w[:, 2]))
                    value += weight * self.field[i0[:, 2] + dz, i0[:, 1] + dy, i0[:, 0] + dx]
        out[ok] = value
        return out

    def inside(self, body_points):
        """Whether body-frame points lie in the dilated body (the interpolated field <= r)."""
        return self.field_at(body_points) <= self.r

    def surface(self, target_triangles):
        """The level r of the field: (vertices, triangles), decimated to about target_triangles."""
        image = vtk.vtkImageData()
        image.SetDimensions(*[int(x) for x in self.dims])
        image.SetOrigin(*self.origin)
        image.SetSpacing(self.spacing, self.spacing, self.spacing)
        image.GetPointData().SetScalars(numpy_to_vtk(self.field.reshape(-1).copy(), deep=True))
        contour = vtk.vtkFlyingEdges3D()
        contour.SetInputData(image)
        contour.SetValue(0, self.r)
        contour.ComputeNormalsOff()
        contour.Update()
        mesh = contour.GetOutput()
        count = mesh.GetNumberOfPolys()
        if count > target_triangles:
            # Quadric decimation, or, where it breaks the surface (it does on large flat faces
            # lying along the grid: the volume collapses), topology-preserving decimation; the
            # full contour if neither keeps the volume within 0.5 %.
            full = enclosed_volume(mesh)
            for make in (vtk.vtkQuadricDecimation, vtk.vtkDecimatePro):
                decimate = make()
                decimate.SetInputData(mesh)
                decimate.SetTargetReduction(1.0 - target_triangles / count)
                if make is vtk.vtkDecimatePro:
                    decimate.PreserveTopologyOn()
                    decimate.SplittingOff()
                    decimate.BoundaryVertexDeletionOff()
                decimate.Update()
                if abs(enclosed_volume(decimate.GetOutput()) / full - 1) < 0.005:
                    mesh = decimate.GetOutput()
                    break
        v = vtk_to_numpy(mesh.GetPoints().GetData()).astype(float)
        f = vtk_to_numpy(mesh.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
        return v, f


def enclosed_volume(mesh):
    properties = vtk.vtkMassProperties()
    properties.SetInputData(mesh)
    properties.Update()
    return properties.GetVolume()


def polydata(v, f):
    poly = vtk.vtkPolyData()
    pts = vtk.vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(v, float), deep=True))
    poly.SetPoints(pts)
    cells = np.hstack([np.full((len(f), 1), 3), np.asarray(f)]).astype(np.int64).ravel()
    arr = vtk.vtkCellArray()
    arr.SetCells(len(f), numpy_to_vtkIdTypeArray(cells, deep=True))
    poly.SetPolys(arr)
    return poly


def winding_numbers(points, v, f, chunk=1500):
    """Generalised winding number of a closed outward mesh at points (1 inside, 0 outside)."""
    tri = v[np.asarray(f)]  # T x 3 x 3
    out = np.empty(len(points))
    for start in range(0, len(points), chunk):
        p = points[start:start + chunk]
        a = tri[None, :, 0, :] - p[:, None, :]
        b = tri[None, :, 1, :] - p[:, None, :]
        c = tri[None, :, 2, :] - p[:, None, :]
        la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
        num = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc
               + np.einsum("ptk,ptk->pt", b, c) * la + np.einsum("ptk,ptk->pt", c, a) * lb)
        out[start:start + chunk] = (2 * np.arctan2(num, den)).sum(axis=1) / (4 * math.pi)
    return out


def body_templates(particles, surfaces, mesh_dir, scales, mesh_shapes, dilation):
    """A Template per shape id present in the frame, keyed by shape id; the shape's name is the
    name of the source of its first particle (one source per shape)."""
    points, triangles, point_ids = surfaces
    first_point = {}
    ids_in_order, starts = np.unique(point_ids, return_index=True)
    first_point = dict(zip(ids_in_order.tolist(), starts.tolist()))
    rot = rotation_matrices(particles["quaternion"])
    templates = {}
    for shape_id in sorted(set(particles["shape"].tolist())):
        i = int(np.nonzero(particles["shape"] == shape_id)[0][0])
        name = particles["source_names"][int(particles["source"][i])]
        pid = int(particles["id"][i])
        start = first_point[pid]
        count = int((point_ids == pid).sum())
        world = points[start:start + count]
        body = (world - particles["position"][i]) @ rot[i]  # R^T (x - p), row form
        tri_mask = (triangles[:, 0] >= start) & (triangles[:, 0] < start + count)
        faces = triangles[tri_mask] - start
        if name in mesh_shapes:
            v, f = read_obj(os.path.join(mesh_dir, name + ".obj"))
            v = v * scales[name]
            if len(v) != count:
                raise SystemExit(f"{name}: the frame draws {count} points, the mesh has {len(v)}")
            drawn = v + dilation * unit_rows(pseudonormals(v, f))
            match = rigid_match(drawn, body)
            if match is None or match[3] > 1e-6 * dilation:
                residual = float("nan") if match is None else match[3]
                raise SystemExit(f"{name}: the drawn surface does not match the mesh "
                                 f"(residual {residual:.2e} m)")
            r_fit, t_fit, _, residual = match
            core = v @ r_fit.T + t_fit
            faces = f
        else:
            core = body - dilation * unit_rows(pseudonormals(body, faces))
            residual = float("nan")
        templates[shape_id] = Template(name, core, faces, dilation, residual)
    return templates
