#!/usr/bin/python3
"""Free rotation of an asymmetric superquadric about its intermediate axis: energy and |L| over
time, body-frame angular velocity with the periodic flips, and the flip times against an
independent RK4 integration of Euler's equations.

usage: plot_free_rotation.py RUN_DIR PNG

Euler's equations in the body (principal) frame, torque-free:
    I1 w1' = (I2 - I3) w2 w3,  I2 w2' = (I3 - I1) w3 w1,  I3 w3' = (I1 - I2) w1 w2,
integrated by classical Runge-Kutta with step 1e-4 s from the run's initial state. A flip is a
change of sign of the body-frame component w2 (linear interpolation between samples).
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import common  # noqa: E402

A, B, C, N1, N2, DENSITY = 0.01, 0.006, 0.003, 4.0, 4.0, 7800.0


def euler_rk4(inertia, w0, horizon, h=1e-4):
    I1, I2, I3 = inertia

    def f(w):
        return np.array([(I2 - I3) * w[1] * w[2] / I1, (I3 - I1) * w[2] * w[0] / I2,
                         (I1 - I2) * w[0] * w[1] / I3])
    steps = int(round(horizon / h))
    out = np.empty((steps + 1, 3))
    w = np.array(w0, float)
    out[0] = w
    for n in range(steps):
        k1 = f(w)
        k2 = f(w + 0.5 * h * k1)
        k3 = f(w + 0.5 * h * k2)
        k4 = f(w + h * k3)
        w = w + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out[n + 1] = w
    return np.arange(steps + 1) * h, out


def sign_changes(t, y):
    times = []
    for n in range(len(y) - 1):
        if (y[n] > 0) != (y[n + 1] > 0):
            times.append(t[n] + (t[n + 1] - t[n]) * y[n] / (y[n] - y[n + 1]))
    return np.array(times)


def main():
    run_dir, png = sys.argv[1:3]
    states = common.read_checkpoints(run_dir)
    series = common.read_series(run_dir)
    inertia = states[0]["inertia"][0]
    closed = common.superquadric_inertia(A, B, C, N1, N2, DENSITY)
    t = np.array([s["time"] for s in states])
    wb = np.array([common.body_angular_velocity(s, 0) for s in states])
    L = np.array([np.linalg.norm(common.momenta(s)[1]) for s in states])
    E = np.array([common.kinetic_energy(s)[1][0] for s in states])
    # the first checkpoint is written after the first interval, not at t = 0
    tr, wr = euler_rk4(inertia, wb[0], t[-1] - t[0])
    tr = tr + t[0]
    flips_kdem = sign_changes(t, wb[:, 1])
    flips_ref = sign_changes(tr, wr[:, 1])
    lines = []
    say = lambda text: (print(text), lines.append(text))
    say("inertia (checkpoint) %s kg m^2, closed form %s" % (np.array2string(inertia, precision=6),
                                                             np.array2string(closed, precision=6)))
    say("energy: largest relative deviation %.2e (checkpoints), %.2e (series.csv); |L|: %.2e"
        % (np.max(np.abs(E / E[0] - 1)),
           np.max(np.abs(series["rotational_energy"] / series["rotational_energy"][0] - 1)),
           np.max(np.abs(L / L[0] - 1))))
    say("flip times kdem      (s): %s" % np.array2string(flips_kdem, precision=4))
    say("flip times Euler RK4 (s): %s" % np.array2string(flips_ref, precision=4))
    if len(flips_kdem) == len(flips_ref):
        say("largest difference %.2e s (flip period %.3f s)" %
            (np.max(np.abs(flips_kdem - flips_ref)), np.mean(np.diff(flips_ref)) if len(flips_ref) > 1 else np.nan))
    else:
        say("different numbers of flips: %d (kdem) vs %d (reference)" % (len(flips_kdem), len(flips_ref)))
    # body-frame omega of kdem against the reference at the checkpoint times
    ref_at = np.array([np.interp(t, tr, wr[:, k]) for k in range(3)]).T
    say("largest |w_kdem - w_ref| in the body frame: %.2e rad/s (|w| = %.1f rad/s)"
        % (np.max(np.linalg.norm(wb - ref_at, axis=1)), np.linalg.norm(wb[0])))

    fig, ax = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for k, name in enumerate(("x (smallest I)", "y (intermediate I)", "z (largest I)")):
        ax[0].plot(tr, wr[:, k], color="C%d" % k, lw=0.8, label="Euler RK4, " + name)
        ax[0].plot(t, wb[:, k], "o", color="C%d" % k, ms=2.5, label="kdem, " + name)
    for f in flips_ref:
        ax[0].axvline(f, color="0.7", lw=0.5)
    ax[0].set_ylabel("body-frame angular velocity (rad/s)")
    ax[0].set_title("a, b, c = 10, 6, 3 mm, n1 = n2 = 4: spin about the intermediate axis (grey: reference flips)")
    ax[0].legend(fontsize=7, ncol=3, loc="lower left")
    ax[1].semilogy(series["time"], np.maximum(np.abs(series["rotational_energy"] / series["rotational_energy"][0] - 1), 1e-17),
                   label="|E/E0 - 1|")
    ax[1].semilogy(t, np.maximum(np.abs(L / L[0] - 1), 1e-17), label="| |L|/|L0| - 1 |")
    ax[1].set_xlabel("time (s)")
    ax[1].set_ylabel("relative error")
    ax[1].legend()
    fig.tight_layout()
    common.save_figure_and_summary(
        fig, png, os.path.join(os.path.dirname(os.path.abspath(run_dir)), "summary.txt"), lines)


if __name__ == "__main__":
    main()
