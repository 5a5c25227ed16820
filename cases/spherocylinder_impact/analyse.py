"""Compares a spherocylinder_impact run with the book's Eqs. 3.30 and 3.31 (Kodam et al. 2012) and
writes result.json and the plot beside it.

The analytic rebound uses the simulated body's own mass and inertia I_yy (the union of its
elements, as the engine computed them: read from the checkpoint) and the restitution the engine's
damping gives in a central impact (end-on, theta0 = 0, where the formulas reduce to v+ = -e v-):
  w_y+ = m v- (1 + e) c0 sin(theta0) / (I_yy + m c0^2 sin^2(theta0))      (3.30)
  v+   = w_y+ c0 sin(theta0) - e v-                                     (3.31)
with c0 = r0, the distance from the centroid to the landing sphere's centre. The true
spherocylinder's curves (m and I_yy of the book digest, Sect. 4.1) are drawn dotted.

An elastic run (restitution 1) is compared the same way: what is left without damping is the
contact's finite duration (the body turns while it lasts). With damping, also that the damping
acts with the body's mass where the contact point's effective mass m / (1 + m |r x n|^2 / I) is
smaller at oblique landings, so the effective restitution falls with the lever arm (book digest
Sect. 4.1, its own integration of this model).

usage: analyse.py RUN_DIR ELASTIC_RUN_DIR OUTPUT_DIR"""
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scene  # noqa: E402

# The true spherocylinder of r0 = c0 = 6 mm at 2500 kg/m3 (book digest Sect. 4.1).
TRUE_MASS = 5.65487e-3
TRUE_INERTIA_YY = 2.46326e-7
# The book's own union (digest Sect. 4.1, from its grid).
BOOK_UNION_MASS = 5.64113e-3
BOOK_UNION_INERTIA_YY = 2.45756e-7


def final_state(run_dir):
    """Per source's particle at the end of the run, ordered by angle: velocity, angular velocity
    (world), mass and principal inertia (body frame: the spherocylinder's axes)."""
    with h5py.File(os.path.join(run_dir, "checkpoint.h5"), "r") as f:
        source = f["particles/source"][:, 0]
        velocity = f["particles/velocity"][...]
        spin = f["particles/angular_velocity"][...]
        mass = f["particles/mass"][:, 0]
        inertia = f["particles/inertia"][...]
        names = f["source_names"][()].decode().split()  # one name per line
    angles = [int(names[s].split("_")[1]) for s in source]
    order = np.argsort(angles)
    return np.array(angles)[order], velocity[order], spin[order], mass[order], inertia[order]


def analytic(theta_degrees, mass, c0, inertia_yy, e, v_minus):
    arm = c0 * np.sin(np.radians(theta_degrees))
    spin = mass * v_minus * (1 + e) * arm / (inertia_yy + mass * arm ** 2)
    return spin * arm - e * v_minus, spin


def compared(run_dir, r0, v_minus):
    """The run's rebound against Eqs. 3.30-3.31 with its own mass properties and central-impact
    restitution."""
    angles, velocity, spin, masses, inertias = final_state(run_dir)
    if list(angles) != make_scene.ANGLES:
        sys.exit(f"{run_dir}: expected the angles {make_scene.ANGLES}, found {list(angles)}")
    mass, inertia_yy = float(masses[0]), float(inertias[0, 1])
    dem_v = velocity[:, 2] / v_minus
    dem_spin = r0 * spin[:, 1] / v_minus
    e_central = -velocity[angles == 0, 2][0] / v_minus
    theory_v, theory_w = analytic(angles, mass, r0, inertia_yy, e_central, v_minus)
    theory_v, theory_spin = theory_v / v_minus, r0 * theory_w / v_minus
    errors = np.concatenate([np.abs(dem_v - theory_v), np.abs(dem_spin - theory_spin)])
    rows = [{"theta0_degrees": int(a), "v_ratio": float(dv), "v_ratio_analytic": float(tv),
             "spin_ratio": float(ds), "spin_ratio_analytic": float(ts),
             "v_ratio_error": float(abs(dv - tv)), "spin_ratio_error": float(abs(ds - ts))}
            for a, dv, tv, ds, ts in zip(angles, dem_v, theory_v, dem_spin, theory_spin)]
    body = {"mass_kg": mass, "inertia_yy_kg_m2": inertia_yy}
    return ({"restitution_central_impact": float(e_central), "rows": rows,
             "max_abs_error": float(np.max(errors))}, body,
            (angles, dem_v, dem_spin, e_central, mass, inertia_yy))


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    run_dir, elastic_dir, out_dir = sys.argv[1:]
    r0, v_minus = make_scene.R0, -make_scene.SPEED
    damped, body, points = compared(run_dir, r0, v_minus)
    elastic, _, elastic_points = compared(elastic_dir, r0, v_minus)
    result = {
        "case": "spherocylinder_impact",
        "reference": "book Eqs. 3.30, 3.31 (Kodam et al. 2012): rigid-body impulse at the landing "
                     "sphere, with the union's own m and I_yy",
        "quantities": "v_ratio = v_z+ / v_z-, spin_ratio = r0 w_y+ / v_z- (book Fig. 3.11b-c)",
        "body": {"r0_m": r0, "c0_m": r0, **body,
                 "mass_error_against_true_spherocylinder": body["mass_kg"] / TRUE_MASS - 1,
                 "inertia_yy_error_against_true_spherocylinder":
                     body["inertia_yy_kg_m2"] / TRUE_INERTIA_YY - 1,
                 "mass_error_against_book_union": body["mass_kg"] / BOOK_UNION_MASS - 1,
                 "inertia_yy_error_against_book_union":
                     body["inertia_yy_kg_m2"] / BOOK_UNION_INERTIA_YY - 1},
        "restitution_input": 0.85,
        **damped,
        "elastic": {"restitution_input": 1.0, **elastic},
    }
    os.makedirs(out_dir, exist_ok=True)
    write_json(os.path.join(out_dir, "result.json"), result)
    plot(os.path.join(out_dir, "spherocylinder_impact.png"), points, elastic_points, v_minus, r0)
    print(f"spherocylinder_impact: e (central) = {damped['restitution_central_impact']:.4f}, "
          f"max |error| = {damped['max_abs_error']:.2e}; elastic: "
          f"{elastic['max_abs_error']:.2e}")


def write_json(path, value):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(value, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def plot(path, points, elastic_points, v_minus, r0):
    theta = np.linspace(0, 90, 181)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for (angles, dem_v, dem_spin, e, mass, inertia_yy), colour in ((points, "C0"),
                                                                    (elastic_points, "C1")):
        body_v, body_w = analytic(theta, mass, r0, inertia_yy, e, v_minus)
        true_v, true_w = analytic(theta, TRUE_MASS, r0, TRUE_INERTIA_YY, e, v_minus)
        for ax, dem, model, true in ((axes[0], dem_spin, r0 * body_w / v_minus,
                                      r0 * true_w / v_minus),
                                     (axes[1], dem_v, body_v / v_minus, true_v / v_minus)):
            ax.plot(theta, model, "-", color=colour, label=f"Eqs. 3.30-3.31, this body, e = {e:.3f}")
            ax.plot(theta, true, ":", color=colour, label="Eqs. 3.30-3.31, true spherocylinder")
            ax.plot(angles, dem, "o", color=colour, label="kdem")
    for ax, label in ((axes[0], r"$r_0\,\omega_y^+ / v_z^-$"), (axes[1], r"$v_z^+ / v_z^-$")):
        ax.set_xlabel(r"tilt angle $\theta_0$ (degrees)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=7)
    fig.suptitle("Multi-superquadric spherocylinder on a frictionless plane")
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, path)


if __name__ == "__main__":
    main()
