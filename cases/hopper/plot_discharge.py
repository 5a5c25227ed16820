#!/usr/bin/env python3
"""Discharged mass against time for a hopper run, its mean rate, and Beverloo's correlation.

usage: plot_discharge.py OUTPUT_DIR [--gate-open 0.25] [--orifice 0.016] [--diameter 0.002]
                         [--density 2500] [--solid-fraction 0.6] [--png FILE]

The mean rate is the slope of a least-squares line through the discharged mass from
0.05 s after the gate opens (the start-up transient) to the end of the run.

Beverloo et al. (Chem. Eng. Sci. 15, 1961) in its area form for a square orifice of side L:
    W = C_A rho_b sqrt(g) (L - k d)^2.5,  C_A = 4 C / pi = 0.74 (C = 0.58), k = 1.5,
with the bulk density rho_b = solid fraction x particle density. The correlation is for flat-
bottomed bins; a converging hopper discharges somewhat faster (Rose & Tanaka 1956).
"""
import argparse
import csv
import math
import os
import sys


def read_series(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    time = [float(r["time"]) for r in rows]
    mass = [float(r["discharged_mass"]) for r in rows]
    return time, mass


def least_squares_slope(xs, ys):
    n = len(xs)
    mean_x, mean_y = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mean_x) ** 2 for x in xs)
    sxy = sum((x - mean_x) * (y - mean_y) for x, y in zip(xs, ys))
    return sxy / sxx


def beverloo_rate(orifice, diameter, density, solid_fraction, g=9.81, c=0.58, k=1.5):
    bulk_density = solid_fraction * density
    return 4.0 * c / math.pi * bulk_density * math.sqrt(g) * (orifice - k * diameter) ** 2.5


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output_dir")
    parser.add_argument("--gate-open", type=float, default=0.25)
    parser.add_argument("--orifice", type=float, default=0.016)
    parser.add_argument("--diameter", type=float, default=0.002)
    parser.add_argument("--density", type=float, default=2500.0)
    parser.add_argument("--solid-fraction", type=float, default=0.6)
    parser.add_argument("--png", default=None)
    args = parser.parse_args()

    series = os.path.join(args.output_dir, "series.csv")
    if not os.path.exists(series):
        sys.exit("error: %s not found (run the scene first)" % series)
    time, mass = read_series(series)
    window = [(t, m) for t, m in zip(time, mass) if t >= args.gate_open + 0.05]
    if len(window) < 3 or window[-1][1] <= 0:
        sys.exit("error: too little discharge after the gate opened to measure a rate")
    rate = least_squares_slope([t for t, _ in window], [m for _, m in window])
    reference = beverloo_rate(args.orifice, args.diameter, args.density, args.solid_fraction)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(time, [1e3 * m for m in mass], label="kdem")
    t0 = window[0][0]
    m0 = window[0][1]
    ax.plot([t0, time[-1]], [1e3 * m0, 1e3 * (m0 + reference * (time[-1] - t0))], "--",
            label="Beverloo slope (%.1f g/s)" % (1e3 * reference))
    ax.axvline(args.gate_open, color="grey", lw=0.8, ls=":", label="gate opens")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("discharged mass (g)")
    ax.set_title("Hopper discharge: mean rate %.1f g/s" % (1e3 * rate))
    ax.legend()
    fig.tight_layout()
    png = args.png or os.path.join(args.output_dir, "discharge.png")
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, png)
    print("mean discharge rate %.2f g/s (from t = %.3f s to %.3f s)" % (1e3 * rate, t0, time[-1]))
    print("Beverloo correlation %.2f g/s (C = 0.58, k = 1.5, bulk density %.0f kg/m^3); ratio %.2f"
          % (1e3 * reference, args.solid_fraction * args.density, rate / reference))
    print("plot: %s" % png)


if __name__ == "__main__":
    main()
