#!/usr/bin/env python3
"""Plots for docs/validation.md from the CSV files the engine tests write when
KDEM_VALIDATION_OUT is set:

    mkdir -p out/validation
    KDEM_VALIDATION_OUT=out/validation build/openmp/bin/kdem_tests_openmp
    /usr/bin/python3 cases/validation/plot_validation.py out/validation docs/img

Hertz impact (sphere on a steel plane, 5 mm radius, 1 m/s): the reference force-time curve is
an independent RK4 integration of m x'' = -k x^1.5 - gamma sqrt(1.5 k m) x^0.25 x', written here.
"""
import csv
import glob
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) for r in rows] for key in rows[0]}


def hertz_reference(e, mass=7800 * 4 / 3 * math.pi * 0.005 ** 3, radius=0.005, youngs=2e11, poisson=0.3,
                    speed=1.0, steps=20000):
    e_star = 1.0 / (2 * (1 - poisson ** 2) / youngs)
    k = 4.0 / 3.0 * e_star * math.sqrt(radius)
    gamma = 0.0 if e == 1 else -2 * math.sqrt(5 / 6) * math.log(e) / math.sqrt(math.log(e) ** 2 + math.pi ** 2)
    x, v, t = 0.0, speed, 0.0
    d_max = (15 * mass * speed ** 2 / (16 * e_star * math.sqrt(radius))) ** 0.4
    h = 3.5 * d_max / speed / steps

    def accel(x, v):
        xp = max(x, 0.0)
        return (-k * xp ** 1.5 - gamma * math.sqrt(1.5 * k * mass) * xp ** 0.25 * v) / mass

    times, forces = [], []
    while True:
        k1x, k1v = v, accel(x, v)
        k2x, k2v = v + 0.5 * h * k1v, accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v)
        k3x, k3v = v + 0.5 * h * k2v, accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v)
        k4x, k4v = v + h * k3v, accel(x + h * k3x, v + h * k3v)
        x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        t += h
        if x <= 0:
            break
        times.append(t)
        forces.append(-mass * accel(x, v))
    return times, forces


def plot_hertz(data_dir, image_dir):
    files = sorted(glob.glob(os.path.join(data_dir, "hertz_sphere_wall_e*.csv")))
    if not files:
        return None
    fig, ax = plt.subplots(figsize=(6, 4))
    for path in files:
        e = int(os.path.basename(path)[len("hertz_sphere_wall_e"):-4]) / 100.0
        d = read(path)
        ref_t, ref_f = hertz_reference(e)
        line, = ax.plot([1e6 * t for t in ref_t], ref_f, lw=3, alpha=0.35)
        ax.plot([1e6 * t for t in d["time"]], d["force"], ".", ms=2, color=line.get_color(),
                label="kdem, e = %.1f" % e)
    ax.set_xlabel("time since first touch (us)")
    ax.set_ylabel("contact force (N)")
    ax.set_title("Sphere on a plane at 1 m/s: kdem (dots) and Hertz ODE (bands)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = os.path.join(image_dir, "validation_hertz.png")
    fig.savefig(out, dpi=120)
    return out


def plot_chung_ooi(data_dir, image_dir):
    files = sorted(glob.glob(os.path.join(data_dir, "chung_ooi_test4_*.csv")))
    if not files:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for path in files:
        name = os.path.basename(path)[len("chung_ooi_test4_"):-4]
        d = read(path)
        x = d["incidence"]
        line, = axes[0].plot(x, d["recoil"], "o", label="kdem, " + name)
        sliding = [(a, b) for a, b in zip(x, d["sliding_recoil"]) if a > 3.5 * 2 * 1.0]
        axes[0].plot([a for a, _ in sliding], [b for _, b in sliding], "-", color=line.get_color(), alpha=0.5,
                     label="Coulomb sliding theory, " + name)
        axes[1].plot(x, d["spin"], "o", color=line.get_color(), label="kdem, " + name)
        axes[1].plot(x, d["sliding_spin"], "-", color=line.get_color(), alpha=0.5, label="sliding theory, " + name)
    axes[0].set_xscale("log")
    axes[0].set_xlabel("normalised incidence  v_t / (mu v_n)")
    axes[0].set_ylabel("normalised recoil  u' / (mu v_n)")
    axes[0].axhline(0, color="grey", lw=0.5)
    axes[0].legend(fontsize=7)
    axes[1].set_xscale("log")
    axes[1].set_xlabel("normalised incidence  v_t / (mu v_n)")
    axes[1].set_ylabel("normalised spin  R w' / (mu v_n)")
    axes[1].legend(fontsize=7)
    fig.suptitle("Chung & Ooi test 5 set-up (v_n = 5 m/s, mu = 0.3, e = 1): oblique impacts on a plane")
    fig.tight_layout()
    out = os.path.join(image_dir, "validation_oblique.png")
    fig.savefig(out, dpi=120)
    return out


def main():
    data_dir, image_dir = sys.argv[1], sys.argv[2]
    os.makedirs(image_dir, exist_ok=True)
    for made in [plot_hertz(data_dir, image_dir), plot_chung_ooi(data_dir, image_dir)]:
        if made:
            print("wrote", made)


if __name__ == "__main__":
    main()
