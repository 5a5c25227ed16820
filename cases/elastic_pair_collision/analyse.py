"""Reads the elastic pair collision runs (one scene per shape, so each series.csv holds one pair)
and writes result.json and the plot (book Fig. 4.12: translational, rotational and total kinetic
energy against time, normalised).

Per shape: the kinetic energy before (the first row) and after (the last row, once the bodies are
apart for good: their centres farther apart than the sum of their bounding radii and receding,
so that without gravity they cannot meet again), energy_error = after / before - 1, the
translational and rotational energy after, the contact episodes (maximal runs of series rows,
one per step, with a contact point of positive overlap), the mass and volume from the
checkpoint. A run the engine stopped (exit status 3: one of its checks, failure.json) has no
"after": its failure is reported, with the energy after its last complete episode before it.

Time is normalised by the Hertz duration t_H of the central impact of the volume-equivalent
spheres at the relative speed 1 m/s (R* = R/2, m* = m/2, E* = E / (2 (1 - nu^2)), as the engine's
contact law for dilated polyhedra uses, Eq. 4.19), from the first contact; energy by the
kinetic energy before.

usage: analyse.py OUT_DIR RESULTS_DIR
  OUT_DIR holds calibration.json and the runs dt1e-6/<scene>/ (and dt2.5e-7/<scene>/ for the
  time-step check)."""
import json
import math
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scene as ms  # noqa: E402

MAIN = "dt1e-6"
FINE = "dt2.5e-7"
LABELS = {"sphere": "dilated sphere", "super_ellipsoid": "super-ellipsoid",
          "harmonic": "spherical-harmonic body", "polyhedron": "polyhedron"}


def hertz_duration(mass):
    e_star = ms.YOUNGS_MODULUS / (2 * (1 - ms.POISSON ** 2))
    r_star = ms.EQUIVALENT_RADIUS / 2
    m_star = mass / 2
    v = 2 * ms.SPEED
    overlap = (15 * m_star * v ** 2 / (16 * e_star * math.sqrt(r_star))) ** 0.4
    return 2.9432 * overlap / v


def episodes(contacts):
    """(first row, last row) of each maximal run of rows with a contact."""
    on = np.concatenate([[0], (contacts > 0).astype(int), [0]])
    starts = np.nonzero(np.diff(on) == 1)[0]
    ends = np.nonzero(np.diff(on) == -1)[0] - 1
    return list(zip(starts, ends))


def read_run(run_dir):
    if not os.path.isdir(run_dir) or not (
            os.path.exists(os.path.join(run_dir, "checkpoint.h5"))
            or os.path.exists(os.path.join(run_dir, "failure.json"))):
        return None  # not run, or not finished
    s = np.genfromtxt(os.path.join(run_dir, "series.csv"), delimiter=",", names=True)
    failure = None
    checkpoint = os.path.join(run_dir, "checkpoint.h5")
    if os.path.exists(os.path.join(run_dir, "failure.json")):
        with open(os.path.join(run_dir, "failure.json")) as f:
            failure = json.load(f)
        checkpoint = os.path.join(run_dir, "failure_checkpoint.h5")
    with h5py.File(checkpoint, "r") as f:
        state = {k: f["particles/" + k][...] for k in
                 ("position", "velocity", "mass", "radius")}
    wall = None
    if os.path.exists(os.path.join(run_dir, "run.json")):
        with open(os.path.join(run_dir, "run.json")) as f:
            wall = json.load(f)["wall_seconds"]
    return s, state, failure, wall


def summarise(run_dir):
    """The quantities of one run, and its curves for the plot."""
    got = read_run(run_dir)
    if got is None:
        return None, None
    s, state, failure, wall = got
    t = s["time"]
    et, er = s["translational_energy"], s["rotational_energy"]
    total = et + er
    before = float(total[0])
    mass = float(state["mass"][0, 0])
    eps = episodes(s["pair_contacts"])
    row = {"energy_before_J": before, "mass_kg": mass, "volume_m3": mass / ms.DENSITY,
           "volume_error": mass / ms.DENSITY / ms.TARGET_VOLUME - 1,
           "bounding_radius_m": float(state["radius"][0, 0]),
           "contact_episodes": len(eps),
           "episodes_s": [[float(t[a]), float(t[b])] for a, b in eps],
           "episode_energy_errors": [float(total[min(b + 1, len(t) - 1)] / before - 1)
                                     for a, b in eps],
           "max_contact_points": int(s["pair_contacts"].max()),
           "largest_overlap_ratio": float(s["largest_overlap_ratio"].max()),
           "simulated_time_s": float(t[-1]), "wall_seconds": wall}
    if failure is None:
        dx = state["position"][1] - state["position"][0]
        dv = state["velocity"][1] - state["velocity"][0]
        apart = (float(np.linalg.norm(dx)) > float(state["radius"][:, 0].sum())
                 and float(np.dot(dx, dv)) > 0)
        row.update({"status": "apart for good" if apart else "NOT apart at the end of the run",
                    "energy_after_J": float(total[-1]),
                    "energy_error": float(total[-1] / before - 1),
                    "translational_after_J": float(et[-1]),
                    "rotational_after_J": float(er[-1]),
                    "rotational_fraction_after": float(er[-1] / total[-1])})
        if not apart:
            row["energy_error"] = None
    else:
        complete = [(a, b) for a, b in eps if b + 1 < len(t) - 1]
        last = complete[-1][1] + 1 if complete else 0
        row.update({"status": "stopped by the engine's checks (failure.json)",
                    "stopped_at_s": float(failure["time"]),
                    "engine_finding": failure["finding"],
                    "energy_after_J": None, "energy_error": None,
                    "energy_error_after_last_complete_episode": float(total[last] / before - 1),
                    "translational_after_last_complete_episode_J": float(et[last]),
                    "rotational_after_last_complete_episode_J": float(er[last]),
                    "first_overlap_ratio_of_failing_episode":
                        float(s["largest_overlap_ratio"][eps[-1][0]]) if eps else None})
    t_hertz = hertz_duration(mass)
    t0 = t[eps[0][0]] if eps else 0.0
    curves = {"tau": (t - t0) / t_hertz, "translational": et / before,
              "rotational": er / before, "total": total / before,
              "episodes": [((t[a] - t0) / t_hertz, (t[b] - t0) / t_hertz) for a, b in eps],
              "failure": failure is not None}
    row["hertz_duration_s"] = t_hertz
    row["first_contact_s"] = float(t0)
    return row, curves


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out, results = sys.argv[1:]
    with open(os.path.join(out, "calibration.json")) as f:
        calibration = json.load(f)
    shapes, curves = {}, {}
    for name in ms.SHAPES:
        row, curve = summarise(os.path.join(out, MAIN, name))
        row["core_scale"] = calibration["shapes"][name]["scale"]
        fine, _ = summarise(os.path.join(out, FINE, name))
        if fine is not None:
            row["time_step_check"] = {
                "time_step_s": 2.5e-7, "status": fine["status"],
                "energy_error": fine["energy_error"],
                "contact_episodes": fine["contact_episodes"],
                "rotational_fraction_after": fine.get("rotational_fraction_after"),
                "stopped_at_s": fine.get("stopped_at_s")}
        shapes[name], curves[name] = row, curve
    checks = {}
    fine_sphere, _ = summarise(os.path.join(out, MAIN, ms.FINE_SPHERE))
    if fine_sphere is not None:
        checks[ms.FINE_SPHERE] = fine_sphere
    errors = [abs(r["energy_error"]) for r in shapes.values() if r["energy_error"] is not None]
    result = {
        "case": "elastic_pair_collision",
        "reference": "book Sect. 4.3.1, Figs. 4.11-4.12 (digest ch4_5 Tables A6.1-A6.2 row 1): "
                     "elastic frictionless collision of two identical dilated polyhedra; total "
                     "kinetic energy conserved, part of the translational energy of the "
                     "irregular shapes turned into rotational",
        "setup": {"equivalent_radius_m": ms.EQUIVALENT_RADIUS, "target_volume_m3": ms.TARGET_VOLUME,
                  "dilation_radius_m": ms.DILATION, "density": ms.DENSITY,
                  "youngs_modulus_Pa": ms.YOUNGS_MODULUS, "poisson_ratio": ms.POISSON,
                  "restitution": 1.0, "friction": 0.0, "rolling_friction": 0.0,
                  "speed_of_each_body_m_s": ms.SPEED, "lateral_offset_m": ms.OFFSET,
                  "time_step_s": ms.TIME_STEP, "duration_s": ms.DURATION,
                  "super_ellipsoid": ms.SUPER_ELLIPSOID, "harmonics": ms.HARMONICS,
                  "polyhedron": f"convex hull of {ms.POLYHEDRON_POINTS} random points "
                                f"(seed {ms.POLYHEDRON_SEED})",
                  "orientation_seed": ms.SEED},
        "shapes": shapes,
        "checks": checks,
        "max_abs_energy_error": max(errors) if errors else None,
        "max_abs_energy_error_over": [n for n in ms.SHAPES
                                      if shapes[n]["energy_error"] is not None],
        "shapes_without_energy_error": [n for n in ms.SHAPES
                                        if shapes[n]["energy_error"] is None],
    }
    os.makedirs(results, exist_ok=True)
    write_json(os.path.join(results, "result.json"), result)
    plot(os.path.join(results, "elastic_pair_collision.png"), curves, shapes)
    for name in ms.SHAPES:
        r = shapes[name]
        err = r["energy_error"]
        print(f"{name}: {r['contact_episodes']} episode(s), energy_error "
              + (f"{err:.2e}" if err is not None else "none") + f", {r['status']}")
    print(f"max |energy_error| = {result['max_abs_energy_error']:.2e} over "
          f"{result['max_abs_energy_error_over']}")


def write_json(path, value):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(value, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def plot(path, curves, shapes):
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    for ax, name in zip(axes.ravel(), ms.SHAPES):
        c = curves[name]
        end = max(b for _, b in c["episodes"]) + 3 if c["episodes"] else 5
        keep = (c["tau"] >= -1) & (c["tau"] <= end)
        for a, b in c["episodes"]:
            ax.axvspan(a, b, color="0.9")
        ax.plot(c["tau"][keep], c["translational"][keep], color="C0", label="translational")
        ax.plot(c["tau"][keep], c["rotational"][keep], color="C1", label="rotational")
        ax.plot(c["tau"][keep], c["total"][keep], color="k", lw=1, label="total")
        r = shapes[name]
        title = f"{LABELS[name]}: {r['contact_episodes']} contact episode(s)"
        if r["energy_error"] is not None:
            title += f", error {r['energy_error']:.1e}"
        ax.set_title(title, fontsize=9)
        if c["failure"]:
            ax.set_ylim(-0.05, 1.3)
            ax.text(0.08, 0.12, f"run stopped by the engine's checks\n"
                    f"at {r['stopped_at_s'] * 1e3:.1f} ms (failure.json)",
                    transform=ax.transAxes, fontsize=8, color="C3")
        ax.set_xlabel(r"$(t - t_{\rm first\ contact}) / t_{\rm Hertz}$")
        ax.set_ylabel(r"$E / E_{\rm kin,0}$")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="center right")
    fig.suptitle("Elastic collision of two identical dilated polyhedra (shaded: in contact)")
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, path)


if __name__ == "__main__":
    main()
