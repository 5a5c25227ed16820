"""Helpers shared by the superquadric validation scripts: reading kdem output (series.csv and
HDF5 checkpoints), quaternions, the closed-form volume and inertia of a superquadric, and
writing a figure and its summary (each to a temporary name, then renamed)."""
import csv
import glob
import math
import os

import h5py
import numpy as np


def read_series(run_dir):
    """series.csv as a dict of numpy arrays, one per column."""
    with open(os.path.join(run_dir, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


def read_checkpoint(path):
    """Particle fields of one checkpoint, sorted by particle id, plus time, step and pairs."""
    with h5py.File(path, "r") as f:
        ids = f["particles/id"][:, 0]
        order = np.argsort(ids)
        state = {name: f["particles/" + name][...][order] for name in
                 ("position", "velocity", "angular_velocity", "orientation", "mass", "inertia",
                  "shape", "radius", "id")}
        state["mass"] = state["mass"][:, 0]
        state["time"] = float(f["time"][()])
        state["step"] = int(f["step"][()])
        state["pair_count"] = int(f["pair_count"][()])
        pairs = {}
        for name in ("pair_i", "pair_j", "overlap", "midway_point", "force_on_i"):
            if "pairs/" + name in f:
                pairs[name] = f["pairs/" + name][...]
        state["pairs"] = pairs
        # wall contacts per particle: entries of the contact history (CSR rows over the particles
        # as stored) with a positive overlap; an entry may stay listed after the contact ended
        if "wall_contacts/row_start" in f:
            rows = f["wall_contacts/row_start"][:, 0]
            overlap = f["wall_contacts/overlap"][:, 0]
            touching = np.array([int(np.sum(overlap[rows[k]:rows[k + 1]] > 0))
                                 for k in range(len(rows) - 1)])
            state["wall_contacts"] = touching[order]
    return state


def read_checkpoints(run_dir):
    """All checkpoints written during a run (checkpoints/*.h5), in time order, then the final one."""
    paths = sorted(glob.glob(os.path.join(run_dir, "checkpoints", "*.h5")))
    states = [read_checkpoint(p) for p in paths]
    final = os.path.join(run_dir, "checkpoint.h5")
    if os.path.exists(final):
        last = read_checkpoint(final)
        if not states or last["step"] > states[-1]["step"]:
            states.append(last)
    return states


def rotation_matrix(q):
    """Rotation matrix of the unit quaternion q = [w, x, y, z] (body frame -> world frame)."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def beta(p, q):
    return math.exp(math.lgamma(p) + math.lgamma(q) - math.lgamma(p + q))


def superquadric_volume(a, b, c, n1, n2):
    """Volume of (|x/a|^n2 + |y/b|^n2)^(n1/n2) + |z/c|^n1 <= 1 (Jaklic et al. 2000, eps = 2/n)."""
    e1, e2 = 2.0 / n1, 2.0 / n2
    return 2 * a * b * c * e1 * e2 * beta(0.5 * e1 + 1, e1) * beta(0.5 * e2, 0.5 * e2)


def superquadric_inertia(a, b, c, n1, n2, density):
    """Principal moments of inertia about the body x, y, z axes (same source)."""
    e1, e2 = 2.0 / n1, 2.0 / n2
    common = 0.5 * a * b * c * e1 * e2
    section = common * beta(1.5 * e2, 0.5 * e2) * beta(0.5 * e1, 2 * e1 + 1)
    axial = common * 4 * beta(0.5 * e2, 0.5 * e2 + 1) * beta(1.5 * e1, e1 + 1)
    mx, my, mz = a * a * section, b * b * section, c * c * axial
    return density * np.array([my + mz, mx + mz, mx + my])


def world_inertia(q, principal):
    R = rotation_matrix(q)
    return R @ np.diag(principal) @ R.T


def kinetic_energy(state):
    """Translational and rotational kinetic energy of each particle."""
    m = state["mass"]
    trans = 0.5 * m * np.sum(state["velocity"] ** 2, axis=1)
    rot = np.empty(len(m))
    for k in range(len(m)):
        I = world_inertia(state["orientation"][k], state["inertia"][k])
        w = state["angular_velocity"][k]
        rot[k] = 0.5 * w @ I @ w
    return trans, rot


def momenta(state, indices=None, origin=(0.0, 0.0, 0.0)):
    """Total linear momentum and angular momentum about `origin` (orbital + spin)."""
    if indices is None:
        indices = range(len(state["mass"]))
    origin = np.asarray(origin)
    p = np.zeros(3)
    L = np.zeros(3)
    for k in indices:
        m = state["mass"][k]
        v = state["velocity"][k]
        x = state["position"][k] - origin
        I = world_inertia(state["orientation"][k], state["inertia"][k])
        p += m * v
        L += m * np.cross(x, v) + I @ state["angular_velocity"][k]
    return p, L


def body_angular_velocity(state, k):
    R = rotation_matrix(state["orientation"][k])
    return R.T @ state["angular_velocity"][k]


def save_figure_and_summary(fig, png, summary_path, lines):
    """The figure as PNG and the printed lines as text; no file is left half written."""
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, png)
    tmp = summary_path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, summary_path)
