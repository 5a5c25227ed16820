"""Analyses the level-set wall impact runs (make_scene.py): per body, the state just after its
first impact (the first checkpoint interval after the impact began over which its velocity and
angular momentum no longer change: no gravity, so a free body keeps both; its angular velocity
turns as it tumbles), then
- for the superquadric made a level set, its rebound against the superquadric family's body of
  the same superquadric at the same tilt: the vertical velocity v_z and the angular momentum
  about y as a spin, L_y / (m R), R the volume-equivalent radius, each as a fraction of the
  impact speed (`max_rel_error` over the tilts, and the largest of each);
- for every level-set body: the kinetic energy after against before (elastic: `energy_error`),
  and the horizontal velocity (a frictionless plane gives no horizontal impulse:
  `max_tangential_speed_ratio`).
Writes result.json and levelset_wall_impact.png into the results folder.

usage: analyse.py RUNS_FOLDER RESULTS_FOLDER"""
import glob
import json
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scene  # noqa: E402


def rotation(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def states(run_dir):
    """Per checkpoint (in time order): time and, per source name, the body's fields."""
    out = []
    for path in sorted(glob.glob(os.path.join(run_dir, "checkpoints", "checkpoint_*.h5"))):
        with h5py.File(path, "r") as f:
            names = f["source_names"][()].decode().split()
            source = f["particles/source"][:, 0]
            fields = {k: f["particles/" + k][...] for k in
                      ("velocity", "angular_velocity", "mass", "inertia", "orientation")}
            bodies = {names[s]: {k: v[i] for k, v in fields.items()} for i, s in enumerate(source)}
            out.append((float(f["time"][()]), bodies))
    if len(out) < 3:
        sys.exit(f"{run_dir}: expected the checkpoints of the run")
    return out


def angular_momentum(body):
    """World frame (the checkpoint's inertia is the principal inertia, kg m^2)."""
    r = rotation(body["orientation"])
    return r @ np.diag(body["inertia"]) @ r.T @ body["angular_velocity"]


def first_rebound(history, name):
    """The body's state after its first impact, and the time it was reached."""
    def moving(a, b):
        scale = float(a["mass"][0]) * equivalent_radius(a) * make_scene.SPEED
        return (np.abs(a["velocity"] - b["velocity"]).max() > 1e-9 or
                np.abs(angular_momentum(a) - angular_momentum(b)).max() > 1e-9 * scale)
    started = False
    for (t0, s0), (t1, s1) in zip(history, history[1:]):
        if moving(s0[name], s1[name]):
            started = True
        elif started:
            return s1[name], t1
    sys.exit(f"{name}: no completed impact within the run")


def kinetic_energy(body):
    m = float(body["mass"][0])
    r = rotation(body["orientation"])
    inertia = r @ np.diag(body["inertia"]) @ r.T
    w = body["angular_velocity"]
    return 0.5 * m * float(body["velocity"] @ body["velocity"]) + 0.5 * float(w @ inertia @ w)


def spin_y(body):
    """The angular momentum about y as a speed, L_y / (m R) with R the volume-equivalent radius."""
    return float(angular_momentum(body)[1]) / (float(body["mass"][0]) * equivalent_radius(body))


def equivalent_radius(body):
    return (3 * float(body["mass"][0]) / make_scene.DENSITY / (4 * math.pi)) ** (1 / 3)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    runs, out_dir = sys.argv[1:]
    level_sets = states(os.path.join(runs, "levelset_wall_impact"))
    reference = states(os.path.join(runs, "superquadric_reference"))
    speed = make_scene.SPEED
    rows = []
    for shape in [s for s in make_scene.SHAPES if s.endswith("level_set")]:
        for tilt in make_scene.TILTS:
            name = f"{shape}_{tilt:02d}"
            before = level_sets[0][1][name]
            after, t_after = first_rebound(level_sets, name)
            e_before, e_after = kinetic_energy(before), kinetic_energy(after)
            row = {"shape": shape, "tilt_deg": tilt, "time_after": t_after,
                   "v_z": float(after["velocity"][2]), "spin_y": spin_y(after),
                   "energy_error": (e_after - e_before) / e_before,
                   "tangential_speed_ratio": float(np.hypot(*after["velocity"][:2])) / speed,
                   "equivalent_radius": equivalent_radius(after)}
            if shape == "sq_level_set":
                ref, _ = first_rebound(reference, f"sq_reference_{tilt:02d}")
                row["reference_v_z"] = float(ref["velocity"][2])
                row["reference_spin_y"] = spin_y(ref)
                row["v_z_error"] = abs(row["v_z"] - row["reference_v_z"]) / speed
                row["spin_y_error"] = abs(row["spin_y"] - row["reference_spin_y"]) / speed
            rows.append(row)
    sq = [r for r in rows if "v_z_error" in r]
    result = {
        "case": "levelset_wall_impact",
        "reference": "the superquadric family's body of the same superquadric, same tilt",
        "impact_speed": speed,
        "tilts_deg": make_scene.TILTS,
        "max_rel_error": max(max(r["v_z_error"], r["spin_y_error"]) for r in sq),
        "max_v_z_error": max(r["v_z_error"] for r in sq),
        "max_spin_y_error": max(r["spin_y_error"] for r in sq),
        "energy_error": max(abs(r["energy_error"]) for r in rows),
        "max_tangential_speed_ratio": max(r["tangential_speed_ratio"] for r in rows),
        "rows": rows}
    os.makedirs(out_dir, exist_ok=True)
    tmp = os.path.join(out_dir, "result.json.tmp")
    with open(tmp, "w") as f:
        json.dump(result, f, indent=1)
    os.replace(tmp, os.path.join(out_dir, "result.json"))
    plot(result, os.path.join(out_dir, "levelset_wall_impact.png"))
    print(f"max_rel_error {result['max_rel_error']:.4f} (v_z {result['max_v_z_error']:.4f}, "
          f"L_y/(m R) {result['max_spin_y_error']:.4f}), energy_error {result['energy_error']:.2e}, "
          f"tangential {result['max_tangential_speed_ratio']:.1e}")


def plot(result, target):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    sq = [r for r in result["rows"] if r["shape"] == "sq_level_set"]
    tilts = [r["tilt_deg"] for r in sq]
    left.plot(tilts, [r["reference_v_z"] for r in sq], "k-", label="superquadric family: v_z")
    left.plot(tilts, [r["v_z"] for r in sq], "o", label="level set: v_z")
    left.plot(tilts, [r["reference_spin_y"] for r in sq], "k--",
              label="superquadric family: L_y / (m R)")
    left.plot(tilts, [r["spin_y"] for r in sq], "s", label="level set: L_y / (m R)")
    left.set_xlabel("tilt (degrees)")
    left.set_ylabel("after the first impact (m/s)")
    left.set_title("Superquadric as a level set against the superquadric family", fontsize=9)
    left.legend(fontsize=7)
    left.grid(True, lw=0.3)
    for shape, marker in (("sq_level_set", "o"), ("harmonic_level_set", "s"),
                          ("l_prism_level_set", "^")):
        rows = [r for r in result["rows"] if r["shape"] == shape]
        right.semilogy([r["tilt_deg"] for r in rows],
                       [max(abs(r["energy_error"]), 1e-12) for r in rows], marker + "-",
                       label=shape.replace("_level_set", ""))
    right.set_xlabel("tilt (degrees)")
    right.set_ylabel("|kinetic energy change| / before")
    right.set_title("Elastic impacts: energy kept", fontsize=9)
    right.legend(fontsize=7)
    right.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(target, dpi=120)


if __name__ == "__main__":
    main()
