#!/usr/bin/python3
"""Solid fraction of poured, settled packings of prolate spheroids, measured in a central
sub-volume away from the walls, against published random-packing values.

usage: plot_packing.py PNG ALPHA:RUN_DIR [ALPHA:RUN_DIR ...]

The solid fraction is measured on a regular grid of points (spacing 0.04 mm) filling the
sub-volume: a point is solid when it lies inside at least one spheroid (so contact overlaps are
not counted twice). The sub-volume keeps 4 mm (2 equivalent diameters, 2.5 long semi-axes at
alpha = 2) from the side walls and the floor and 4 mm below the bed surface, where the
surface is where the solid fraction of 0.25 mm thick slabs of the central column first drops
below half its value at z = 4-8 mm. The quoted uncertainty is the standard deviation of the four
quadrants (in x, y) of the sub-volume divided by 2.
"""
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
import make_scenes as setup  # noqa: E402

MARGIN = 4e-3
SPACING = 4e-5

# Frictionless jammed packings of hard spheroids (Donev et al., Science 303 (2004) 990, Fig. 2),
# values read approximately (+-0.01) from the published curve: spheres 0.64, a cusp-like rise,
# a maximum near 0.71 around alpha = 1.5, a slow decrease beyond.
DONEV_APPROX = {1.0: 0.64, 1.25: 0.70, 1.5: 0.71, 2.0: 0.70}


def solid_mask(centres, rotations, axes, lo, hi):
    """Boolean grid of points in [lo, hi) (spacing SPACING) lying inside any spheroid."""
    shape = np.ceil((hi - lo) / SPACING).astype(int)
    mask = np.zeros(shape, bool)
    reach = max(axes)
    grid = [lo[k] + (np.arange(shape[k]) + 0.5) * SPACING for k in range(3)]
    inv_axes2 = 1.0 / np.asarray(axes) ** 2
    for x, R in zip(centres, rotations):
        if np.any(x + reach < lo) or np.any(x - reach > hi):
            continue
        idx = []
        for k in range(3):
            i0 = max(0, int(np.floor((x[k] - reach - lo[k]) / SPACING)))
            i1 = min(shape[k], int(np.ceil((x[k] + reach - lo[k]) / SPACING)) + 1)
            idx.append((i0, i1))
        if any(i1 <= i0 for i0, i1 in idx):
            continue
        gx = grid[0][idx[0][0]:idx[0][1]] - x[0]
        gy = grid[1][idx[1][0]:idx[1][1]] - x[1]
        gz = grid[2][idx[2][0]:idx[2][1]] - x[2]
        # body coordinates u_j = sum_i R_ij d_i
        P = np.stack(np.meshgrid(gx, gy, gz, indexing="ij"), axis=-1)
        U = P @ R
        inside = (U ** 2 @ inv_axes2) <= 1.0
        mask[idx[0][0]:idx[0][1], idx[1][0]:idx[1][1], idx[2][0]:idx[2][1]] |= inside
    return mask


def measure(alpha, run_dir):
    s = common.read_checkpoint(os.path.join(run_dir, "checkpoint.h5"))
    axes = setup.semi_axes(alpha)
    centres = s["position"]
    rotations = [common.rotation_matrix(q) for q in s["orientation"]]
    h = setup.HALF_WIDTH
    z_max = centres[:, 2].max() + max(axes)
    lo = np.array([-h + MARGIN, -h + MARGIN, 0.0])
    hi = np.array([h - MARGIN, h - MARGIN, z_max])
    mask = solid_mask(centres, rotations, axes, lo, hi)
    z = lo[2] + (np.arange(mask.shape[2]) + 0.5) * SPACING
    slab = int(round(2.5e-4 / SPACING))
    nslab = mask.shape[2] // slab
    profile = mask[:, :, :nslab * slab].reshape(mask.shape[0], mask.shape[1], nslab, slab).mean(axis=(0, 1, 3))
    zs = lo[2] + (np.arange(nslab) + 0.5) * slab * SPACING
    plateau = profile[(zs > MARGIN) & (zs < 2 * MARGIN)].mean()
    above = np.where((zs > 2 * MARGIN) & (profile < 0.5 * plateau))[0]
    surface = zs[above[0]] if len(above) else zs[-1]
    keep = (z > MARGIN) & (z < surface - MARGIN)
    core = mask[:, :, keep]
    phi = core.mean()
    nx, ny = core.shape[0] // 2, core.shape[1] // 2
    quads = [core[:nx, :ny].mean(), core[nx:, :ny].mean(), core[:nx, ny:].mean(), core[nx:, ny:].mean()]
    # orientation order: <P2(cos theta)> of the long axes against vertical
    long_axes = np.array([R[:, 2] for R in rotations])
    p2 = np.mean(1.5 * long_axes[:, 2] ** 2 - 0.5)
    volume = 4.0 / 3.0 * np.pi * axes[0] * axes[1] * axes[2]
    bulk = len(centres) * volume / ((2 * h) ** 2 * surface)
    overlaps = s["pairs"].get("overlap", np.zeros((0, 1)))[:, 0]
    touching = overlaps[overlaps > 0]
    return dict(phi=phi, err=np.std(quads) / 2, surface=surface, zs=zs, profile=profile,
                z_range=(MARGIN, surface - MARGIN), p2=p2, bulk=bulk, count=len(centres),
                contacts=2.0 * len(touching) / len(centres),
                mean_overlap=(touching.mean() / setup.R_EQ) if len(touching) else 0.0)


def main():
    png = sys.argv[1]
    results = {}
    lines = []
    say = lambda text: (print(text), lines.append(text))
    for item in sys.argv[2:]:
        alpha, run_dir = item.split(":", 1)
        alpha = float(alpha)
        r = measure(alpha, run_dir)
        series = common.read_series(run_dir)
        ke = series["translational_energy"][-1] + series["rotational_energy"][-1]
        results[alpha] = r
        say("alpha %.2f: %d particles, bed surface %.2f mm, core z = %.1f-%.1f mm, solid fraction %.4f +- %.4f "
            "(whole bed, volume / (box area x surface height): %.3f); <P2> of long axes vs vertical %.3f; "
            "particle contacts per particle %.2f, mean overlap %.2e r_eq; "
            "final kinetic energy %.2e J (potential %.2e J); Donev et al. 2004 approx. %.2f"
            % (alpha, r["count"], r["surface"] * 1e3, r["z_range"][0] * 1e3, r["z_range"][1] * 1e3, r["phi"],
               r["err"], r["bulk"], r["p2"], r["contacts"], r["mean_overlap"], ke, series["potential_energy"][-1], DONEV_APPROX.get(alpha, np.nan)))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    al = sorted(results)
    ax[0].errorbar(al, [results[a]["phi"] for a in al], yerr=[results[a]["err"] for a in al], fmt="o",
                   label="kdem: poured, frictionless, settled (core)")
    ax[0].plot(sorted(DONEV_APPROX), [DONEV_APPROX[a] for a in sorted(DONEV_APPROX)], "s--", color="0.4",
               mfc="none", label="Donev et al. 2004, jammed frictionless (approx.)")
    ax[0].axhspan(0.68, 0.74, color="0.92", label="dense random ellipsoids, 0.68-0.74")
    ax[0].set_xlabel("aspect ratio c/a of prolate spheroids")
    ax[0].set_ylabel("solid fraction")
    ax[0].set_ylim(0.55, 0.78)
    ax[0].legend(fontsize=8, loc="lower right")
    for a in al:
        r = results[a]
        ax[1].plot(r["profile"], r["zs"] * 1e3, label="alpha = %g" % a)
        ax[1].axhline(r["z_range"][1] * 1e3, color=ax[1].lines[-1].get_color(), lw=0.5, ls=":")
    ax[1].axhline(MARGIN * 1e3, color="k", lw=0.5, ls=":")
    ax[1].set_xlabel("solid fraction of 0.25 mm slabs (central column)")
    ax[1].set_ylabel("height (mm); dotted: core limits")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    out = os.path.dirname(os.path.abspath(sys.argv[2].split(":", 1)[1]))
    common.save_figure_and_summary(fig, png, os.path.join(out, "summary.txt"), lines)


if __name__ == "__main__":
    main()
