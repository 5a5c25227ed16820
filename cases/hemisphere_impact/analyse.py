"""Compares a hemisphere_impact run with the book's Eqs. 3.32 and 3.33 (Kodam et al. 2010) and
writes result.json and the plot beside it.

The analytic rebound uses the simulated body's own mass, centroid offset c0 and inertia I_yy
(closed form, poly_superquadric.py) and the restitution the engine's damping gives in a central
impact (the pole landing, phi0 = 90 degrees, where the formulas reduce to v+ = -e v-):
  w_y+ = -m v- (1 + e) c0 cos(phi0) / (I_yy + m c0^2 cos^2(phi0))      (3.32)
  v+   = -w_y+ c0 cos(phi0) - e v-                                     (3.33)
The true hemisphere's analytic curves (m = 2/3 pi r0^3 rho, c0 = 3 r0 / 8, I_yy = 83/320 m r0^2)
are drawn for comparison.

An elastic run (restitution 1) is compared the same way: without damping, what is left is the
geometry, mass properties and the turn of the body during the contact (which the impulse theory
neglects); with damping, also that the damping acts with the body's mass where the contact
point's effective mass m / (1 + m |r x n|^2 / I) is smaller at oblique landings (so the
effective restitution falls with the lever arm, as the digest's own integration of this model
shows; book digest Sect. 4.1).

usage: analyse.py RUN_DIR ELASTIC_RUN_DIR OUTPUT_DIR"""
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
import make_scene  # noqa: E402
import poly_superquadric  # noqa: E402

DENSITY = 2500.0


def final_state(run_dir):
    """Velocity and angular velocity (world) of each source's particle at the end of the run."""
    with h5py.File(os.path.join(run_dir, "checkpoint.h5"), "r") as f:
        source = f["particles/source"][:, 0]
        velocity = f["particles/velocity"][...]
        spin = f["particles/angular_velocity"][...]
        names = f["source_names"][()].decode().split()  # one name per line
    angles = [int(names[s].split("_")[1]) for s in source]
    order = np.argsort(angles)
    return np.array(angles)[order], velocity[order], spin[order]


def analytic(phi_degrees, mass, c0, inertia_yy, e, v_minus):
    arm = c0 * np.cos(np.radians(phi_degrees))
    spin = -mass * v_minus * (1 + e) * arm / (inertia_yy + mass * arm ** 2)
    return -spin * arm - e * v_minus, spin


def compared(run_dir, mass, c0, inertia_yy, r0, v_minus):
    """The run's rebound against Eqs. 3.32-3.33 with its central-impact restitution."""
    angles, velocity, spin = final_state(run_dir)
    if list(angles) != make_scene.ANGLES:
        sys.exit(f"{run_dir}: expected the angles {make_scene.ANGLES}, found {list(angles)}")
    dem_v = velocity[:, 2] / v_minus
    dem_spin = r0 * spin[:, 1] / v_minus
    e_central = -velocity[angles == 90, 2][0] / v_minus
    theory_v, theory_w = analytic(angles, mass, c0, inertia_yy, e_central, v_minus)
    theory_v, theory_spin = theory_v / v_minus, r0 * theory_w / v_minus
    errors = np.concatenate([np.abs(dem_v - theory_v), np.abs(dem_spin - theory_spin)])
    rows = [{"phi0_degrees": int(a), "v_ratio": float(dv), "v_ratio_analytic": float(tv),
             "spin_ratio": float(ds), "spin_ratio_analytic": float(ts),
             "v_ratio_error": float(abs(dv - tv)), "spin_ratio_error": float(abs(ds - ts))}
            for a, dv, tv, ds, ts in zip(angles, dem_v, theory_v, dem_spin, theory_spin)]
    return {"restitution_central_impact": float(e_central), "rows": rows,
            "max_abs_error": float(np.max(errors))}, (angles, dem_v, dem_spin, e_central)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    run_dir, elastic_dir, out_dir = sys.argv[1:]
    r0, v_minus = make_scene.R0, -make_scene.SPEED
    mass, centroid, inertia = poly_superquadric.mass_properties(
        [r0, r0, r0], [make_scene.CAP, r0, r0], 2, 2, DENSITY)
    c0 = centroid[0]
    damped, points = compared(run_dir, mass, c0, inertia[1, 1], r0, v_minus)
    elastic, elastic_points = compared(elastic_dir, mass, c0, inertia[1, 1], r0, v_minus)
    true_mass = DENSITY * 2.0 / 3.0 * math.pi * r0 ** 3
    result = {
        "case": "hemisphere_impact",
        "reference": "book Eqs. 3.32, 3.33 (Kodam et al. 2010): rigid-body impulse at the dome",
        "quantities": "v_ratio = v_z+ / v_z-, spin_ratio = r0 w_y+ / v_z- (book Fig. 3.12c-d)",
        "body": {"r0_m": r0, "r_x_minus_m": make_scene.CAP, "mass_kg": mass, "c0_m": c0,
                 "inertia_yy_kg_m2": inertia[1, 1], "true_hemisphere_mass_kg": true_mass},
        "restitution_input": 0.85,
        **damped,
        "elastic": {"restitution_input": 1.0, **elastic},
    }
    os.makedirs(out_dir, exist_ok=True)
    write_json(os.path.join(out_dir, "result.json"), result)
    plot(os.path.join(out_dir, "hemisphere_impact.png"), points, elastic_points, mass, c0,
         inertia[1, 1], v_minus, r0)
    print(f"hemisphere_impact: e (central) = {damped['restitution_central_impact']:.4f}, "
          f"max |error| = {damped['max_abs_error']:.2e}; elastic: "
          f"{elastic['max_abs_error']:.2e}")


def write_json(path, value):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(value, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def plot(path, points, elastic_points, mass, c0, inertia_yy, v_minus, r0):
    phi = np.linspace(0, 90, 181)
    true_mass = DENSITY * 2.0 / 3.0 * math.pi * r0 ** 3
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for (angles, dem_v, dem_spin, e), colour in ((points, "C0"), (elastic_points, "C1")):
        body_v, body_w = analytic(phi, mass, c0, inertia_yy, e, v_minus)
        true_v, true_w = analytic(phi, true_mass, 3 * r0 / 8, 83 / 320 * true_mass * r0 ** 2, e,
                                  v_minus)
        for ax, dem, body, true in ((axes[0], dem_spin, r0 * body_w / v_minus,
                                     r0 * true_w / v_minus),
                                    (axes[1], dem_v, body_v / v_minus, true_v / v_minus)):
            ax.plot(phi, body, "-", color=colour, label=f"Eqs. 3.32-3.33, this body, e = {e:.3f}")
            ax.plot(phi, true, ":", color=colour, label="Eqs. 3.32-3.33, true hemisphere")
            ax.plot(angles, dem, "o", color=colour, label="kdem")
    for ax, label in ((axes[0], r"$r_0\,\omega_y^+ / v_z^-$"), (axes[1], r"$v_z^+ / v_z^-$")):
        ax.set_xlabel(r"landing angle $\varphi_0$ (degrees)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=7)
    fig.suptitle("Poly-superquadric hemisphere on a frictionless plane")
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, path)


if __name__ == "__main__":
    main()
