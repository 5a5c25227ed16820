#!/usr/bin/python3
"""Two ellipsoids colliding: kinetic energy, linear and angular momentum before/after, and the
measured restitution against the input.

usage: plot_two_ellipsoids.py HEAD_ON_RUN_DIR OBLIQUE_RUN_DIR PNG

HEAD_ON_RUN_DIR: output of head_on.yaml (three pairs, e = 1.0, 0.7, 0.3, mu = 0).
OBLIQUE_RUN_DIR: output of oblique.yaml (one pair, e = 0.6, mu = 0.4, general orientations).
Prints a summary and writes it to summary.txt in OBLIQUE_RUN_DIR's parent.
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import common  # noqa: E402

A, B, C = 1e-3, 1e-3, 2e-3
DENSITY = 2500.0
INPUT_RESTITUTION = {-0.02: 1.0, 0.0: 0.7, 0.02: 0.3}   # pair's y position -> input e


def ellipsoid_gradient(local):
    return 2 * local / np.array([A, B, C]) ** 2


def main():
    head_dir, oblique_dir, png = sys.argv[1:4]
    lines = []
    say = lambda text: (print(text), lines.append(text))

    # ---------------- head-on ----------------
    states = common.read_checkpoints(head_dir)
    first, last = states[0], states[-1]
    mass = first["mass"][0]
    mass_closed_form = DENSITY * common.superquadric_volume(A, B, C, 2, 2)
    inertia_closed_form = common.superquadric_inertia(A, B, C, 2, 2, DENSITY)
    say("mass in checkpoint %.6e kg, closed form %.6e kg (4/3 pi a b c rho)" % (mass, mass_closed_form))
    say("inertia in checkpoint %s, closed form %s (m (b^2+c^2)/5 ...)" %
        (np.array2string(first["inertia"][0], precision=6), np.array2string(inertia_closed_form, precision=6)))
    pairs = {}
    for k in range(len(first["mass"])):
        y = round(first["position"][k, 1], 2)
        pairs.setdefault(y, []).append(k)
    t = np.array([s["time"] for s in states])
    head_energy, head_momentum, head_results = {}, {}, []
    for y, members in sorted(pairs.items()):
        members.sort(key=lambda k: first["position"][k, 0])
        left, right = members
        e_in = INPUT_RESTITUTION[y]
        approach = first["velocity"][left, 0] - first["velocity"][right, 0]
        rebound = last["velocity"][right, 0] - last["velocity"][left, 0]
        e_meas = rebound / approach
        energy = []
        momentum = []
        for s in states:
            tr, rot = common.kinetic_energy(s)
            energy.append(tr[members].sum() + rot[members].sum())
            p, L = common.momenta(s, members)
            momentum.append(p)
        energy = np.array(energy)
        momentum = np.array(momentum)
        head_energy[e_in] = energy / energy[0]
        head_momentum[e_in] = momentum[:, 0] / (mass * 0.5)
        spin = max(np.linalg.norm(last["angular_velocity"][k]) for k in members)
        lateral = max(abs(last["velocity"][k, 1]) + abs(last["velocity"][k, 2]) for k in members)
        p_after = np.linalg.norm(momentum[-1])
        head_results.append((e_in, e_meas))
        say("head-on e_in = %.2f: measured restitution %.5f (error %+.2e), KE after/before %.5f "
            "(e^2 = %.5f), |p| after %.2e (m v = %.2e), largest spin after %.2e rad/s, lateral speed %.1e m/s"
            % (e_in, e_meas, e_meas - e_in, energy[-1] / energy[0], e_in ** 2, p_after, mass * 0.5,
               spin, lateral))

    # ---------------- oblique ----------------
    ostates = common.read_checkpoints(oblique_dir)
    series = common.read_series(oblique_dir)
    to = np.array([s["time"] for s in ostates])
    p0, L0 = common.momenta(ostates[0])
    # the pair's total momentum is zero: changes are measured against the sum of |m v|
    p_scale = sum(ostates[0]["mass"][k] * np.linalg.norm(ostates[0]["velocity"][k]) for k in range(2))
    tr0, rot0 = common.kinetic_energy(ostates[0])
    E0 = tr0.sum() + rot0.sum()
    dp, dL, energy = [], [], []
    touching = []
    for s in ostates:
        p, L = common.momenta(s)
        dp.append(np.linalg.norm(p - p0) / p_scale)
        dL.append(np.linalg.norm(L - L0) / np.linalg.norm(L0))
        tr, rot = common.kinetic_energy(s)
        energy.append((tr.sum(), rot.sum()))
        ov = s["pairs"].get("overlap")
        touching.append(ov is not None and len(ov) > 0 and np.any(ov[:, 0] > 0))
    dp, dL, energy = np.array(dp), np.array(dL), np.array(energy)
    touching = np.array(touching)
    first_touch = int(np.argmax(touching))
    last_touch = len(touching) - 1 - int(np.argmax(touching[::-1]))
    before, after = ostates[first_touch - 1], ostates[last_touch + 1]
    assert touching.any() and not touching[-1], "the oblique pair must touch and separate"
    # contact normal and point at first touch: the midway point, the normal of particle i there
    s = ostates[first_touch]
    i, j = int(s["pairs"]["pair_i"][0, 0]), int(s["pairs"]["pair_j"][0, 0])
    # pair indices are storage indices; checkpoint fields were sorted by id: map back
    with_ids = common.h5py.File(sorted(common.glob.glob(os.path.join(oblique_dir, "checkpoints", "*.h5")))[first_touch], "r")
    stored_ids = with_ids["particles/id"][:, 0]
    with_ids.close()
    i, j = int(stored_ids[i]), int(stored_ids[j])
    x_c = s["pairs"]["midway_point"][0]
    R_i = common.rotation_matrix(s["orientation"][i])
    n = R_i @ ellipsoid_gradient(R_i.T @ (x_c - s["position"][i]))
    n /= np.linalg.norm(n)
    if np.dot(n, s["position"][j] - s["position"][i]) < 0:
        n = -n

    def contact_velocity(state):
        vi = state["velocity"][i] + np.cross(state["angular_velocity"][i], x_c - state["position"][i])
        vj = state["velocity"][j] + np.cross(state["angular_velocity"][j], x_c - state["position"][j])
        return vj - vi

    vn_before = np.dot(contact_velocity(before), n)
    vn_after = np.dot(contact_velocity(after), n)
    p1, L1 = common.momenta(ostates[-1])
    tr1, rot1 = common.kinetic_energy(ostates[-1])
    E1 = tr1.sum() + rot1.sum()
    # effective mass of the pair along n at the contact point
    inv_m = 0.0
    for k in (i, j):
        r = x_c - s["position"][k]
        rn = np.cross(r, n)
        Iw = common.world_inertia(s["orientation"][k], s["inertia"][k])
        inv_m += 1 / s["mass"][k] + rn @ np.linalg.solve(Iw, rn)
    m_eff = 1 / inv_m
    say("oblique (e = 0.6, mu = 0.4): contact from t = %.1f to %.1f us (checkpoints every %.0f us)"
        % (to[first_touch] * 1e6, to[last_touch] * 1e6, (to[1] - to[0]) * 1e6))
    say("  linear momentum before %s kg m/s, after %s, |dp|/sum|m v| = %.2e (largest during run %.2e)"
        % (np.array2string(p0, precision=4), np.array2string(p1, precision=4),
           np.linalg.norm(p1 - p0) / p_scale, dp.max()))
    say("  angular momentum about origin before %s kg m^2/s, after %s, |dL|/|L0| = %.2e (largest %.2e)"
        % (np.array2string(L0, precision=4), np.array2string(L1, precision=4),
           np.linalg.norm(L1 - L0) / np.linalg.norm(L0), dL.max()))
    say("  kinetic energy before %.6e J, after %.6e J: %.1f %% dissipated (translational %.3e -> %.3e, "
        "rotational %.3e -> %.3e)" % (E0, E1, 100 * (1 - E1 / E0), tr0.sum(), tr1.sum(), rot0.sum(), rot1.sum()))
    say("  series.csv total KE: first %.6e J, last %.6e J" %
        (series["translational_energy"][0] + series["rotational_energy"][0],
         series["translational_energy"][-1] + series["rotational_energy"][-1]))
    say("  normal at first touch %s, effective mass along it %.3f m (m/2 for a central contact)"
        % (np.array2string(n, precision=3), m_eff / mass))
    say("  kinematic normal restitution at the first-touch point: -v_n'/v_n = %.4f (input 0.6; v_n = %.4f, "
        "v_n' = %.4f m/s)" % (-vn_after / vn_before, vn_before, vn_after))

    # ---------------- plot ----------------
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for e_in, energy_curve in head_energy.items():
        ax[0, 0].plot(t * 1e6, energy_curve, label="input e = %.1f" % e_in)
        ax[0, 0].axhline(e_in ** 2, color="gray", lw=0.6, ls=":")
    ax[0, 0].set_xlabel("time (us)")
    ax[0, 0].set_ylabel("kinetic energy / initial")
    ax[0, 0].set_title("head-on, along long axes (dotted: e$^2$)")
    ax[0, 0].legend()
    for e_in, mom in head_momentum.items():
        ax[0, 1].plot(t * 1e6, mom, label="input e = %.1f" % e_in)
    ax[0, 1].set_xlabel("time (us)")
    ax[0, 1].set_ylabel("total p$_x$ / (m v)")
    ax[0, 1].set_title("head-on: total momentum of each pair")
    ins = ax[0, 1].inset_axes([0.55, 0.55, 0.4, 0.38])
    ins.plot([r[0] for r in head_results], [r[1] for r in head_results], "o")
    ins.plot([0, 1], [0, 1], "k-", lw=0.6)
    ins.set_xlabel("input e", fontsize=7)
    ins.set_ylabel("measured e", fontsize=7)
    ins.tick_params(labelsize=7)
    ax[0, 1].set_ylim(-1, 1)
    ax[0, 1].legend(loc="lower left")
    ts = series["time"]
    ax[1, 0].plot(ts * 1e6, series["translational_energy"] / E0, label="translational")
    ax[1, 0].plot(ts * 1e6, series["rotational_energy"] / E0, label="rotational")
    ax[1, 0].plot(ts * 1e6, (series["translational_energy"] + series["rotational_energy"]) / E0, label="total")
    ax[1, 0].axvspan(to[first_touch] * 1e6, to[last_touch] * 1e6, color="0.9")
    ax[1, 0].set_xlabel("time (us)")
    ax[1, 0].set_ylabel("kinetic energy / initial")
    ax[1, 0].set_title("oblique, e = 0.6, mu = 0.4 (grey: contact)")
    ax[1, 0].legend()
    ax[1, 1].semilogy(to * 1e6, np.maximum(dp, 1e-17), label="|p - p0| / sum |m v|")
    ax[1, 1].semilogy(to * 1e6, np.maximum(dL, 1e-17), label="|L - L0| / |L0| (about origin)")
    ax[1, 1].axvspan(to[first_touch] * 1e6, to[last_touch] * 1e6, color="0.9")
    ax[1, 1].set_xlabel("time (us)")
    ax[1, 1].set_ylabel("relative change")
    ax[1, 1].set_title("oblique: momenta")
    ax[1, 1].legend()
    fig.tight_layout()
    common.save_figure_and_summary(
        fig, png, os.path.join(os.path.dirname(os.path.abspath(oblique_dir)), "summary.txt"), lines)


if __name__ == "__main__":
    main()
