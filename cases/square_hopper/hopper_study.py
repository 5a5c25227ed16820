#!/usr/bin/env python3
"""Shared machinery of the book's chapter 3 hopper studies (cases/clump_hopper,
cases/poly_superquadric_hopper): a square bin over a pyramidal hopper with a square orifice
(book Figs. 3.14 and 3.18), a closed gate at the orifice while the bed settles, and an open
container below it (Fig. 3.14: 225 x 225 mm, 75 mm deep) where the discharged particles heap.

A *study* module names its shapes and cases and calls `main(study)`, which offers three
commands (each with `--cases a,b` to take some cases only, `--count N` for another particle
count):

  scenes  OUT_DIR                 write every case's scene (and the hopper meshes)
  run     OUT_DIR [--jobs 2]      write the scenes and run the cases not finished yet, each on
                                  one thread, in restarted segments (see run_case)
  analyse OUT_DIR                 discharged mass against time, rates, angle of repose per
                                  case, the study's claims checked: result.json and a plot in
                                  the study's results/ folder

Discharged mass at time t: the mass of the particles whose centre lies below the orifice plane
(z < 0) in the checkpoint written at t. Mean rate: the mass discharged in the first 0.5 s after
the orifice opened, over 0.5 s; it ranks the shapes, a flow that an arch stops included.
Discharge rate while flowing: least-squares slope of the discharged mass between 10 % and 50 %
of the mass that has left when the run ends (a flat hopper keeps part of the bed; the window
stays in the steady part of every flow). Angle of repose: the heap in the container, from its
upper envelope (highest centre of a particle at rest, slower than 0.05 m/s, in rings of one
diameter about the orifice axis; a stream still falling is not the heap), fitted by a straight
line between 20 % and 80 % of its height above the floor, outwards from the apex to where the
envelope first drops below 20 % (a stray particle standing farther out is not the heap). Where
every centre lies within one diameter of the floor, the particles have spread in one layer and
made no heap: the angle is 0. Where fewer than a quarter of the particles reached the container
(an arch stopped the flow), there is no heap to measure.
"""
import argparse
import glob
import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(HERE, "..", "hopper"))
sys.path.insert(0, os.path.join(HERE, "..", "hopper_shapes"))
from make_hopper_stl import hopper_triangles, write_stl  # noqa: E402
from make_scenes import unit_volume  # noqa: E402
from run_table import cpu_name  # noqa: E402

CONTAINER_HALF = 0.1125  # m, Fig. 3.14: L2 = W2 = 225 mm
CONTAINER_DEPTH = 0.075  # m, H2 = 75 mm
SETTLE_TIME = 0.15  # s, after the last particle has fallen onto the bed
PLACEMENT_FILL = 0.25  # bounding-sphere volume fraction of a batch in the rain region
RAIN_HEIGHT = 0.075  # m, the rain region's height
RAIN_CLEARANCE = 0.06  # m, from the pyramid's top edge to the rain region (at least)
BED_FRACTION = 0.5  # solid fraction a settled bed is taken to have (low: its height generous)
RAIN_SPEED = 1.5  # m/s downwards, so that a batch has left the region when the next comes
RAIN_INTERVAL = 0.05  # s, between batches (a batch moves 87 mm in that time)
SEGMENT_TIME = 0.2  # s of a run segment
REST_TIME = 0.2  # s: see at_rest
REST_ENERGY = 1e-3

MATERIAL = {  # the book gives none for these studies (see the studies' README)
    "density": 2500, "youngs_modulus": 4.0e7, "poisson_ratio": 0.3, "restitution": 0.5,
    "friction": 0.5, "rolling_friction": 0.0}


def sphere_volume(diameter):
    return math.pi * diameter ** 3 / 6.0


def superquadric_volume(half_axes, blockiness):
    a, b, c = half_axes
    return unit_volume(*blockiness) * a * b * c


def poly_superquadric_volume(plus, minus, blockiness):
    # Each octant is an eighth of the superquadric with that octant's semi-axes, so the sum
    # over octants factorises.
    product = 1.0
    for p, m in zip(plus, minus):
        product *= p + m
    return unit_volume(*blockiness) * product / 8.0


def fmt(values):
    return "[" + ", ".join("%.9g" % v for v in values) + "]"


class Hopper:
    """The square hopper of one case: upper bin half side, orifice half side, wall angle
    against the horizontal (degrees) and bin height above the pyramid."""

    def __init__(self, top_half, orifice_half, angle_degrees, bin_height):
        self.top_half, self.orifice_half = top_half, orifice_half
        self.angle_degrees, self.bin_height = angle_degrees, bin_height
        self.triangles, self.cone_top, self.top = hopper_triangles(top_half, orifice_half,
                                                                   angle_degrees, bin_height)

    def mesh_name(self):
        return "hopper_%03.0f_%02.0f_%02.0f.stl" % (2e3 * self.top_half, 2e3 * self.orifice_half,
                                                    self.angle_degrees)

    def write_mesh(self, out_dir):
        path = os.path.join(out_dir, self.mesh_name())
        write_stl(path, self.triangles)
        return path


class Shape:
    """A particle shape: its scene lines (empty for a sphere), its volume-equivalent diameter
    and an upper bound of its bounding radius (for the fill region)."""

    def __init__(self, name, label, lines, bounding_radius, diameter, sphere=False):
        self.name, self.label, self.lines = name, label, lines
        self.bounding_radius, self.diameter, self.sphere = bounding_radius, diameter, sphere


class Case:
    seed_default = 11

    def __init__(self, name, shape, hopper, count, discharge_time, seed=seed_default):
        self.name, self.shape, self.count = name, shape, count
        self.discharge_time, self.seed = discharge_time, seed
        needed = self.rain_clearance(hopper) + RAIN_HEIGHT + 0.005
        if hopper.bin_height < needed:  # a bed too deep for the bin: a taller one
            hopper = Hopper(hopper.top_half, hopper.orifice_half, hopper.angle_degrees, needed)
        self.hopper = hopper

    def rain_clearance(self, hopper):
        """RAIN_CLEARANCE, or more where the settled bed could reach the rain region (the bed
        taken at a solid fraction of BED_FRACTION in the bin, the pyramid left out)."""
        side = 2.0 * hopper.top_half
        bed = self.count * sphere_volume(self.shape.diameter) / (BED_FRACTION * side * side)
        return max(RAIN_CLEARANCE, bed + 0.02)

    def fill_region(self):
        """The box the particles rain from: the bin's width, RAIN_HEIGHT tall, its floor
        rain_clearance above the pyramid's top edge (above the settled bed)."""
        low = self.hopper.cone_top + self.rain_clearance(self.hopper)
        return low, low + RAIN_HEIGHT

    def batch_size(self):
        """Particles per batch: bounding spheres filling PLACEMENT_FILL of the region."""
        side = 2.0 * (self.hopper.top_half - 1e-4)
        bounding_volume = 4.0 / 3.0 * math.pi * self.shape.bounding_radius ** 3
        return max(1, min(self.count, int(PLACEMENT_FILL * side * side * RAIN_HEIGHT
                                          / bounding_volume)))

    def gate_open(self):
        """The last batch's time, its fall onto the bed and SETTLE_TIME."""
        batches = math.ceil(self.count / self.batch_size())
        drop = self.rain_clearance(self.hopper) + RAIN_HEIGHT
        fall = (-RAIN_SPEED + math.sqrt(RAIN_SPEED ** 2 + 2 * 9.81 * drop)) / 9.81
        return (batches - 1) * RAIN_INTERVAL + fall + SETTLE_TIME

    def duration(self):
        return self.gate_open() + self.discharge_time


def scene_text(case, mesh_path, scene_dir, time_step):
    h, shape = case.hopper, case.shape
    low, high = case.fill_region()
    if high + 0.002 > h.top:
        raise SystemExit(f"{case.name}: rain region top {high:.3f} m above the bin ({h.top:.3f} m)")
    half = h.top_half - 1e-4
    gate = case.gate_open()
    lines = [
        f"# {case.count} particles '{shape.name}' in the {2e3 * h.top_half:.0f} mm square hopper, "
        f"{2e3 * h.orifice_half:.0f} mm orifice, walls {h.angle_degrees:g} degrees from the "
        "horizontal.",
        "# Generated by cases/square_hopper/hopper_study.py.",
        f"time_step: {time_step}", f"duration: {case.duration():.4f}", "gravity: [0, 0, -9.81]",
        f"domain: {{min: {fmt([-CONTAINER_HALF - 0.005] * 2 + [-CONTAINER_DEPTH - 0.005])}, "
        f"max: {fmt([CONTAINER_HALF + 0.005] * 2 + [h.top + 0.005])}}}",
        "materials:", "  - name: grain",
    ]
    lines += [f"    {k}: {v}" for k, v in MATERIAL.items()]
    if shape.lines:
        lines += ["shapes:"] + ["  " + line for line in shape.lines]
    lines += ["particles:", f"  - name: {shape.name}", "    material: grain"]
    lines.append(f"    size: {{radius: {shape.diameter / 2:.9g}}}" if shape.sphere
                 else f"    shape: {shape.name}")
    region = f"{{min: {fmt([-half, -half, low])}, max: {fmt([half, half, high])}}}"
    lines += [f"    region: {{box: {region}}}",
              f"    count: {case.count}", f"    seed: {case.seed}",
              f"    velocity: [0, 0, {-RAIN_SPEED}]",
              f"    rate: {case.batch_size() / RAIN_INTERVAL:.6g}",
              f"    interval: {RAIN_INTERVAL}"]
    lines += [
        "walls:", "  - name: hopper", "    material: grain",
        f"    mesh: {{file: {os.path.relpath(mesh_path, scene_dir)}}}",
        "  - name: gate", "    material: grain", "    plane: {point: [0, 0, 0], normal: [0, 0, 1]}",
        f"    active_until: {gate:.4f}",
        "  - name: container", "    material: grain",
        f"    box: {{min: {fmt([-CONTAINER_HALF, -CONTAINER_HALF, -CONTAINER_DEPTH])}, "
        f"max: {fmt([CONTAINER_HALF, CONTAINER_HALF, 0.0])}, open_faces: [zmax]}}",
        "output:", f"  directory: out/{case.name}", f"  frame_interval: {gate:.4f}",
        "  series_interval: 0.01", "  checkpoint_interval: 0.02",
    ]
    return "\n".join(lines) + "\n"


def write_scenes(study, out_dir):
    os.makedirs(out_dir, exist_ok=True)
    meshes = {}
    for case in study.CASES:
        name = case.hopper.mesh_name()
        if name not in meshes:
            meshes[name] = case.hopper.write_mesh(out_dir)
        path = os.path.join(out_dir, case.name + ".yaml")
        with open(path + ".tmp", "w") as f:
            f.write(scene_text(case, meshes[name], out_dir, study.TIME_STEP))
        os.replace(path + ".tmp", path)
    print(f"{len(study.CASES)} scenes in {out_dir}")


# ---- analysis -------------------------------------------------------------------------------

STEADY_WINDOW = (0.1, 0.5)  # of the finally discharged mass: the window of the discharge rate
HEAP_WINDOW = (0.2, 0.8)  # of the heap's height above the floor: the window of its slope
HEAP_LEAST_SHARE = 0.25  # of the particles: fewer in the container make no heap to measure
HEAP_REST_SPEED = 0.05  # m/s: the heap is made of the particles slower than this at the end
MEAN_RATE_TIME = 0.5  # s after the orifice opened: the mean rate over it ranks the shapes


def read_state(path):
    """Time, and the particles' positions, masses and speeds, of a checkpoint."""
    import h5py

    with h5py.File(path, "r") as f:
        position = f["particles/position"][...].reshape(-1, 3)
        mass = f["particles/mass"][...].reshape(-1)
        speed = (f["particles/velocity"][...].reshape(-1, 3) ** 2).sum(axis=1) ** 0.5
        return float(f["time"][()]), position, mass, speed


def discharge_series(run_dir, gate):
    """Time after the gate opened and mass below the orifice plane, from the checkpoints."""
    paths = []
    for segment in segment_dirs(run_dir):
        paths += sorted(glob.glob(os.path.join(segment, "checkpoints", "checkpoint_*.h5")))
        paths.append(os.path.join(segment, "checkpoint.h5"))
    series = []
    for path in paths:
        time, position, mass, _ = read_state(path)
        if time >= gate - 1e-9 and (not series or time - gate > series[-1][0] + 1e-9):
            series.append((time - gate, float(mass[position[:, 2] < 0].sum())))
    return [t for t, _ in series], [m for _, m in series]


def least_squares(xs, ys):
    """Slope, intercept and the slope's standard error of the line through (xs, ys)."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    intercept = my - slope * mx
    residual = sum((y - intercept - slope * x) ** 2 for x, y in zip(xs, ys))
    error = math.sqrt(residual / (n - 2) / sxx) if n > 2 else float("nan")
    return slope, intercept, error


def discharge_figures(time, mass, total):
    """Rate in the steady window, fraction discharged at the end, time to half of it, and the
    share of checkpoint intervals without any discharge while the hopper empties (from the
    first discharge to 90 % of the final discharged mass): intermittent flow stalls."""
    final = mass[-1]
    mean_rate = float("nan")
    if time[-1] >= MEAN_RATE_TIME:
        k = next(k for k, t in enumerate(time) if t >= MEAN_RATE_TIME)
        mean_rate = mass[k] / time[k]
    low, high = STEADY_WINDOW[0] * final, STEADY_WINDOW[1] * final
    window = [(t, m) for t, m in zip(time, mass) if low <= m <= high]
    rate = least_squares(*zip(*window))[0] if len(window) >= 3 else float("nan")
    half = next((t for t, m in zip(time, mass) if m >= 0.5 * final), float("nan"))
    first = next((k for k, m in enumerate(mass) if m > 0), len(mass) - 1)
    last = next((k for k, m in enumerate(mass) if m >= 0.9 * final), len(mass) - 1)
    steps = [mass[k + 1] - mass[k] for k in range(first, last)]
    stalled = sum(1 for d in steps if d <= 0) / len(steps) if steps else float("nan")
    return {"mean_rate_kg_per_s": mean_rate, "discharge_rate_kg_per_s": rate,
            "discharged_fraction": final / total,
            "time_to_half_s": half, "stalled_interval_share": stalled}


def heap_figures(position, diameter, count):
    """Angle of repose of the heap in the container (see the module's text) made by the
    particles at `position` (those at rest), of `count` in all, with the envelope it was fitted
    to."""
    below = position[position[:, 2] < 0]
    if len(below) < HEAP_LEAST_SHARE * count:
        return {"angle_of_repose_degrees": float("nan"), "envelope": [],
                "no_heap": "%d particles at rest in the container, too few for a heap"
                           % len(below)}
    floor = -CONTAINER_DEPTH
    radius = (below[:, 0] ** 2 + below[:, 1] ** 2) ** 0.5
    rings = int(CONTAINER_HALF / diameter)
    envelope = []
    for k in range(rings):
        inside = below[(radius >= k * diameter) & (radius < (k + 1) * diameter)]
        if len(inside):
            envelope.append(((k + 0.5) * diameter, float(inside[:, 2].max()) - floor))
    if len(envelope) < 3:
        return {"angle_of_repose_degrees": float("nan"), "envelope": envelope}
    top = max(h for _, h in envelope)
    if top < diameter:  # every centre within a diameter of the floor: one layer, no heap
        return {"angle_of_repose_degrees": 0.0, "angle_standard_error_degrees": 0.0,
                "heap_height_m": top, "one_layer": True, "envelope": envelope}
    apex = max(range(len(envelope)), key=lambda k: envelope[k][1])
    flank = []  # outwards from the apex, until the envelope first drops below the window
    for r, h in envelope[apex:]:
        if h < HEAP_WINDOW[0] * top:
            break
        if h <= HEAP_WINDOW[1] * top:
            flank.append((r, h))
    if len(flank) < 3:
        return {"angle_of_repose_degrees": float("nan"), "envelope": envelope,
                "heap_height_m": top}
    slope, intercept, error = least_squares(*zip(*flank))
    angle = math.degrees(math.atan(-slope))
    spread = math.degrees(math.atan(-slope + error)) - angle
    return {"angle_of_repose_degrees": angle, "angle_standard_error_degrees": abs(spread),
            "heap_height_m": top, "fit_points": len(flank), "fit": [slope, intercept],
            "envelope": envelope}


def analyse_case(out_dir, case):
    run_dir = os.path.join(out_dir, case.name)
    segments = segment_dirs(run_dir)
    summaries = []
    for segment in segments:
        with open(os.path.join(segment, "run.json")) as f:
            summaries.append(json.load(f))
    summary = summaries[-1]
    _, position, mass, speed = read_state(os.path.join(segments[-1], "checkpoint.h5"))
    resting = position[speed < HEAP_REST_SPEED]
    time, discharged = discharge_series(run_dir, case.gate_open())
    record = {"case": case.name, "shape": case.shape.name, "label": case.shape.label,
              "hopper_angle_degrees": case.hopper.angle_degrees,
              "orifice_m": 2 * case.hopper.orifice_half, "count": case.count,
              "particles_at_end": int(len(mass)), "total_mass_kg": float(mass.sum()),
              "gate_open_s": case.gate_open(), "simulated_s": summary["simulated_time"],
              "stopped_at_rest": summary["simulated_time"] < scene_value(
                  os.path.join(out_dir, case.name + ".yaml"), "duration") - 1e-9,
              "segments": len(segments), "threads": summary["threads"],
              "wall_seconds": sum(s["wall_seconds"] for s in summaries),
              "steps": sum(s["steps"] for s in summaries),
              "narrow_phase_evaluations": sum(s["extra"].get("narrow_phase_evaluations", 0)
                                              for s in summaries),
              "narrow_phase_failures": sum(s["narrow_phase_failures"] for s in summaries),
              "narrow_phase_fallbacks": sum(s["extra"].get("narrow_phase_fallbacks", 0)
                                            for s in summaries),
              "lost_count": summary["extra"].get("lost_count", 0)}
    record.update(discharge_figures(time, discharged, float(mass.sum())))
    record.update(heap_figures(resting, case.shape.diameter, len(position)))
    record["series_time_s"], record["series_discharged_kg"] = time, discharged
    return record


def replicates(records, cases):
    """Each case run again with another seed (other random positions and orientations),
    beside the first: the spread the claims' differences must exceed to mean anything."""
    first = {(c.shape.name, c.hopper.angle_degrees): r for r, c in zip(records, cases)
             if c.seed == Case.seed_default}
    out = []
    for r, c in zip(records, cases):
        base = first.get((c.shape.name, c.hopper.angle_degrees))
        if c.seed == Case.seed_default or base is None:
            continue
        pair = {"shape": c.shape.name, "hopper_angle_degrees": c.hopper.angle_degrees,
                "seeds": [Case.seed_default, c.seed]}
        for key in ("mean_rate_kg_per_s", "discharge_rate_kg_per_s", "angle_of_repose_degrees",
                    "discharged_fraction"):
            pair[key] = [base[key], r[key]]
        a, b = pair["mean_rate_kg_per_s"]
        pair["rate_relative_difference"] = abs(a - b) / max(a, b)
        out.append(pair)
    return out


def claim(text, holds, **figures):
    return {"claim": text, "holds": bool(holds), **figures}


def write_json(path, data):
    with open(path + ".tmp", "w") as f:
        json.dump(data, f, indent=1)
    os.replace(path + ".tmp", path)


def with_count(case, count, study_count):
    return Case(case.name, case.shape, case.hopper, count,
                case.discharge_time * max(1.0, count / study_count), case.seed)


def analyse(study, out_dir, results_name="results"):
    finished = [case for case in study.CASES if case_finished(out_dir, case)]
    records = [analyse_case(out_dir, case) for case in finished]
    missing = [c.name for c in study.CASES if c not in finished]
    results_dir = os.path.join(os.path.dirname(os.path.abspath(study.__file__)), results_name)
    os.makedirs(results_dir, exist_ok=True)
    main = [r for r, case in zip(records, finished) if case.seed == Case.seed_default]
    result = {"study": study.TITLE, "cpu": cpu_name(), "missing_cases": missing,
              "material": MATERIAL, "time_step_s": study.TIME_STEP,
              "mean_rate_time_s": MEAN_RATE_TIME, "discharge_rate_window": STEADY_WINDOW,
              "heap_fit_window": HEAP_WINDOW, "heap_least_share": HEAP_LEAST_SHARE,
              "claims": study.claims(main), "replicates": replicates(records, finished),
              "cases": records}
    write_json(os.path.join(results_dir, "result.json"), result)
    study.plot(main, os.path.join(results_dir, study.PLOT))
    for c in result["claims"]:
        print(("holds   " if c["holds"] else "FAILS   ") + c["claim"])
    for r in records:
        print("%-18s %4.0f deg  mean rate %6.1f g/s  flowing %6.1f g/s  discharged %5.1f %%  "
              "repose %5.1f +- %.1f deg  stalled %4.2f  failures %d / %d" % (
                  r["case"], r["hopper_angle_degrees"], 1e3 * r["mean_rate_kg_per_s"],
                  1e3 * r["discharge_rate_kg_per_s"],
                  100 * r["discharged_fraction"], r["angle_of_repose_degrees"],
                  r.get("angle_standard_error_degrees", float("nan")),
                  r["stalled_interval_share"], r["narrow_phase_failures"],
                  r["narrow_phase_evaluations"]))


def plot_discharge(axis, records):
    for r in records:
        total = r["total_mass_kg"]
        axis.plot(r["series_time_s"], [100 * m / total for m in r["series_discharged_kg"]],
                  label=r["label"])
    axis.set_xlabel("time after the orifice opened (s)")
    axis.set_ylabel("discharged mass (%)")
    axis.grid(alpha=0.3)


def plot_heaps(axis, records):
    for r in records:
        if not r["envelope"]:
            continue
        rs, hs_ = zip(*r["envelope"])
        line, = axis.plot([1e3 * x for x in rs], [1e3 * h for h in hs_], ".", ms=4)
        if "fit" in r:
            slope, intercept = r["fit"]
            axis.plot([1e3 * x for x in rs], [1e3 * (intercept + slope * x) for x in rs], "-",
                      color=line.get_color(), lw=1,
                      label="%s %.1f deg" % (r["label"], r["angle_of_repose_degrees"]))
    axis.set_ylim(bottom=0)
    axis.set_xlabel("distance from the orifice axis (mm)")
    axis.set_ylabel("heap envelope above the floor (mm)")
    axis.grid(alpha=0.3)


def segment_dirs(run_dir):
    """The finished segments of a case, in order."""
    dirs = []
    while os.path.exists(os.path.join(run_dir, "segment_%03d" % len(dirs), "run.json")):
        dirs.append(os.path.join(run_dir, "segment_%03d" % len(dirs)))
    return dirs


def read_series_rows(run_dir):
    import csv

    rows = []
    for segment in segment_dirs(run_dir):
        with open(os.path.join(segment, "series.csv")) as f:
            for row in csv.DictReader(f):
                if not rows or float(row["time"]) > rows[-1]["time"]:
                    rows.append({k: float(v) for k, v in row.items()})
    return rows


def at_rest(case, run_dir, total_mass):
    """Whether the run may stop: REST_TIME after the gate opened at least, and the particles'
    translational kinetic energy below REST_ENERGY x total mass x g x D0 throughout the last
    REST_TIME (the book runs "until everything is at rest"; a jammed orifice is at rest too)."""
    rows = read_series_rows(run_dir)
    if not rows or rows[-1]["time"] < case.gate_open() + REST_TIME:
        return False
    limit = REST_ENERGY * total_mass * 9.81 * case.shape.diameter
    recent = [r for r in rows if r["time"] >= rows[-1]["time"] - REST_TIME]
    return all(r["translational_energy"] < limit for r in recent)


def case_finished(out_dir, case):
    run_dir = os.path.join(out_dir, case.name)
    done = segment_dirs(run_dir)
    if not done:
        return False
    with open(os.path.join(done[-1], "run.json")) as f:
        simulated = json.load(f)["simulated_time"]
    total_mass = case.count * MATERIAL["density"] * sphere_volume(case.shape.diameter)
    duration = scene_value(os.path.join(out_dir, case.name + ".yaml"), "duration")
    return simulated >= duration - 1e-9 or at_rest(case, run_dir, total_mass)


def run_case(kdem, out_dir, case):
    """Runs one case on one thread in segments of SEGMENT_TIME, each restarted from the one
    before (bit for bit), until it is at rest or reaches its duration. Finished segments are
    kept: a stopped study goes on from the last one. Returns the exit status."""
    run_dir = os.path.join(out_dir, case.name)
    scene = os.path.join(out_dir, case.name + ".yaml")
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
    while not case_finished(out_dir, case):
        done = segment_dirs(run_dir)
        simulated = 0.0
        if done:
            with open(os.path.join(done[-1], "run.json")) as f:
                simulated = json.load(f)["simulated_time"]
        end = case.gate_open() + REST_TIME if not done else simulated + SEGMENT_TIME
        dt = scene_value(scene, "time_step")
        steps = max(1, round((min(end, scene_value(scene, "duration")) - simulated) / dt))
        command = [kdem, "run", scene, "--out", os.path.join(run_dir, "segment_%03d" % len(done)),
                   "--steps", str(steps), "--quiet"]
        if done:
            command += ["--restart", os.path.join(done[-1], "checkpoint.h5")]
        with open(os.path.join(out_dir, case.name + ".log"), "a") as log:
            status = subprocess.run(command, env=env, stdout=log,
                                    stderr=subprocess.STDOUT).returncode
        print(f"{case.name}: segment {len(done)} to t = {end:.3f} s: exit {status}", flush=True)
        if status:
            return status
    return 0


def scene_value(scene, key):
    """A top-level number of a scene as written (the run stops at its duration as written)."""
    with open(scene) as f:
        return float(next(line for line in f if line.startswith(key + ":")).split(":")[1])


def run_all(study, out_dir, jobs):
    kdem = os.path.join(ROOT, "build", "openmp", "bin", "kdem")
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        statuses = list(pool.map(lambda case: run_case(kdem, out_dir, case), study.CASES))
    if any(statuses):
        raise SystemExit("failed: " + ", ".join(c.name for c, s in zip(study.CASES, statuses) if s))


def main(study):
    parser = argparse.ArgumentParser(description=study.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command", choices=["scenes", "run", "analyse"])
    parser.add_argument("out_dir")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    parser.add_argument("--count", type=int, default=0,
                        help="particles per case instead of the study's (results then go to "
                             "results/count_N; each case's longest duration grows in step)")
    args = parser.parse_args()
    results_name = "results"
    if args.count:
        study.CASES = [with_count(c, args.count, study.COUNT) for c in study.CASES]
        results_name = os.path.join("results", "count_%d" % args.count)
    if args.cases:
        wanted = args.cases.split(",")
        unknown = [w for w in wanted if w not in [c.name for c in study.CASES]]
        if unknown:
            raise SystemExit("unknown cases: " + ", ".join(unknown))
        study.CASES = [c for c in study.CASES if c.name in wanted]
    if args.command == "scenes":
        write_scenes(study, args.out_dir)
    elif args.command == "run":
        write_scenes(study, args.out_dir)
        run_all(study, args.out_dir, args.jobs)
    else:
        analyse(study, args.out_dir, results_name)
