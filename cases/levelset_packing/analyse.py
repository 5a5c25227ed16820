"""Analyses a level-set packing run (book Sect. 5.4.2): the energy history (series.csv) and the final
packing (the run's checkpoint), and writes result.json and levelset_packing.png.

Energies as in cases/polyhedra_packing/analyse.py: kinetic K (translational + rotational),
gravitational potential P = sum m g z, total E = K + P, each over the initial total E0; checks:
the total never rises by more than 1e-4 E0 between series rows, the run ends at rest (K below
1e-4 of its peak) with E = P.

Packing fraction: each shape's body is the surface the engine draws for it (the grid's zero level
set, the surface its contacts see, decimated to at most 2000 triangles), taken from the run's
first frame in the body frame; its signed distance on a 1 mm grid (dilated_bodies.Template with
no dilation, signed by winding numbers; its volume against the engine's is in
shape_grid_checks). Points 2 mm apart over the central column, one equivalent diameter
(0.04 m) from the side walls, are solid when inside any body; the packing fraction is the solid
fraction of that column from 0.04 m above the floor to 0.04 m below the bed surface (the highest
1 cm slab at least half as full as the bulk), with the spread of its four quadrants (standard
deviation / 2) as its uncertainty, and the volume of the bodies whose centroids lie in that box
over its volume beside it.

usage: analyse.py RUN_DIR SETUP_DIR RESULTS_DIR WIDTH"""
import importlib.util
import json
import math
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
POLYHEDRA = os.path.join(HERE, "..", "polyhedra_packing")
sys.path.insert(0, POLYHEDRA)
sys.path.insert(0, HERE)
import dilated_bodies as db  # noqa: E402
import levelset_scene as ls  # noqa: E402


def polyhedra_analysis():
    """cases/polyhedra_packing/analyse.py (its series reader and solid-point sampler)."""
    spec = importlib.util.spec_from_file_location("polyhedra_analyse",
                                                  os.path.join(POLYHEDRA, "analyse.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


pa = polyhedra_analysis()
FIELD_SPACING = 0.001      # m: the bodies' distance grids
GRID = pa.GRID             # m: the packing-fraction points
CLEARANCE = 0.04           # m from the side walls, above the floor, below the surface
SLAB = pa.SLAB             # m
TOTAL_RISE_LIMIT = 1e-4    # of E0, between two series rows
REST_LIMIT = 1e-4          # final K over peak K


def drawn_templates(particles, surfaces):
    """A Template per shape id: the body-frame drawn surface of its first particle, no dilation."""
    points, triangles, point_ids = surfaces
    rot = db.rotation_matrices(particles["quaternion"])
    templates = {}
    for shape_id in sorted(set(particles["shape"].tolist())):
        i = int(np.nonzero(particles["shape"] == shape_id)[0][0])
        name = particles["source_names"][int(particles["source"][i])]
        mine = np.nonzero(point_ids == particles["id"][i])[0]
        start, count = int(mine[0]), len(mine)
        body = (points[start:start + count] - particles["position"][i]) @ rot[i]
        faces = triangles[(triangles[:, 0] >= start) & (triangles[:, 0] < start + count)] - start
        templates[shape_id] = db.Template(name, body, faces, 0.0, float("nan"))
    return templates


def packing(particles, templates, calibration, width):
    hx = width / 2 - CLEARANCE
    top = float((particles["position"][:, 2] + particles["radius"]).max())
    lo = np.array([-hx, -hx, 0.0])
    hi = np.array([hx, hx, SLAB * math.ceil(top / SLAB)])
    solid, axes = pa.solid_points(particles, templates, lo, hi, GRID)
    per_slab = int(round(SLAB / GRID))
    nz = solid.shape[0] // per_slab
    profile = solid[:nz * per_slab].reshape(nz, per_slab, -1).mean(axis=(1, 2))
    slab_z = SLAB * (np.arange(nz) + 0.5)
    h_max = SLAB * (np.nonzero(profile > 0)[0][-1] + 1)
    bulk = float(np.median(profile[(slab_z >= CLEARANCE) & (slab_z <= max(0.5 * h_max,
                                                                          CLEARANCE + SLAB))]))
    surface = float(SLAB * (np.nonzero(profile >= 0.5 * bulk)[0][-1] + 1))
    z_lo, z_hi = CLEARANCE, surface - CLEARANCE
    if z_hi - z_lo < 0.02:
        sys.exit(f"the bed (surface at {surface:.3f} m) is too low for the measuring box")
    box = solid[(axes[2] >= z_lo) & (axes[2] <= z_hi)]
    hy, hxi = box.shape[1] // 2, box.shape[2] // 2
    quadrants = [box[:, :hy, :hxi].mean(), box[:, :hy, hxi:].mean(), box[:, hy:, :hxi].mean(),
                 box[:, hy:, hxi:].mean()]
    pos = particles["position"]
    in_box = ((np.abs(pos[:, 0]) <= hx) & (np.abs(pos[:, 1]) <= hx) & (pos[:, 2] >= z_lo)
              & (pos[:, 2] <= z_hi))
    volume_each = np.array([calibration["shapes"][templates[int(k)].name]["volume_m3"]
                            for k in particles["shape"]])
    return {
        "definition": (f"solid fraction of the box |x|, |y| <= {hx:.2f} m, {z_lo:.2f} m <= z <= "
                       f"{z_hi:.3f} m (bed surface {surface:.3f} m less {CLEARANCE} m): grid "
                       f"points {GRID * 1e3:g} mm apart inside any body's drawn zero level set; "
                       "uncertainty = std of the four quadrants / 2"),
        "packing_fraction": float(box.mean()),
        "packing_fraction_uncertainty": float(np.std(quadrants) / 2),
        "packing_fraction_centroids_in_box":
            float(volume_each[in_box].sum() / ((2 * hx) ** 2 * (z_hi - z_lo))),
        "bed_surface_m": surface, "bulk_fraction_of_the_profile": bulk,
        "profile_z_m": [round(float(z), 4) for z in slab_z],
        "profile_fraction": [round(float(p), 4) for p in profile]}


def energies(s):
    t = s["time"]
    kinetic = s["translational_energy"] + s["rotational_energy"]
    potential = s["potential_energy"]
    total = kinetic + potential
    e0 = float(total[0])
    peak = int(np.argmax(kinetic))
    rises = np.diff(total)
    return t, kinetic, potential, total, {
        "initial_total_J": e0, "peak_kinetic_J": float(kinetic[peak]),
        "peak_kinetic_time_s": float(t[peak]),
        "final_kinetic_over_peak_kinetic": float(kinetic[-1] / kinetic[peak]),
        "final_potential_over_initial_total": float(potential[-1] / e0),
        "final_total_over_initial_total": float(total[-1] / e0),
        "largest_rise_of_total_between_rows_over_initial_total": float(max(rises.max(), 0) / e0),
        "rows_where_total_rises": int((rises > 0).sum()), "rows": int(len(t))}


def plot(path, t, kinetic, potential, total, count):
    e0, k_peak = total[0], kinetic.max()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes[0]
    ax.plot(t, kinetic / e0, label="kinetic", color="C3")
    ax.plot(t, potential / e0, label="potential", color="C0")
    ax.plot(t, total / e0, label="total", color="k", ls="--")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy / initial total energy")
    ax.set_title(f"{count} mixed level-set bodies (4 of 9 shapes concave): energies", fontsize=9)
    ax.legend()
    ax.set_ylim(bottom=0)
    ax = axes[1]
    ax.semilogy(t[1:], kinetic[1:] / k_peak, color="C3")
    ax.set_ylim(max(1e-8, 0.3 * float((kinetic[1:] / k_peak).min())), 2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("kinetic energy / its peak")
    ax.set_title(f"final / peak = {kinetic[-1] / k_peak:.1e}", fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=120)
    os.replace(path + ".tmp.png", path)


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    run_dir, setup, results = sys.argv[1:4]
    width = float(sys.argv[4])
    os.makedirs(results, exist_ok=True)
    with open(os.path.join(setup, "calibration.json")) as f:
        calibration = json.load(f)
    with open(os.path.join(run_dir, "run.json")) as f:
        run = json.load(f)
    particles = db.read_state(os.path.join(run_dir, "checkpoint.h5"))
    s = pa.read_series(os.path.join(run_dir, "series.csv"))
    t, kinetic, potential, total, energy = energies(s)
    vtu, vtp, _ = db.first_frame(run_dir)
    templates = drawn_templates(db.read_particles(vtu), db.read_surfaces(vtp))
    shape_checks = {}
    for tpl in templates.values():
        tpl.build_field(FIELD_SPACING)
        volume = calibration["shapes"][tpl.name]["volume_m3"]
        shape_checks[tpl.name] = {"engine_volume_m3": volume, "grid_volume_m3": tpl.grid_volume,
                                  "grid_over_engine": tpl.grid_volume / volume}
        print(f"{tpl.name}: drawn body's grid volume / engine volume = "
              f"{tpl.grid_volume / volume:.4f}")
    source = particles["source"]
    checks = {
        "total_never_rises_by_more_than_1e-4": energy[
            "largest_rise_of_total_between_rows_over_initial_total"] <= TOTAL_RISE_LIMIT,
        "at_rest_kinetic_below_1e-4_of_peak": energy["final_kinetic_over_peak_kinetic"] < REST_LIMIT,
        "none_lost": run.get("extra", {}).get("lost_count", 0) == 0,
        "no_narrow_phase_failures": run.get("narrow_phase_failures", 0) == 0,
    }
    result = {
        "case": "book Sect. 5.4.2: packing of mixed level-set bodies, concave ones included",
        "particles": int(len(source)),
        "particles_per_shape": {n: int((source == k).sum())
                                for k, n in enumerate(particles["source_names"])},
        "concave_shapes": ls.CONCAVE,
        "container_m": [width, width],
        "equivalent_diameter_m": ls.pms.EQUIVALENT_DIAMETER,
        "grid_spacing_m": ls.GRID_SPACING, "surface_points_per_body": ls.POINT_COUNT,
        "shapes": calibration["shapes"],
        "time_step_s": run.get("extra", {}).get("time_step"),
        "simulated_time_s": run.get("simulated_time"), "steps": run.get("steps"),
        "wall_time_s": run.get("wall_seconds"), "threads": run.get("threads"),
        "git_hash": run.get("git_hash"),
        "energy": energy,
        "packing": packing(particles, templates, calibration, width),
        "shape_grid_checks": shape_checks,
        "final_pair_contacts": int(s["pair_contacts"][-1]) if "pair_contacts" in s else None,
        "largest_overlap_ratio": run.get("largest_overlap_ratio"),
        "narrow_phase_failures": run.get("narrow_phase_failures"),
        "checks": checks,
        "passed": all(checks.values()),
    }
    ls.pms.write(os.path.join(results, "result.json"), json.dumps(result, indent=2) + "\n")
    plot(os.path.join(results, "levelset_packing.png"), t, kinetic, potential, total,
         len(source))
    print(json.dumps({k: result[k] for k in ("particles", "steps", "wall_time_s", "checks")}),
          json.dumps({k: v for k, v in result["packing"].items() if not k.startswith("profile")},
                     indent=1))
    if not result["passed"]:
        sys.exit("a check failed: " + ", ".join(k for k, v in checks.items() if not v))


if __name__ == "__main__":
    main()
