#!/usr/bin/env python3
"""Roofline model of a kdem time step on a GPU, from counts taken on the CPU.

For each stage of the step (perf/stages.py) the model takes
  - bytes moved per particle-step, counted from the data layout and the kernels' code (the
    table STAGE_BYTES below: every field a kernel reads or writes, once per item, for the
    items of the stage: particles, candidate pairs, touching pairs, narrow-phase evaluations,
    wall candidates, list rebuilds), with the item counts of a measured run;
  - FP64 operations per particle-step, counted by callgrind on the CPU (the executed SSE2/FMA
    arithmetic instructions, perf/callgrind_stages.py); for the superquadric narrow phase, per
    evaluation, and divided by the SIMT efficiency of its Newton loop (the mean iteration count
    over the expected largest of a warp's 32, from the measured iteration histograms);
  - kernel launches per step (`kdem run --kernel-times`), each costing a fixed latency.
A stage takes max(bytes / bandwidth, flops / FP64 peak); the step is the sum over stages plus
the launches. This is a bound in the roofline sense: peak bandwidth and peak FP64 rate,
perfect caching of the gathered particle rows (each particle's row read once per kernel),
no atomics contention, no occupancy limit. What is assumed, rather than counted, is named in
ASSUMPTIONS and in docs/performance.md.

  perf/gpu_model.py --counts perf/results/callgrind_stages.json \\
      --narrow-phase perf/results/narrow_phase_warm_start_after.json \\
      --hopper perf/results/hopper_shapes.json --out perf/results/gpu_model.json
"""

import argparse
import json
import math
import sys
from pathlib import Path

GPUS = {
    # name: (DRAM bandwidth B/s, FP64 peak flop/s without tensor cores), vendor data sheets
    "H100 SXM5": (3.35e12, 34.0e12),
    "A100 SXM4 80GB": (2.039e12, 9.7e12),
    "Quadro GV100": (0.870e12, 7.4e12),
}

ASSUMPTIONS = {
    "launch_latency_s": 5e-6,  # per kernel, launch plus the wait of a step's ordered kernels
    "warp_size": 32,
}

# Bytes of the engine's Views (kernels/particles.hpp, pair_list.hpp, walls.hpp).
PARTICLE_ROW = 24 * 7 + 32 + 8 * 3 + 4 * 2 + 8  # 3-vectors, quaternion, scalars, ints, id
# i, j, reverse index, partner id, spring, force, torque on i, overlap; + rolling torque if on
PAIR_ROW_SPHERES = 4 * 3 + 8 + 24 * 3 + 8
PAIR_ROW_SUPERQUADRIC = 24 + 8 + 4 + 8 + 24 + 8 + 8  # warm start, box axis, certificate


def stage_bytes(items, rigid, rolling, cached_gathers=True):
    """Bytes per particle-step of each stage, given the items per particle-step (a dict with
    candidates, contacts, evaluations, superquadric_candidates, wall_candidates, rebuilds).
    With cached_gathers each particle's row is read from memory once per kernel (its pairs'
    partners are its neighbours in cell order, so they stay in cache); without, every pair
    reads its partner's row again (the pessimistic end)."""
    c, t = items["candidates"], items["contacts"]
    w, b = items["wall_candidates"], items["rebuilds"]
    history = 48 if rolling else 24  # tangential spring, and the rolling torque if on
    pair_row = PAIR_ROW_SPHERES + (24 if rolling else 0) + (PAIR_ROW_SUPERQUADRIC if rigid else 0)
    out = {}
    # kick_and_drift: reads v f m x q w I torque (184), writes v x q w (104); rigid bodies also
    # read and write turned_angle. kick: reads v f m w q I torque (160), writes v w (48).
    out["integration"] = 288 + (16 if rigid else 0) + 208
    # max_displacement every step (x, x at build); per rebuild: the pair count and fill pass
    # (x, r of the particle, pair i, j, partner id written), the history transfer (old and new
    # pair rows), the reverse index, the wall candidate lists and their history.
    out["lists"] = 48 + b * (32 + c * (16 + 2 * pair_row + 8) + w * 2 * (4 + 8 + history + 8))
    # per rebuild: every particle field gathered into cell order (read and write), cell counts.
    out["binning"] = b * (2 * PARTICLE_ROW + 16)
    # per particle: x r v w m material, force and torque written; per wall candidate: element,
    # history read and written, overlap read and written.
    out["walls"] = 148 + w * (4 + 2 * history + 16)
    if rigid:
        e, s = items["evaluations"], items["superquadric_candidates"]
        # prefilter per candidate: row, i, j, overlap, certificate (margin, offset, angles), box
        # axis, pass flag; compaction: flag, row read, row written; per particle x r q shape.
        out["superquadric box tests"] = 76 + s * (4 + 8 + 8 + 8 + 24 + 16 + 8 + 4 + 12)
        # per evaluation: row, i, j, warm start read and written, certificate written; per
        # touching pair: the contact law's history and the force and torque on i written.
        out["superquadric contacts"] = e * (4 + 8 + 2 * 32 + 8 + 24 + 16) + t * (
            2 * history + 48 + 8)
        out["sphere contacts"] = 0
    else:
        # per particle: x r v w m material; per candidate: i, j, overlap; per contact: history
        # read and written, force and the torque on i written.
        out["sphere contacts"] = 92 + c * 16 + t * (2 * history + 48)
    # per particle: row and reverse starts, x, force and torque read and written; per candidate:
    # reverse index, force and torque on i read twice, and the pair's i (the torque on j needs
    # its position: a neighbour's row, cached).
    out["gather"] = 128 + c * (4 + 48 + 48 + 4)
    if not cached_gathers:  # partner rows read per pair: x r (box tests: + q shape turned)
        out["gather"] += c * 24
        if rigid:
            s_ = items["superquadric_candidates"]
            out["superquadric box tests"] += s_ * 76
            out["superquadric contacts"] += items["evaluations"] * 60 + t * 60
        else:
            out["sphere contacts"] += c * 32 + t * 60
    return out


def expected_warp_max(histogram, warp):
    """E[max of `warp` independent draws] of an iteration histogram {iterations: counts}."""
    values = sorted(histogram.items())
    total = sum(n for _, n in values)
    expected, below = 0.0, 0.0
    for k, n in values:
        cdf_prev = below / total
        below += n
        cdf = below / total
        expected += k * (cdf ** warp - cdf_prev ** warp)
    return expected


def simt_efficiency(narrow_phase_path, warp):
    """Mean over expected warp maximum of the Newton iteration counts of the warm-started sets
    of a bench_narrow_phase result (the state of pairs already in contact, as in a run)."""
    data = json.loads(Path(narrow_phase_path).read_text())
    merged = {}
    for run in data["runs"]:
        for case_set in run["sets"]:
            if not case_set.get("warm_start"):
                continue
            h = case_set["iteration_histogram"]
            for k, n in zip(h["iterations"], h["counts"]):
                merged[k] = merged.get(k, 0) + n
    if not merged:
        return 1.0, {}
    mean = sum(k * n for k, n in merged.items()) / sum(merged.values())
    return mean / expected_warp_max(merged, warp), merged


def items_of(scene):
    n = scene["particles"]
    steps = scene["steps"]
    rebuilds = 0
    for label, tally in scene["kernel_times"].items():
        if label == "kdem::pair_fill":
            rebuilds = tally["launches"] / steps
    evaluations = scene["narrow_phase_evaluations"] / scene["particle_steps"]
    return {
        "candidates": scene["pair_candidates"] / n,
        "superquadric_candidates": scene["pair_candidates"] / n,
        "contacts": scene["pair_contacts"] / n,
        "wall_candidates": scene["wall_candidates"] / n,
        "evaluations": evaluations,
        "rebuilds": rebuilds,
    }


def model_stage(stage, rigid):
    """The stage of the byte table that a counted (callgrind) stage belongs to: the contact law
    runs inside the pair kernels, and the narrow phase inside the superquadric pair kernel."""
    if stage == "contact law":
        return "superquadric contacts" if rigid else "sphere contacts"
    if stage == "superquadric narrow phase":
        return "superquadric contacts"
    return stage


def predict_step(scene, gpu, efficiency, rigid, rolling=False, cached_gathers=True):
    """Seconds per particle-step per stage at large N (no launch latency), and the limiting
    resource of each stage."""
    bandwidth, peak = GPUS[gpu]
    items = items_of(scene)
    bytes_ = stage_bytes(items, rigid, rolling, cached_gathers)
    flops = {}
    for stage, cost in scene["stages"].items():
        f = cost["fp64_per_particle_step"]
        if stage == "superquadric narrow phase":
            f /= efficiency  # lanes of a warp wait for its slowest Newton solve
        target = model_stage(stage, rigid)
        flops[target] = flops.get(target, 0.0) + f
    stages = {}
    for stage in sorted(set(flops) | set(bytes_)):
        moved, f = bytes_.get(stage, 0.0), flops.get(stage, 0.0)
        memory_time, compute_time = moved / bandwidth, f / peak
        stages[stage] = {
            "bytes_per_particle_step": moved,
            "fp64_per_particle_step": f,
            "seconds_per_particle_step": max(memory_time, compute_time),
            "limit": "memory" if memory_time >= compute_time else "FP64",
        }
    return stages, items


def throughput(stages, particles, launches_per_step):
    per_step = particles * sum(s["seconds_per_particle_step"] for s in stages.values())
    per_step += launches_per_step * ASSUMPTIONS["launch_latency_s"]
    return particles / per_step


def hopper_prediction(runs, scenes, gpu, efficiency):
    """Predicted GPU wall time of each measured hopper run: particle-steps and evaluations of
    the run, costs per item from the settled scenes, plus the launches of every step."""
    table = []
    for run in runs:
        rigid = run["shape"] != "sphere"
        scene = scenes.get(SCENE_OF_SHAPE[run["shape"]]) or scenes["cubes" if rigid else "spheres"]
        stages, _ = predict_step(scene, gpu, efficiency, rigid)
        particle_steps = run["particle_steps_per_second"] * run["wall_seconds"]
        seconds = 0.0
        for stage, s in stages.items():
            if stage == "superquadric contacts" and scene["narrow_phase_evaluations"] > 0:
                per_evaluation = s["seconds_per_particle_step"] * scene["particle_steps"] / \
                    scene["narrow_phase_evaluations"]
                seconds += per_evaluation * run["narrow_phase_evaluations"]
            else:
                seconds += s["seconds_per_particle_step"] * particle_steps
        launches = run["steps"] * scene["kernel_launches_per_step"]
        seconds += launches * ASSUMPTIONS["launch_latency_s"]
        table.append({"shape": run["shape"], "count": run["count"], "steps": run["steps"],
                      "predicted_seconds": seconds,
                      "launch_seconds": launches * ASSUMPTIONS["launch_latency_s"]})
    return table


SCENE_OF_SHAPE = {"sphere": "spheres", "cylinder": "cylinders", "cube": "cubes"}

BOOK_GV100 = {  # Table 6.4 of the book, GPU column (s), hopper discharged until empty
    ("sphere", 1000): 39, ("cylinder", 1000): 53, ("cube", 1000): 71,
    ("sphere", 3162): 93, ("cylinder", 3162): 143, ("cube", 3162): 249,
    ("sphere", 10000): 363, ("cylinder", 10000): 576, ("cube", 10000): 939,
    ("sphere", 31620): 1938, ("cylinder", 31620): 3022, ("cube", 31620): 5212,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--counts", default="perf/results/callgrind_stages.json")
    parser.add_argument("--narrow-phase", default="perf/results/narrow_phase_warm_start_after.json")
    parser.add_argument("--hopper", default="perf/results/hopper_shapes.json")
    parser.add_argument("--particles", type=float, default=1e6)
    parser.add_argument("--out", default="perf/results/gpu_model.json")
    args = parser.parse_args()
    counts = json.loads(Path(args.counts).read_text())
    scenes = counts["scenes"]
    efficiency, histogram = simt_efficiency(args.narrow_phase, ASSUMPTIONS["warp_size"])
    result = {"assumptions": ASSUMPTIONS, "gpus": GPUS, "simt_efficiency": efficiency,
              "iteration_histogram": histogram, "counts_from": args.counts,
              "machine_of_counts": counts["machine"], "large_n": {}, "hopper": {}}
    for gpu in GPUS:
        result["large_n"][gpu] = {}
        for name, scene in scenes.items():
            rigid = name != "spheres"
            stages, items = predict_step(scene, gpu, efficiency, rigid)
            limiting = max(stages, key=lambda s: stages[s]["seconds_per_particle_step"])
            uncached, _ = predict_step(scene, gpu, efficiency, rigid, cached_gathers=False)
            result["large_n"][gpu][name] = {
                "particles": args.particles,
                "particle_steps_per_second": throughput(stages, args.particles,
                                                        scene["kernel_launches_per_step"]),
                "particle_steps_per_second_uncached_gathers": throughput(
                    uncached, args.particles, scene["kernel_launches_per_step"]),
                "limiting_stage": limiting,
                "limiting_resource": stages[limiting]["limit"],
                "items_per_particle_step": items,
                "stages": stages,
            }
        if Path(args.hopper).exists():
            runs = json.loads(Path(args.hopper).read_text())["runs"]
            table = hopper_prediction(runs, scenes, gpu, efficiency)
            for row in table:
                row["book_seconds"] = BOOK_GV100.get((row["shape"], row["count"]))
            result["hopper"][gpu] = table
    text = json.dumps(result, indent=2) + "\n"
    out = Path(args.out)
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(text)
    tmp.replace(out)
    print(f"SIMT efficiency of the narrow phase: {efficiency:.2f}")
    for gpu, by_scene in result["large_n"].items():
        for name, r in by_scene.items():
            print(f"{gpu:16s} {name:10s} {r['particle_steps_per_second']:.3g} particle-steps/s "
                  f"({r['particle_steps_per_second_uncached_gathers']:.3g} uncached; largest "
                  f"stage: {r['limiting_stage']}, {r['limiting_resource']})")
    for row in result["hopper"].get("Quadro GV100", []):
        book = row["book_seconds"]
        print(f"GV100 hopper {row['shape']:8s} N={row['count']:6d}: predicted "
              f"{row['predicted_seconds']:8.1f} s, book {book if book else '-'} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
