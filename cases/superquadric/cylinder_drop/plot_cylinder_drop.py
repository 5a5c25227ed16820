#!/usr/bin/python3
"""Cylinder-like superquadric dropped on a frictionless plane: velocity and spin after the first
impact against rigid-body impact theory, as functions of the tilt.

usage: plot_cylinder_drop.py RUN_DIR_E1 RUN_DIR_E05 PNG

Theory (e.g. Brach, Mechanical Impact Dynamics, 1991; Stronge, Impact Mechanics, 2000), impulse
along the plane normal n at the body's lowest point r (from the centre), contact point velocity
v_c = v + w x r:
    J = -(1 + e) v_c.n / (1/m + (r x n).I^-1 (r x n)),  v' = v + J n / m,  w' = w + I^-1 (r x n) J
with I the world-frame inertia tensor at impact. The state after the first impact of each
particle is taken from the first checkpoint (every 1 us) in which the particle has no wall
contact any more after having had one; without gravity it stays constant until a later contact.
"""
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
import common  # noqa: E402
import make_scenes as geometry  # noqa: E402

DENSITY = 7800.0


def restitution_for_damping(gamma, h=2e-4):
    """Restitution of the scaled damped Hertz impact X'' = -X^1.5 - gamma sqrt(1.5) X^0.25 X',
    X(0) = 0, X'(0) = 1, by classical Runge-Kutta (independent of kdem's code)."""
    def f(x, u):
        xp = max(x, 0.0)
        return u, -xp ** 1.5 - gamma * math.sqrt(1.5) * xp ** 0.25 * u
    x, u = 0.0, 1.0
    while True:
        k1 = f(x, u)
        k2 = f(x + 0.5 * h * k1[0], u + 0.5 * h * k1[1])
        k3 = f(x + 0.5 * h * k2[0], u + 0.5 * h * k2[1])
        k4 = f(x + h * k3[0], u + h * k3[1])
        xn = x + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        un = u + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        if xn < 0 and un < 0:
            # linear interpolation of the velocity at the crossing
            return -(u + (un - u) * x / (x - xn))
        x, u = xn, un


def damping_for_restitution(e):
    """The closed form of kdem's contact law documentation (Tsuji et al. 1992 scaling)."""
    ln = math.log(e)
    return -2 * math.sqrt(5.0 / 6.0) * ln / math.sqrt(ln * ln + math.pi * math.pi)


def effective_restitution(e, mass_ratio):
    """Restitution of the contact law when the damping is set for mass m but the contact point
    moves with the effective mass m_eff = mass_ratio * m: the scaled damping grows by
    sqrt(m / m_eff)."""
    if e >= 1.0:
        return 1.0
    return restitution_for_damping(damping_for_restitution(e) / math.sqrt(mass_ratio))


def theory(tilt, e, mass, inertia_body):
    R = common.rotation_matrix(np.array([math.cos(tilt / 2), math.sin(tilt / 2), 0, 0]))
    r = R @ np.array(geometry.lowest_point_body(tilt))
    n = np.array([0.0, 0.0, 1.0])
    v = np.array([0.0, 0.0, -geometry.SPEED])
    I_inv = R @ np.diag(1 / inertia_body) @ R.T
    rn = np.cross(r, n)
    J = -(1 + e) * np.dot(v, n) / (1 / mass + rn @ I_inv @ rn)
    m_eff = 1 / (1 / mass + rn @ I_inv @ rn)
    return v + J * n / mass, I_inv @ rn * J, m_eff


def measured(run_dir):
    states = common.read_checkpoints(run_dir)
    count = len(states[0]["mass"])
    result = [None] * count
    touched = np.zeros(count, bool)
    later_contact = np.zeros(count, bool)
    for s in states:
        w = s["wall_contacts"] > 0
        for k in range(count):
            if result[k] is None:
                if w[k]:
                    touched[k] = True
                elif touched[k]:
                    result[k] = (s["velocity"][k].copy(), s["angular_velocity"][k].copy(), s["time"])
            elif w[k]:
                later_contact[k] = True
    tilts = []
    for k in range(count):
        q = states[0]["orientation"][k]
        tilts.append(2 * math.atan2(q[1], q[0]))
    return states[0], np.array(tilts), result, later_contact


def main():
    run_e1, run_e05, png = sys.argv[1:4]
    mass = DENSITY * common.superquadric_volume(geometry.A, geometry.B, geometry.C, geometry.N1, geometry.N2)
    inertia = common.superquadric_inertia(geometry.A, geometry.B, geometry.C, geometry.N1, geometry.N2, DENSITY)
    lines = []
    say = lambda text: (print(text), lines.append(text))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    fine = np.radians(np.linspace(0, 90, 361))
    colours = {1.0: "C0", 0.5: "C3"}
    for run_dir, e in ((run_e1, 1.0), (run_e05, 0.5)):
        first, tilts, result, later = measured(run_dir)
        say("e = %.1f: mass %.6e kg (closed form %.6e), inertia %s (closed form %s)"
            % (e, first["mass"][0], mass, np.array2string(first["inertia"][0], precision=5),
               np.array2string(inertia, precision=5)))
        say("  tilt   v_z' kdem   v_z' theory   w_x' kdem   w_x' theory   |dv|/v0   |dw|/|w'|  m_eff/m   e_eff = -v_c'/v_c   e(m_eff)  (speeds m/s, spins rad/s)")
        tv = np.array([theory(t, e, mass, inertia)[0][2] for t in fine])
        tw = np.array([theory(t, e, mass, inertia)[1][0] for t in fine])
        ax[0].plot(np.degrees(fine), tv, color=colours[e], lw=1, label="theory, e = %.1f" % e)
        ax[1].plot(np.degrees(fine), tw, color=colours[e], lw=1, label="theory, e = %.1f" % e)
        if e < 1:
            coarse = np.radians(np.linspace(0, 90, 91))
            corrected = []
            for t in coarse:
                ratio = theory(t, e, mass, inertia)[2] / mass
                e_c = effective_restitution(e, ratio)
                v_c, w_c, _ = theory(t, e_c, mass, inertia)
                corrected.append((v_c[2], w_c[0]))
            corrected = np.array(corrected)
            ax[0].plot(np.degrees(coarse), corrected[:, 0], "--", color=colours[e], lw=1,
                       label="theory with e(m_eff), e = %.1f" % e)
            ax[1].plot(np.degrees(coarse), corrected[:, 1], "--", color=colours[e], lw=1,
                       label="theory with e(m_eff), e = %.1f" % e)
        mv, mw = [], []
        for k, tilt in enumerate(tilts):
            v_t, w_t, m_eff = theory(tilt, e, mass, inertia)
            if result[k] is None:
                say("  %5.2f  no separation within the run" % math.degrees(tilt))
                mv.append(np.nan), mw.append(np.nan)
                continue
            v, w, t_sep = result[k]
            # effective restitution of the contact point: -v_c'.n / v_c.n, r from theory
            R = common.rotation_matrix(first["orientation"][k])
            r = R @ np.array(geometry.lowest_point_body(tilt))
            vc_after = v[2] + np.cross(w, r)[2]
            e_eff = vc_after / geometry.SPEED
            dv = np.linalg.norm(v - v_t) / geometry.SPEED
            dw = np.linalg.norm(w - w_t) / np.linalg.norm(w_t) if np.linalg.norm(w_t) > 1e-9 else np.nan
            say("  %5.2f  %10.5f  %11.5f  %10.3f  %12.3f  %8.1e  %9.1e  %7.3f  %8.4f  %8.4f%s"
                % (math.degrees(tilt), v[2], v_t[2], w[0], w_t[0], dv, dw, m_eff / mass, e_eff,
                   effective_restitution(e, m_eff / mass),
                   "  (touches the plane again later)" if later[k] else ""))
            mv.append(v[2]), mw.append(w[0])
        ax[0].plot(np.degrees(tilts), mv, "o", color=colours[e], mfc="none", label="kdem, e = %.1f" % e)
        ax[1].plot(np.degrees(tilts), mw, "o", color=colours[e], mfc="none", label="kdem, e = %.1f" % e)
    ax[0].set_xlabel("tilt of the cylinder axis from vertical (deg)")
    ax[0].set_ylabel("vertical velocity after impact (m/s)")
    ax[0].set_title("n1 = 8, n2 = 2 cylinder on a frictionless plane, v0 = 0.5 m/s")
    ax[0].legend()
    ax[1].set_xlabel("tilt of the cylinder axis from vertical (deg)")
    ax[1].set_ylabel("spin after impact about x (rad/s)")
    ax[1].legend()
    fig.tight_layout()
    common.save_figure_and_summary(
        fig, png, os.path.join(os.path.dirname(os.path.abspath(run_e1)), "summary.txt"), lines)


if __name__ == "__main__":
    main()
