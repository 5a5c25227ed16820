"""Analyses a packing run (book Sect. 4.3.3, Figs. 4.19-4.20): the energy history (series.csv) and
the final packing (the last frame), and writes result.json and polyhedra_packing_energy.png.

Energies: translational + rotational = kinetic K, gravitational potential P = sum m g z (floor at
z = 0, as the engine reports it), total E = K + P; the plot shows each over the initial total E0
(the book's Fig. 4.20), and K over its peak on a log scale.

Packing fraction: a grid of points (spacing GRID, 2 mm) over the central column, WALL_CLEARANCE
(0.04 m, one equivalent diameter) from the side walls; a point is solid when it
lies in at least one particle's true dilated body (dilated_bodies.py: within r of the core, from
the signed distance on a 0.5 mm grid per shape, interpolated). The solid fraction of each 1 cm
slab gives the profile phi(z); the bed surface h is the highest slab whose fraction is at least
half the bulk value (the median of the slabs between FLOOR_CLEARANCE and h_max / 2). The packing
fraction is the solid fraction of that column between FLOOR_CLEARANCE (0.04 m) above the floor and
SURFACE_CLEARANCE (0.04 m) below h,
with the spread of its four quadrants (standard deviation / 2) as its uncertainty. A cruder
estimate is given beside it: the volume of the particles whose centroids lie in that box over the
box's volume.

The final state is RUN_DIR/checkpoint.h5, or STATE (a checkpoint of the run, when the run was
stopped before its duration: the series is then read up to that checkpoint's time, and the wall
time is the time between the first frame's file and that checkpoint's file). The shapes' surfaces
are taken from the run's first frame.

usage: analyse.py RUN_DIR MESH_DIR RESULTS_DIR [WIDTH] [STATE] [END_RUN_DIR]
  WIDTH: the container's side (default 0.6 m); END_RUN_DIR: a short run restarted from STATE,
  whose run.json gives the engine's counters (narrow-phase failures, largest overlap) there."""
import csv
import json
import math
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import dilated_bodies as db  # noqa: E402
import make_scene as ms  # noqa: E402

GRID = 0.002             # m: spacing of the packing-fraction points
FIELD_SPACING = 0.0005   # m: the shapes' distance grids
WALL_CLEARANCE = 0.04    # m from the side walls (one equivalent diameter)
FLOOR_CLEARANCE = 0.04   # m above the floor
SURFACE_CLEARANCE = 0.04  # m below the bed surface
SLAB = 0.01              # m: slabs of the profile


def read_series(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    return cols


def solid_points(particles, templates, lo, hi, spacing):
    """Boolean grid (z, y, x) of the points lo + spacing (k + 1/2) inside any particle."""
    dims = np.floor((hi - lo) / spacing).astype(int)
    solid = np.zeros((dims[2], dims[1], dims[0]), bool)
    axes = [lo[k] + spacing * (np.arange(dims[k]) + 0.5) for k in range(3)]
    rot = db.rotation_matrices(particles["quaternion"])
    for i, (p, s) in enumerate(zip(particles["position"], particles["shape"])):
        t = templates[int(s)]
        rb = t.bounding_radius
        ranges = []
        for k in range(3):
            a = np.searchsorted(axes[k], p[k] - rb)
            b = np.searchsorted(axes[k], p[k] + rb)
            ranges.append((a, b))
        if any(a >= b for a, b in ranges):
            continue
        (xa, xb), (ya, yb), (za, zb) = ranges
        zz, yy, xx = np.meshgrid(axes[2][za:zb], axes[1][ya:yb], axes[0][xa:xb], indexing="ij")
        pts = np.stack([xx, yy, zz], axis=-1).reshape(-1, 3)
        body = (pts - p) @ rot[i]
        inside = t.inside(body).reshape(zz.shape)
        solid[za:zb, ya:yb, xa:xb] |= inside
    return solid, axes


def main():
    if len(sys.argv) not in (4, 5, 6, 7):
        sys.exit(__doc__)
    end_run = None
    if len(sys.argv) == 7:
        with open(os.path.join(sys.argv[6], "run.json")) as f:
            end_run = json.load(f)
    run_dir, mesh_dir, results = sys.argv[1:4]
    width = float(sys.argv[4]) if len(sys.argv) >= 5 else ms.BOX[0]
    state_path = sys.argv[5] if len(sys.argv) >= 6 else os.path.join(run_dir, "checkpoint.h5")
    os.makedirs(results, exist_ok=True)
    with open(os.path.join(mesh_dir, "calibration.json")) as f:
        calibration = json.load(f)
    scales = {n: s["scale"] for n, s in calibration["shapes"].items()}
    particles = db.read_state(state_path)
    final_time = particles["time"]
    run_path = os.path.join(run_dir, "run.json")
    run = {}
    if os.path.exists(run_path):
        with open(run_path) as f:
            run = json.load(f)
    stopped = abs(run.get("simulated_time", -1) - final_time) > 1e-9
    if stopped:  # the run was stopped at (or after) this checkpoint
        first_vtu = db.first_frame(run_dir)[0]
        run = {"steps": particles["step"], "threads": 1,
               "wall_seconds": os.path.getmtime(state_path) - os.path.getmtime(first_vtu),
               "extra": {"time_step": final_time / particles["step"]}}

    # Energies.
    s = read_series(os.path.join(run_dir, "series.csv"))
    upto = s["time"] <= final_time + 1e-9
    s = {k: v[upto] for k, v in s.items()}
    t = s["time"]
    kinetic = s["translational_energy"] + s["rotational_energy"]
    potential = s["potential_energy"]
    total = kinetic + potential
    e0 = total[0]
    k_peak_index = int(np.argmax(kinetic))
    k_peak = float(kinetic[k_peak_index])
    rises = np.diff(total)
    settle = np.nonzero(kinetic < 1e-3 * k_peak)[0]
    settle = settle[settle > k_peak_index]
    settled_time = float(t[settle[0]]) if len(settle) else None

    # Final state: the checkpoint; the shapes' surfaces from the first frame.
    source = particles["source"]
    names = particles["source_names"]
    counts = {n: int((source == k).sum()) for k, n in enumerate(names)}
    vtu, vtp, _ = db.first_frame(run_dir)
    templates = db.body_templates(db.read_particles(vtu), db.read_surfaces(vtp), mesh_dir, scales,
                                  ms.MESH_SHAPES, ms.DILATION)
    shape_checks = {}
    for shape_id, tpl in templates.items():
        tpl.build_field(FIELD_SPACING)
        volume = calibration["shapes"][tpl.name]["volume_m3"]
        shape_checks[tpl.name] = {"engine_volume_m3": volume, "grid_volume_m3": tpl.grid_volume,
                                  "grid_over_engine": tpl.grid_volume / volume,
                                  "bounding_radius_m": tpl.bounding_radius,
                                  "core_fit_residual_m": (None if math.isnan(tpl.fit_residual)
                                                          else tpl.fit_residual)}
        print(f"{tpl.name}: grid volume / engine volume = {tpl.grid_volume / volume:.4f}")

    hx = width / 2 - WALL_CLEARANCE
    top = float((particles["position"][:, 2] + particles["radius"]).max())
    lo = np.array([-hx, -hx, 0.0])
    hi = np.array([hx, hx, SLAB * math.ceil(top / SLAB)])
    solid, axes = solid_points(particles, templates, lo, hi, GRID)
    per_slab = int(round(SLAB / GRID))
    nz = solid.shape[0] // per_slab
    profile = solid[:nz * per_slab].reshape(nz, per_slab, -1).mean(axis=(1, 2))
    slab_z = SLAB * (np.arange(nz) + 0.5)
    occupied = np.nonzero(profile > 0)[0]
    h_max = SLAB * (occupied[-1] + 1)
    bulk_slabs = (slab_z >= FLOOR_CLEARANCE) & (slab_z <= 0.5 * h_max)
    if bulk_slabs.sum() < 2:
        bulk_slabs = (slab_z >= 0.02) & (slab_z <= 0.5 * h_max)
    bulk = float(np.median(profile[bulk_slabs]))
    surface = float(SLAB * (np.nonzero(profile >= 0.5 * bulk)[0][-1] + 1))
    z_lo, z_hi = FLOOR_CLEARANCE, surface - SURFACE_CLEARANCE
    if z_hi - z_lo < 0.02:
        sys.exit(f"the bed (surface at {surface:.3f} m) is too low for the measuring box")
    zsel = (axes[2] >= z_lo) & (axes[2] <= z_hi)
    box = solid[zsel]
    phi = float(box.mean())
    half_y, half_x = box.shape[1] // 2, box.shape[2] // 2
    quadrants = [box[:, :half_y, :half_x].mean(), box[:, :half_y, half_x:].mean(),
                 box[:, half_y:, :half_x].mean(), box[:, half_y:, half_x:].mean()]
    phi_err = float(np.std(quadrants) / 2)
    box_volume = (2 * hx) ** 2 * (z_hi - z_lo)
    pos = particles["position"]
    in_box = ((np.abs(pos[:, 0]) <= hx) & (np.abs(pos[:, 1]) <= hx)
              & (pos[:, 2] >= z_lo) & (pos[:, 2] <= z_hi))
    volume_each = np.array([calibration["shapes"][templates[int(k)].name]["volume_m3"]
                            for k in particles["shape"]])
    phi_centroids = float(volume_each[in_box].sum() / box_volume)

    result = {
        "case": "book Sect. 4.3.3, Figs. 4.19-4.20: packing of mixed dilated polyhedra",
        "particles": int(len(source)),
        "particles_per_shape": counts,
        "container_m": [width, width, ms.BOX[2]],
        "equivalent_diameter_m": ms.EQUIVALENT_DIAMETER,
        "dilation_radius_m": ms.DILATION,
        "shapes": {n: {"scale": calibration["shapes"][n]["scale"],
                       "engine_volume_m3": calibration["shapes"][n]["volume_m3"],
                       "equivalent_diameter_m": calibration["shapes"][n]["equivalent_diameter_m"],
                       "bounding_radius_m": calibration["shapes"][n]["bounding_radius_m"]}
                   for n in ms.SHAPES},
        "time_step_s": run.get("extra", {}).get("time_step"),
        "simulated_time_s": final_time,
        "run_stopped_at_this_checkpoint": stopped,
        "state": os.path.relpath(state_path, run_dir),
        "steps": run.get("steps"),
        "wall_time_s": run.get("wall_seconds"),
        "wall_time_source": ("file times: first frame to this checkpoint (placement not counted)"
                             if stopped else "run.json"),
        "threads": run.get("threads"),
        "energy": {
            "initial_total_J": float(e0),
            "peak_kinetic_J": k_peak, "peak_kinetic_time_s": float(t[k_peak_index]),
            "peak_kinetic_over_initial_total": k_peak / e0,
            "final_kinetic_J": float(kinetic[-1]),
            "final_kinetic_over_peak_kinetic": float(kinetic[-1] / k_peak),
            "final_potential_over_initial_total": float(potential[-1] / e0),
            "final_total_over_initial_total": float(total[-1] / e0),
            "final_total_minus_potential_over_initial_total": float((total[-1] - potential[-1]) / e0),
            "largest_rise_of_total_between_rows_over_initial_total": float(max(rises.max(), 0) / e0),
            "rows_where_total_rises": int((rises > 0).sum()), "rows": int(len(t)),
            "time_kinetic_below_1e-3_of_peak_s": settled_time},
        "packing": {
            "definition": (f"solid fraction of the box |x|, |y| <= {hx:.2f} m, {z_lo:.2f} m <= z <= "
                           f"{z_hi:.3f} m (bed surface {surface:.3f} m less {SURFACE_CLEARANCE} m): "
                           f"grid points {GRID * 1e3:g} mm apart inside any particle's true dilated "
                           "body; uncertainty = std of the four quadrants / 2"),
            "packing_fraction": phi, "packing_fraction_uncertainty": phi_err,
            "packing_fraction_centroids_in_box": phi_centroids,
            "bed_surface_m": surface, "bulk_fraction_of_the_profile": bulk,
            "profile_z_m": [round(float(z), 4) for z in slab_z],
            "profile_fraction": [round(float(p), 4) for p in profile]},
        "shape_grid_checks": shape_checks,
        "final_pair_contacts": int(s["pair_contacts"][-1]) if "pair_contacts" in s else None,
        "lost_particles": run.get("extra", {}).get("lost_count"),
        "largest_overlap_ratio": run.get("largest_overlap_ratio"),
        "largest_overlap_ratio_in_series": float(s["largest_overlap_ratio"].max()),
        "largest_overlap_ratio_time_s": float(t[int(np.argmax(s["largest_overlap_ratio"]))]),
        "energy_drift": run.get("energy_drift"),
        "narrow_phase_failures": run.get("narrow_phase_failures"),
    }
    if len(source) != ms.COUNT:
        result["reduced"] = (f"{len(source)} particles instead of the book's {ms.COUNT}, for the "
                             "run time on one thread (README.md)")
    if end_run is not None:
        result["end_segment"] = {k: end_run.get(k) for k in (
            "git_hash", "steps", "simulated_time", "narrow_phase_failures", "largest_overlap_ratio",
            "wall_seconds", "particle_steps_per_second")}
        result["end_segment"]["narrow_phase_fallbacks"] = end_run["extra"].get("narrow_phase_fallbacks")
        result["end_segment"]["pair_contacts"] = end_run["extra"].get("pair_contacts")
    ms.write(os.path.join(results, "result.json"), json.dumps(result, indent=2) + "\n")

    fig, axes2 = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes2[0]
    ax.plot(t, kinetic / e0, label="kinetic", color="C3")
    ax.plot(t, potential / e0, label="potential", color="C0")
    ax.plot(t, total / e0, label="total", color="k", ls="--")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy / initial total energy")
    ax.set_title(f"{len(source)} mixed dilated polyhedra: energies (cf. book Fig. 4.20)", fontsize=9)
    ax.legend()
    ax.set_ylim(bottom=0)
    ax = axes2[1]
    ax.semilogy(t[1:], kinetic[1:] / k_peak, color="C3")
    ax.set_ylim(max(1e-7, 0.3 * float((kinetic[1:] / k_peak).min())), 2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("kinetic energy / its peak")
    ax.set_title(f"final / peak = {kinetic[-1] / k_peak:.1e}", fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    png = os.path.join(results, "polyhedra_packing_energy.png")
    fig.savefig(png + ".tmp.png", dpi=120)
    os.replace(png + ".tmp.png", png)
    print(json.dumps({k: result[k] for k in ("particles", "steps", "wall_time_s")}),
          json.dumps(result["energy"], indent=1), json.dumps(
              {k: v for k, v in result["packing"].items() if not k.startswith("profile")}, indent=1))


if __name__ == "__main__":
    main()
