"""Compares the contact forces of a stack run (the last frame's frames/contacts_<step>.csv) with the
weights they carry: between body k and k+1 of a stack, the weight of bodies k+1 ... top; under the
bottom body (its wall contact), the weight of the whole stack (masses from the run's checkpoint,
g = 9.81 m/s2). Writes result.json and stack.png into OUTPUT_DIR.

usage: analyse.py RUN_DIR OUTPUT_DIR"""
import csv
import glob
import json
import os
import re
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scene  # noqa: E402

G = 9.81


def bodies(run_dir):
    """{stack: [(id, shape, mass, position), ...] bottom first} from the final checkpoint."""
    with h5py.File(os.path.join(run_dir, "checkpoint.h5"), "r") as f:
        names = f["source_names"][()].decode().split()
        source = f["particles/source"][:, 0]
        ids = f["particles/id"][:, 0]
        mass = f["particles/mass"][:, 0]
        position = f["particles/position"][...]
    by_name = {names[s]: (int(i), float(m), p) for s, i, m, p in zip(source, ids, mass, position)}
    stacks = {}
    for stack, level, shape, _, _ in make_scene.stack_layout():
        i, m, p = by_name[f"{stack}_{level}"]
        stacks.setdefault(stack, []).append((i, shape, m, p))
    return stacks


def last_contacts(run_dir):
    files = glob.glob(os.path.join(run_dir, "frames", "contacts_*.csv"))
    if not files:
        sys.exit(f"{run_dir}: no frames/contacts_*.csv (was the run made with contact_forces?)")
    path = max(files, key=lambda p: int(re.search(r"contacts_(\d+)\.csv$", p).group(1)))
    with open(path) as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    return path, rows


def force_on(rows, body, partner=None, wall=None):
    """The force (N) on particle `body` from particle `partner` or from wall `wall` (summed over
    the rows that give it; a pair's row may name either particle first). None when not touching."""
    total, found = np.zeros(3), False
    for row in rows:
        f = np.array([row["fx"], row["fy"], row["fz"]])
        if wall is not None:
            if int(row["id"]) == body and int(row["partner"]) == -1 and int(row["wall"]) == wall:
                total += f
                found = True
        elif int(row["wall"]) == -1:
            if int(row["id"]) == body and int(row["partner"]) == partner:
                total += f
                found = True
            elif int(row["id"]) == partner and int(row["partner"]) == body:
                total -= f
                found = True
    return total if found else None


def kinetic_energy(run_dir):
    with open(os.path.join(run_dir, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["time"]) for r in rows])
    k = np.array([float(r["translational_energy"]) + float(r["rotational_energy"]) for r in rows])
    return t, k


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    run_dir, out_dir = sys.argv[1:]
    os.makedirs(out_dir, exist_ok=True)
    stacks = bodies(run_dir)
    path, rows = last_contacts(run_dir)
    step = int(re.search(r"contacts_(\d+)\.csv$", path).group(1))
    all_ids = {b[0] for members in stacks.values() for b in members}
    expected = set()
    result = {"frame_step": step, "g": G, "stacks": {}}
    max_error = 0.0
    for stack, members in stacks.items():
        contacts = []
        for k, (i, shape, _, position) in enumerate(members):
            weight = G * sum(m for _, _, m, _ in members[k:])
            if k == 0:
                force = force_on(rows, i, wall=0)
                what = f"plane under {shape} (level 0)"
                expected.add((i, -1, 0))
            else:
                force = force_on(rows, i, partner=members[k - 1][0])
                what = f"{members[k - 1][1]} (level {k - 1}) under {shape} (level {k})"
                expected.add((min(i, members[k - 1][0]), max(i, members[k - 1][0]), -1))
            entry = {"contact": what, "lower": -1 if k == 0 else members[k - 1][0], "upper": i,
                     "weight_above_N": weight}
            if force is None:
                entry.update({"measured_fz_N": 0.0, "rel_error": 1.0, "touching": False})
                error = 1.0
            else:
                error = abs(force[2] - weight) / weight
                entry.update({"measured_fz_N": float(force[2]), "measured_fx_N": float(force[0]),
                              "measured_fy_N": float(force[1]),
                              "horizontal_over_vertical": float(np.hypot(*force[:2]) / abs(force[2])),
                              "rel_error": float(error), "touching": True})
            contacts.append(entry)
            max_error = max(max_error, error)
        tops = [float(p[2]) for _, _, _, p in members]
        axis = np.array([[p[0], p[1]] for _, _, _, p in members])
        result["stacks"][stack] = {
            "shapes_bottom_first": [s for _, s, _, _ in members],
            "masses_kg": [m for _, _, m, _ in members],
            "centroid_heights_m": tops,
            "largest_offset_from_axis_m": float(np.max(np.hypot(*(axis - axis[0]).T))),
            "contacts": contacts,
            "max_rel_error": max(c["rel_error"] for c in contacts),
            "max_horizontal_over_vertical": max(c.get("horizontal_over_vertical", 0)
                                                for c in contacts),
        }
    # Contacts the stacks should not have (between stacks, or skipping a level).
    others = []
    for row in rows:
        i, j, w = int(row["id"]), int(row["partner"]), int(row["wall"])
        key = (i, -1, w) if w >= 0 else (min(i, j), max(i, j), -1)
        if key not in expected and i in all_ids:
            others.append({"id": i, "partner": j, "wall": w,
                           "force_N": [row["fx"], row["fy"], row["fz"]]})
    t, k = kinetic_energy(run_dir)
    total_weight = sum(s["contacts"][0]["weight_above_N"] for s in result["stacks"].values())
    result.update({
        "contacts_file": os.path.relpath(path, run_dir),
        "unexpected_contacts": others,
        "kinetic_energy_final_J": float(k[-1]),
        "kinetic_energy_peak_J": float(k.max()),
        "kinetic_energy_max_last_10_percent_J": float(k[t >= 0.9 * t[-1]].max()),
        "total_weight_N": total_weight,
        "max_rel_error": max_error,
        "max_rel_error_per_stack": {s: v["max_rel_error"] for s, v in result["stacks"].items()},
        "material": {"density": make_scene.DENSITY, "youngs_modulus": make_scene.YOUNGS_MODULUS,
                     "poisson_ratio": make_scene.POISSON_RATIO,
                     "restitution": make_scene.RESTITUTION, "friction": make_scene.FRICTION},
        "time_step_s": make_scene.TIME_STEP, "duration_s": make_scene.DURATION,
    })
    with open(os.path.join(out_dir, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")

    fig, (ax, ax_k) = plt.subplots(1, 2, figsize=(11, 4.6))
    markers = {"cylinders_r0.1": "o", "cylinders_r5": "s", "plates_r0.1": "^",
               "plates_r5": "D", "mixed_r0.1": "x"}
    top = 0
    for stack, v in result["stacks"].items():
        w = [c["weight_above_N"] for c in v["contacts"]]
        f_ = [c["measured_fz_N"] for c in v["contacts"]]
        top = max(top, max(w), max(f_))
        ax.plot(w, f_, markers.get(stack, "o"), mfc="none", ms=8,
                label=f"{stack} (max rel. error {v['max_rel_error']:.1e})")
    ax.plot([0, top * 1.05], [0, top * 1.05], "k-", lw=0.8, label="y = x")
    ax.set_xlabel("weight of the bodies above the contact (N)")
    ax.set_ylabel("vertical contact force, last frame (N)")
    ax.set_title("Vertical stacks (book Sect. 4.3.3, Fig. 4.18)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax_k.semilogy(t, np.maximum(k, 1e-16))
    ax_k.set_xlabel("time (s)")
    ax_k.set_ylabel("kinetic energy of all bodies (J)")
    ax_k.set_title("Settling")
    ax_k.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "stack.png"), dpi=120)

    print(f"last frame: step {step}; final kinetic energy {k[-1]:.3e} J (peak {k.max():.3e} J)")
    for stack, v in result["stacks"].items():
        print(f"{stack}: max_rel_error {v['max_rel_error']:.3e}, "
              f"max |F_h|/F_z {v['max_horizontal_over_vertical']:.2e}")
        for c in v["contacts"]:
            print(f"   {c['contact']}: Fz {c['measured_fz_N']:.6f} N, weight "
                  f"{c['weight_above_N']:.6f} N, rel. error {c['rel_error']:.2e}")
    if others:
        print(f"{len(others)} unexpected contacts: {others}")
    print(f"max_rel_error {max_error:.3e}")


if __name__ == "__main__":
    main()
