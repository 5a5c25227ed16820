#!/usr/bin/env python3
"""`make gpu-check`: on a machine with an NVIDIA GPU, build kdem for that GPU, run the whole test
suite there, check that Serial, OpenMP and CUDA agree on the same scenes, run the benchmarks,
and write one JSON and one Markdown report naming the GPU. With --preset openmp the same runs
on the CPU (no CUDA column); CI runs it so, so that the script cannot rot.

  perf/gpu_check.py --preset auto|cuda|cuda-sm80|openmp --out out/gpu-check [--quick]
                    [--prebuilt] [--test-shards N] [--shape-particles N]

Stages, the report written after each: backend agreement, shape costs (settled beds of the four
shapes at --shape-particles, cost per particle-step over the sphere's), the benchmark scenes,
the test suites (the CUDA suite in --test-shards shards at once).

Backend agreement: each scene of tests/cli runs --warm-steps from its start (OpenMP), and
from that checkpoint every backend runs --steps more. Serial and OpenMP must be bit-identical.
CUDA rounds differently (fused multiply-adds, its own libm), and a granular flow amplifies any
difference, so CUDA must agree within TOLERANCE_RADII of the smallest particle radius in
position after those steps. The report also measures, on the CPU and on the same scenes, how
far a one-ulp change of every initial position grows over the same steps; CUDA's rounding
perturbs every step by at most about that much (a position's rounding; a force's rounding moves
a particle far less), so after S steps it is bounded by S times that growth, and the check
requires S times the growth to stay below the tolerance (else the horizon is too long for the
tolerance to separate rounding from a defect).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
import run_bench  # noqa: E402
import stages as step_stages  # noqa: E402

AGREEMENT_SCENES = ["small_hopper", "small_superquadrics", "drum"]
TOLERANCE_RADII = 1e-4
BENCH_SCENES = ["spheres", "ellipsoids", "cylinders", "cubes"]  # perf/callgrind/*.yaml
SHAPES = ["sphere", "ellipsoid", "cylinder", "cube"]  # perf/bench_spheres.cpp --shape


class Report:
    def __init__(self, out):
        self.out = out
        self.data = {"started": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "checks": []}
        self.failed = False

    def check(self, name, passed, detail):
        self.data["checks"].append({"name": name, "passed": bool(passed), "detail": detail})
        self.failed = self.failed or not passed
        print(f"[{'ok' if passed else 'FAILED'}] {name}: {detail}", flush=True)

    def write(self):
        self.out.mkdir(parents=True, exist_ok=True)
        for name, text in (("gpu_check.json", json.dumps(self.data, indent=2) + "\n"),
                           ("gpu_check.md", markdown(self.data))):
            tmp = self.out / (name + ".tmp")
            tmp.write_text(text)
            tmp.replace(self.out / name)


def run(command, env=None, check=True, log=None):
    print("$ " + " ".join(str(c) for c in command), flush=True)
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True,
                            env={**os.environ, **(env or {})})
    if log is not None:
        log.write_text(result.stdout + result.stderr)
    if check and result.returncode != 0:
        raise RuntimeError(f"{command[0]} failed ({result.returncode}):\n{result.stderr[-3000:]}")
    return result


def gpu_info():
    if shutil.which("nvidia-smi") is None:
        return None
    result = subprocess.run(["nvidia-smi", "--query-gpu=name,compute_cap,driver_version,"
                             "memory.total", "--format=csv,noheader"],
                            capture_output=True, text=True)
    if result.returncode != 0 or not result.stdout.strip():
        return None
    name, capability, driver, memory = [f.strip() for f in
                                        result.stdout.splitlines()[0].split(",")]
    return {"name": name, "compute_capability": capability, "driver": driver, "memory": memory}


def choose_preset(requested, gpu):
    if requested != "auto":
        return requested
    if gpu is None:
        sys.exit("gpu-check: no NVIDIA GPU visible (nvidia-smi); GPU_CHECK_PRESET=openmp runs the "
                 "same checks on the CPU")
    major = int(gpu["compute_capability"].split(".")[0])
    if major >= 9:
        return "cuda"  # sm_90 code, and its PTX for newer GPUs
    if major == 8:
        return "cuda-sm80"  # sm_80 code, and its PTX for 8.6 and 8.9
    sys.exit(f"gpu-check: compute capability {gpu['compute_capability']} is older than the "
             "builds of scripts/deps.sh (8.0 and 9.0)")


def run_test_suites(report, preset, out, quick, shards):
    """Each suite in `shards` GoogleTest shards run at once (processes sharing the device), so
    that a suite of many short launches is not bound by one process's launch latency."""
    if preset == "openmp":
        binaries = [("openmp", ROOT / "build/openmp/bin/kdem_tests_openmp", ["--kokkos-threads=2"]),
                    ("serial", ROOT / "build/openmp/bin/kdem_tests_serial", [])]
        shards = 1
    else:
        binaries = [("cuda", ROOT / f"build/{preset}/bin/kdem_tests_cuda", [])]
    for backend, binary, extra in binaries:
        started = time.time()
        processes = []
        for shard in range(shards):
            result_file = out / f"tests_{backend}_{shard}.json"
            result_file.unlink(missing_ok=True)
            args = [str(binary), f"--gtest_output=json:{result_file}", *extra]
            if quick:
                args.append("--gtest_filter=MemorySpaces.*:SuperquadricContact.*:ContactHistory.*")
            log = open(out / f"tests_{backend}_{shard}.log", "w")
            env = {**os.environ, "GTEST_TOTAL_SHARDS": str(shards), "GTEST_SHARD_INDEX": str(shard)}
            print("$ " + " ".join(args) + f"  (shard {shard + 1} of {shards})", flush=True)
            processes.append((subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, env=env),
                              result_file, log))
        summary = {"tests": 0, "failures": 0, "disabled": 0, "failed_tests": [], "shards": shards}
        passed = True
        for process, result_file, log in processes:
            passed = process.wait() == 0 and passed
            log.close()
            if not result_file.exists():
                passed = False
                summary["failed_tests"].append(f"(shard wrote no results: {result_file.name})")
                continue
            doc = json.loads(result_file.read_text())
            for key in ("tests", "failures", "disabled"):
                summary[key] += doc.get(key, 0)
            summary["failed_tests"] += [f"{suite['name']}.{test['name']}"
                                        for suite in doc.get("testsuites", [])
                                        for test in suite.get("testsuite", [])
                                        if test.get("failures")]
        summary["wall_seconds"] = round(time.time() - started, 1)
        failed = ", ".join(summary["failed_tests"][:10])
        report.check(f"test suite ({backend})", passed,
                     f"{summary['tests']} tests, {summary['failures']} failures"
                     + (f": {failed}" if failed else "") + f" ({summary['wall_seconds']} s)")
        report.data.setdefault("tests", {})[backend] = summary


def read_state(checkpoint):
    import h5py
    import numpy as np
    with h5py.File(checkpoint, "r") as f:
        return {name: np.array(f["particles/" + name]) for name in
                ("id", "position", "velocity", "radius")}


def position_difference(a, b):
    """Largest position difference over the smallest radius (ids must agree)."""
    import numpy as np
    if a["id"].shape != b["id"].shape or not (a["id"] == b["id"]).all():
        return float("inf")
    return float(np.abs(a["position"] - b["position"]).max() / a["radius"].min())


def nudged_copy(checkpoint, target):
    """The checkpoint with every position coordinate moved by one ulp."""
    import h5py
    import numpy as np
    shutil.copyfile(checkpoint, target)
    with h5py.File(target, "r+") as f:
        x = f["particles/position"]
        x[...] = np.nextafter(np.array(x), np.inf)


def backend_agreement(report, preset, out, warm_steps, steps):
    programs = {"serial": ROOT / "build/openmp/bin/kdem-serial",
                "openmp": ROOT / "build/openmp/bin/kdem"}
    if preset != "openmp":
        programs["cuda"] = ROOT / f"build/{preset}/bin/kdem"
    compare = ROOT / "build/openmp/bin/compare_checkpoints"
    rows = []
    for scene_name in AGREEMENT_SCENES:
        scene = ROOT / "tests/cli" / f"{scene_name}.yaml"
        work = out / "agreement" / scene_name
        shutil.rmtree(work, ignore_errors=True)
        run([programs["openmp"], "run", scene, "--out", work / "warm", "--steps", warm_steps,
             "--quiet", "--kokkos-threads=2"])
        start = work / "warm" / "checkpoint.h5"
        nudged_copy(start, work / "nudged.h5")
        ends = {}
        for backend, program in programs.items():
            extra = ["--kokkos-threads=2"] if backend == "openmp" else []
            run([program, "run", scene, "--out", work / backend, "--restart", start, "--steps",
                 steps, "--quiet", *extra])
            ends[backend] = work / backend / "checkpoint.h5"
        run([programs["openmp"], "run", scene, "--out", work / "nudged", "--restart",
             work / "nudged.h5", "--steps", steps, "--quiet", "--kokkos-threads=2"])
        bitwise = run([compare, ends["serial"], ends["openmp"]], check=False)
        report.check(f"Serial = OpenMP bit for bit ({scene_name}, {steps} steps)",
                     bitwise.returncode == 0, bitwise.stdout.strip() or "identical")
        openmp = read_state(ends["openmp"])
        amplification = position_difference(openmp, read_state(work / "nudged" / "checkpoint.h5"))
        report.check(f"{steps} x one-ulp growth below the CUDA tolerance ({scene_name})",
                     amplification * steps <= TOLERANCE_RADII,
                     f"a one-ulp change of the positions grows to {amplification:.3g} radii")
        row = {"scene": scene_name, "warm_steps": warm_steps, "steps": steps,
               "serial_equals_openmp": bitwise.returncode == 0,
               "one_ulp_growth_radii": amplification}
        if "cuda" in ends:
            difference = position_difference(openmp, read_state(ends["cuda"]))
            row["cuda_difference_radii"] = difference
            report.check(f"CUDA within {TOLERANCE_RADII:g} radii of OpenMP ({scene_name}, "
                         f"{steps} steps)", difference <= TOLERANCE_RADII,
                         f"largest position difference {difference:.3g} radii")
        rows.append(row)
    report.data["agreement"] = {"tolerance_radii": TOLERANCE_RADII, "scenes": rows}


def benchmarks(report, preset, out, quick):
    program = ROOT / ("build/openmp/bin/kdem" if preset == "openmp" else f"build/{preset}/bin/kdem")
    threads = ["--kokkos-threads=2"] if preset == "openmp" else []
    rows = []
    for name in BENCH_SCENES:
        scene = ROOT / "perf/callgrind" / f"{name}.yaml"
        work = out / "bench" / name
        shutil.rmtree(work, ignore_errors=True)
        settle = 4000 if quick else 40000
        steps = 200 if quick else 2000
        run([program, "run", scene, "--out", work / "settle", "--steps", settle, "--quiet",
             *threads])
        run([program, "run", scene, "--out", work / "timed", "--restart",
             work / "settle" / "checkpoint.h5", "--steps", steps, "--quiet", "--kernel-times",
             *threads])
        summary = json.loads((work / "timed" / "run.json").read_text())
        kernel_times = json.loads((work / "timed" / "kernel_times.json").read_text())
        rows.append({"scene": name, "particles": kernel_times["particles"], "steps": steps,
                     "settle_steps": settle,
                     "particle_steps_per_second": summary["particle_steps_per_second"],
                     "bytes_per_particle": kernel_times["memory"]["bytes_per_particle"],
                     "stage_seconds_per_step": {
                         s: t["seconds"] / steps
                         for s, t in step_stages.kernel_stages(kernel_times).items()}})
        report.check(f"benchmark {name}", True,
                     f"{summary['particle_steps_per_second']:.3g} particle-steps/s "
                     f"(stage times fenced), {kernel_times['memory']['bytes_per_particle']:.0f} "
                     "B/particle")
    report.data["benchmarks"] = rows


def tile_cache(quick):
    """Where the benchmark keeps its settled tiles (a superquadric tile takes about a minute to
    settle on 2 CPU cores): perf/cache, or for the CI rehearsal (--quick, from a clean clone)
    beside the Kokkos builds outside the clone, so that it settles them once."""
    if not quick:
        return ROOT / "perf/cache"
    cache = Path(os.environ.get("KDEM_CACHE", Path.home() / ".cache/kdem")) / "bench-tiles"
    cache.mkdir(parents=True, exist_ok=True)
    return cache


def shape_costs(report, preset, out, n, quick):
    """Settled beds of perf/bench_spheres.cpp (the beds of perf/bench_scaling.py), one per shape,
    at n particles: cost per particle-step of each shape over the sphere's, measured side by
    side in this run (the book's GPU ratios are 1.6 to 2.7)."""
    if preset == "openmp":
        binary, threads = ROOT / "build/openmp/bin/kdem_bench_openmp", 2
    else:
        binary, threads = ROOT / f"build/{preset}/bin/kdem_bench_cuda", 1
    steps, repeat = (20, 1) if quick else (200, 3)
    rows = []
    for shape in SHAPES:
        record = run_bench.run_kdem(binary, n, steps, steps // 2, repeat, threads,
                                    tile_cache(quick), extra=["--shape", shape])
        rows.append({"shape": shape, "particles": record["n"], "steps": steps, "repeat": repeat,
                     "particle_steps_per_second": record["particle_steps_per_s"],
                     "stage_seconds_per_step": {
                         s: t["seconds"] / steps
                         for s, t in step_stages.kernel_stages(
                             {"kernels": record["kernels"]}).items()}})
    sphere_rate = rows[0]["particle_steps_per_second"]
    for row in rows:
        row["cost_over_sphere"] = sphere_rate / row["particle_steps_per_second"]
        report.check(f"shape cost {row['shape']} ({row['particles']} particles)", True,
                     f"{row['particle_steps_per_second']:.3g} particle-steps/s, "
                     f"{row['cost_over_sphere']:.2f} x the sphere's cost")
    report.data["shape_costs"] = rows
    (out / "shape_costs.json").write_text(json.dumps(rows, indent=2) + "\n")


def markdown(data):
    lines = ["# kdem gpu-check", ""]
    device = data.get("device", {})
    gpu = device.get("gpu") or {}
    lines.append(f"- device: **{gpu.get('name', 'none (CPU rehearsal)')}**"
                 f" (compute capability {gpu.get('compute_capability', '-')}, "
                 f"driver {gpu.get('driver', '-')})")
    lines.append(f"- host CPU: {device.get('cpu')}; preset `{data.get('preset')}`; "
                 f"commit {data.get('commit')}; started {data.get('started')}")
    lines += ["", "| check | result | detail |", "|---|---|---|"]
    for c in data["checks"]:
        lines.append(f"| {c['name']} | {'ok' if c['passed'] else '**FAILED**'} | {c['detail']} |")
    agreement = data.get("agreement")
    if agreement:
        lines += ["", f"Backend agreement (CUDA tolerance {agreement['tolerance_radii']:g} of the "
                  "smallest radius):", "",
                  "| scene | steps | Serial = OpenMP | one-ulp growth (radii) | CUDA - OpenMP (radii) |",
                  "|---|---|---|---|---|"]
        for r in agreement["scenes"]:
            cuda = r.get("cuda_difference_radii")
            lines.append(f"| {r['scene']} | {r['steps']} | "
                         f"{'bitwise' if r['serial_equals_openmp'] else '**differ**'} | "
                         f"{r['one_ulp_growth_radii']:.3g} | "
                         f"{'-' if cuda is None else format(cuda, '.3g')} |")
    if data.get("shape_costs"):
        lines += ["", "Settled beds (perf/bench_spheres.cpp), cost per particle-step over the "
                  "sphere's:", "", "| shape | particles | particle-steps/s | cost / sphere |",
                  "|---|---|---|---|"]
        for r in data["shape_costs"]:
            lines.append(f"| {r['shape']} | {r['particles']} | "
                         f"{r['particle_steps_per_second']:.3g} | {r['cost_over_sphere']:.2f} |")
    if data.get("benchmarks"):
        lines += ["", "| scene | particles | particle-steps/s | bytes/particle |",
                  "|---|---|---|---|"]
        for b in data["benchmarks"]:
            lines.append(f"| {b['scene']} | {b['particles']} | "
                         f"{b['particle_steps_per_second']:.3g} | {b['bytes_per_particle']:.0f} |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--preset", default="auto", choices=["auto", "cuda", "cuda-sm80", "openmp"])
    parser.add_argument("--out", default="out/gpu-check")
    parser.add_argument("--warm-steps", type=int, default=3000)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--shape-particles", type=int, default=100000,
                        help="particles in each settled bed of the shape-cost comparison")
    parser.add_argument("--test-shards", type=int, default=4,
                        help="GoogleTest shards of the CUDA suite run at once")
    parser.add_argument("--prebuilt", action="store_true",
                        help="use the binaries already in build/ (built elsewhere for this GPU)")
    parser.add_argument("--quick", action="store_true",
                        help="a subset of the tests and short benchmarks (CI rehearsal)")
    args = parser.parse_args()
    out = (ROOT / args.out) if not os.path.isabs(args.out) else Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    gpu = gpu_info()
    preset = choose_preset(args.preset, gpu)
    report = Report(out)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    report.data.update({"preset": preset, "commit": commit,
                        "device": {"gpu": gpu, "cpu": run_bench.machine_info()["cpu_model"],
                                   "cores": os.cpu_count()}})
    try:
        if preset != "openmp" and not args.prebuilt:
            run(["make", "-C", ROOT, preset], log=out / "build.log")
        stages = [
            lambda: backend_agreement(report, preset, out, args.warm_steps, args.steps),
            lambda: shape_costs(report, preset, out,
                                2000 if args.quick else args.shape_particles, args.quick),
            lambda: benchmarks(report, preset, out, args.quick),
            lambda: run_test_suites(report, preset, out, args.quick, args.test_shards)]
        for stage in stages:  # the report is written after each, so a stopped run keeps it
            stage()
            report.write()
    except RuntimeError as error:
        report.check("gpu-check ran to the end", False, str(error).splitlines()[0])
        print(error, file=sys.stderr)
    report.write()
    print(f"gpu-check: report in {out}/gpu_check.md and .json "
          f"({'FAILED' if report.failed else 'all checks passed'})")
    return 1 if report.failed else 0


if __name__ == "__main__":
    sys.exit(main())
