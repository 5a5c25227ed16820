#!/usr/bin/env python3
"""Sphere benchmark: kdem (OpenMP, 1 and 2 threads) against LIGGGHTS (1 and 2 MPI ranks).

Every code runs the same settled bed of N spheres (perf/bench_spheres.cpp builds it and writes it
as a LIGGGHTS data file), with the same contact model (Hertz-Mindlin with tangential history and
Coulomb friction, no rolling resistance), material, time step, skin and neighbour-list trigger.
Each run: W untimed warm-up steps from rest, then R timed runs of M steps in the same process.
kdem times engine.advance with std::chrono; LIGGGHTS reports the "Loop time" of each `run`, which
excludes its set-up (neighbour build and first force evaluation), as kdem's timing does.

    python3 perf/run_bench.py                 # the full benchmark (`make bench`)
    python3 perf/run_bench.py --sizes 1000 10000 --repeat 3 --work 5e6   # a quick look

Writes perf/results/bench_spheres.json and docs/img/bench_spheres.png.
"""
import argparse
import datetime
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def log(message):
    print(f"[bench] {message}", flush=True)


def sh(command):
    try:
        return subprocess.run(command, capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def busy_cpu_seconds():
    """CPU seconds the whole machine has spent busy (all processes), from /proc/stat."""
    try:
        fields = [int(x) for x in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]]
    except (OSError, ValueError):
        return None
    user, nice, system, idle, iowait, irq, softirq, steal = (fields + [0] * 8)[:8]
    return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")


def run_measured(command, **kwargs):
    """subprocess.run, also returning the wall time, the CPU time of the child processes and
    the CPU time that other processes took meanwhile (they compete for the cores)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    busy_before = busy_cpu_seconds()
    started = time.time()
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    wall = time.time() - started
    busy_after = busy_cpu_seconds()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    foreign = None
    if busy_before is not None and busy_after is not None:
        foreign = max(0.0, busy_after - busy_before - cpu)
    return result, wall, cpu, foreign


def wait_for_quiet(max_wait_s, threshold=0.1):
    """Waits (at most max_wait_s) until the other processes use under `threshold` of the
    machine's cores over a 2 s sample; returns the seconds waited."""
    started = time.time()
    cores = os.cpu_count() or 1
    announced = False
    while True:
        busy = busy_cpu_seconds()
        time.sleep(2)
        after = busy_cpu_seconds()
        if busy is None or after is None or (after - busy) / (2 * cores) < threshold:
            return time.time() - started
        if time.time() - started > max_wait_s:
            log(f"  machine still busy after {max_wait_s:.0f} s: measuring anyway")
            return time.time() - started
        if not announced:
            log("  other processes are using the cores: waiting for a quiet moment")
            announced = True
        time.sleep(3)


WAITED = [0.0]  # seconds spent waiting for a quiet machine, not counted in the time budget


def add_quiet_arguments(parser, retries=2):
    """The options of measured_run: how long to wait for a quiet machine, how often to repeat a
    disturbed run and what share of the cores other processes may take."""
    parser.add_argument("--quiet-wait", type=float, default=300,
                        help="seconds to wait, before each run, for other processes to go quiet")
    parser.add_argument("--retries", type=int, default=retries,
                        help="runs repeated while other processes disturbed them")
    parser.add_argument("--foreign-limit", type=float, default=0.05,
                        help="share of the cores other processes may take during a run")


def measured_run(run, args):
    """Runs run() (which returns a record with wall_s and foreign_cpu_s) after waiting for a
    quiet machine; repeats it up to args.retries times while other processes took more than
    args.foreign_limit of the cores meanwhile, and keeps the least disturbed record."""
    cores = os.cpu_count() or 1
    best = None
    for attempt in range(args.retries + 1):
        waited = wait_for_quiet(args.quiet_wait)
        WAITED[0] += waited
        record = run()
        if record is None:
            return None
        foreign = record.get("foreign_cpu_s")
        record["foreign_cpu_fraction"] = (round(foreign / (record["wall_s"] * cores), 4)
                                          if foreign is not None and record["wall_s"] > 0
                                          else None)
        record["attempt"] = attempt + 1
        record["waited_for_quiet_s"] = round(waited, 1)
        if best is None or (record["foreign_cpu_fraction"] or 0) < (best["foreign_cpu_fraction"] or 0):
            best = record
        if record["foreign_cpu_fraction"] is None or record["foreign_cpu_fraction"] <= args.foreign_limit:
            break
        if attempt < args.retries:
            log(f"  other processes took {100 * record['foreign_cpu_fraction']:.0f} % of the "
                f"cores during the run: measuring again")
    return best


def load_average():
    try:
        return float(Path("/proc/loadavg").read_text().split()[0])
    except OSError:
        return None


def machine_info():
    info = {}
    lscpu = sh(["lscpu"])
    fields = {}
    for line in lscpu.splitlines():
        if ":" in line:
            key, value = line.split(":", 1)
            fields[key.strip()] = value.strip()
    info["cpu_model"] = fields.get("Model name", "unknown")
    info["logical_cpus"] = int(fields.get("CPU(s)", os.cpu_count() or 0))
    cores = fields.get("Core(s) per socket")
    sockets = fields.get("Socket(s)", "1")
    if cores and sockets.isdigit():
        info["cores"] = int(cores) * int(sockets)
    info["threads_per_core"] = int(fields.get("Thread(s) per core", "1"))
    if "L3 cache" in fields:
        info["l3_cache"] = fields["L3 cache"]
    if "Hypervisor vendor" in fields:
        info["hypervisor"] = fields["Hypervisor vendor"]
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                info["memory_gib"] = round(int(line.split()[1]) / 2**20, 1)
    except OSError:
        pass
    os_release = {}
    try:
        for line in Path("/etc/os-release").read_text().splitlines():
            if "=" in line:
                k, v = line.split("=", 1)
                os_release[k] = v.strip('"')
    except OSError:
        pass
    info["os"] = os_release.get("PRETTY_NAME", sys.platform)
    info["compiler"] = sh(["c++", "--version"]).splitlines()[0] if sh(["c++", "--version"]) else ""
    return info


def modified_sources():
    """Engine sources that differ from the recorded commit (the build measured them too)."""
    try:
        status = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--", "src",
                                 "kernels", "shapes"], capture_output=True, text=True).stdout
    except OSError:
        return []
    return [line[3:] for line in status.splitlines() if len(line) > 3]


def available_memory_gib():
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) / 2**20
    except OSError:
        pass
    return None


# ---------------------------------------------------------------------------------------- kdem
def kdem_env(threads):
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    env["OMP_PROC_BIND"] = "close"
    env["OMP_PLACES"] = "cores"
    return env


def run_kdem(binary, n, steps, warmup, repeat, threads, cache_dir, write_data=None, rebuild=False,
             extra=()):
    """One kdem benchmark run; extra: further options (e.g. --shape cube, --unsorted)."""
    command = [str(binary), "--n", str(n), "--steps", str(steps), "--warmup", str(warmup),
               "--repeat", str(repeat), "--cache-dir", str(cache_dir),
               f"--kokkos-threads={threads}", *extra]
    if write_data:
        command += ["--write-data", str(write_data)]
    if rebuild:
        command.append("--rebuild-every-step")
    load = load_average()
    result, wall, cpu, foreign = run_measured(command, env=kdem_env(threads), cwd=ROOT)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{result.stderr[-3000:]}")
    record = json.loads(result.stdout.strip().splitlines()[-1])
    record["wall_s"] = round(wall, 2)
    record["cpu_s"] = round(cpu, 2)
    record["foreign_cpu_s"] = None if foreign is None else round(foreign, 2)
    record["load_average_before"] = load
    record["workers"] = threads
    return record


# ------------------------------------------------------------------------------------ LIGGGHTS
def find_liggghts():
    for name in ("liggghts", "lmp_auto", "lmp_mpi", "lmp_serial", "lmp_debian"):
        path = shutil.which(name)
        if path:
            return path
    return None


LIGGGHTS_INPUT = """\
# kdem sphere benchmark bed, run in LIGGGHTS with the model, material and numerics of
# perf/bench_spheres.cpp
atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
processors * * 1
read_data {data}
neighbor {skin} bin
neigh_modify delay 0 every 1 check {check}
fix m1 all property/global youngsModulus peratomtype {youngs}
fix m2 all property/global poissonsRatio peratomtype {poisson}
fix m3 all property/global coefficientRestitution peratomtypepair 1 {restitution}
fix m4 all property/global coefficientFriction peratomtypepair 1 {friction}
pair_style gran model hertz tangential history
pair_coeff * *
timestep {dt}
fix gravity all gravity {gravity} vector 0.0 0.0 -1.0
fix wall_zmin all wall/gran model hertz tangential history primitive type 1 zplane {zlo}
fix wall_xmin all wall/gran model hertz tangential history primitive type 1 xplane {xlo}
fix wall_xmax all wall/gran model hertz tangential history primitive type 1 xplane {xhi}
fix wall_ymin all wall/gran model hertz tangential history primitive type 1 yplane {ylo}
fix wall_ymax all wall/gran model hertz tangential history primitive type 1 yplane {yhi}
fix integrate all nve/sphere
compute rotational all erotate/sphere
compute contacts_per_atom all contact/atom
compute contacts all reduce sum c_contacts_per_atom
thermo_modify norm no
thermo_style custom step atoms ke c_rotational
thermo 0
run {warmup}
{timed_runs}
thermo_style custom step atoms ke c_rotational c_contacts
run 0
"""

LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
BUILDS = re.compile(r"Neighbor list builds = (\d+)")
VERSION = re.compile(r"LIGGGHTS \(Version ([^)]*)\)")


def mpi_launcher(procs):
    if procs == 1:
        return []
    mpirun = shutil.which("mpirun") or shutil.which("mpiexec")
    if not mpirun:
        return None
    launcher = [mpirun, "-np", str(procs)]
    if "Open MPI" in sh([mpirun, "--version"]) or "OpenRTE" in sh([mpirun, "--version"]):
        launcher += ["--bind-to", "core"]
        if os.geteuid() == 0:
            launcher.append("--allow-run-as-root")
    return launcher


def run_liggghts(binary, data_file, bed, model, steps, warmup, repeat, procs, work_dir,
                 rebuild=False):
    launcher = mpi_launcher(procs)
    if launcher is None:
        return None
    lo, hi = bed["box_min"], bed["box_max"]
    script = LIGGGHTS_INPUT.format(
        data=data_file.resolve(), skin=model["skin"], check="no" if rebuild else "yes",
        youngs=model["youngs_modulus"], poisson=model["poisson_ratio"],
        restitution=model["restitution"], friction=model["friction"], dt=model["time_step"],
        gravity=model["gravity"], xlo=lo[0], xhi=hi[0], ylo=lo[1], yhi=hi[1], zlo=lo[2],
        warmup=warmup, timed_runs="\n".join(f"run {steps}" for _ in range(repeat)))
    work_dir.mkdir(parents=True, exist_ok=True)
    tag = f"{bed['n']}_{procs}{'_rebuild' if rebuild else ''}"
    input_file = work_dir / f"in.bench_{tag}"
    input_file.write_text(script)
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    command = launcher + [binary, "-in", str(input_file.resolve()), "-log", "none"]
    load = load_average()
    result, wall, cpu, foreign = run_measured(command, cwd=work_dir, env=env)
    output = result.stdout + result.stderr
    if result.returncode != 0 or "ERROR" in output:
        raise RuntimeError(f"{' '.join(command)} failed:\n{output[-3000:]}")
    (work_dir / f"log.bench_{tag}").write_text(output)
    loops = LOOP.findall(output)
    builds = [int(b) for b in BUILDS.findall(output)]
    # runs: warm-up, R timed, run 0
    if len(loops) != repeat + 2:
        raise RuntimeError(f"expected {repeat + 2} LIGGGHTS runs, found {len(loops)}")
    times = [float(loop[0]) for loop in loops[1:1 + repeat]]
    step, atoms, translational, rotational, contacts = thermo_rows(output)[-1]
    median_s = statistics.median(times) if times else 0.0
    n = int(loops[0][3])
    version = VERSION.search(output)
    return {
        "code": "LIGGGHTS", "version": version.group(1) if version else "unknown",
        "procs": int(loops[0][1]), "workers": procs, "n": n, "steps": steps, "repeat": repeat,
        "warmup": warmup, "rebuild_every_step": rebuild, "median_s": median_s, "times_s": times,
        "particle_steps_per_s": n * steps / median_s if median_s > 0 else 0.0,
        "pair_contacts": int(round(contacts / 2)),
        "contacts_per_particle": contacts / n,
        "list_builds_timed": sum(builds[1:1 + repeat]) if len(builds) >= repeat + 1 else None,
        "kinetic_energy_j": translational + rotational,
        "wall_s": round(wall, 2), "cpu_s": round(cpu, 2),
        "foreign_cpu_s": None if foreign is None else round(foreign, 2),
        "load_average_before": load,
    }


def thermo_rows(output):
    """Numeric rows of LIGGGHTS thermo blocks (headers are truncated, so rows are positional)."""
    rows, width = [], 0
    for line in output.splitlines():
        words = line.split()
        if words[:2] == ["Step", "Atoms"]:
            width = len(words)
            continue
        if width and len(words) == width:
            try:
                rows.append([float(w) for w in words])
                continue
            except ValueError:
                pass
        width = 0
    return rows


# ------------------------------------------------------------------------------------ plotting
def worker_label(code, workers):
    unit = "thread" if code == "kdem" else "proc"
    return f"{code} {workers} {unit}{'s' if workers > 1 else ''}"


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter

    colours = {1: "tab:blue", 2: "tab:orange"}
    fig, (ax, ratio_ax) = plt.subplots(1, 2, figsize=(11.5, 4.4))
    series = {}
    for run in results["runs"]:
        if not run.get("rebuild_every_step"):
            series.setdefault((run["code"], run["workers"]), []).append(
                (run["n"], run["particle_steps_per_s"] / 1e6))
    for (code, workers), points in sorted(series.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        points.sort()
        ax.plot([q[0] for q in points], [q[1] for q in points], label=worker_label(code, workers),
                color=colours.get(workers, "gray"), marker="o" if code == "kdem" else "s",
                linestyle="-" if code == "kdem" else "--")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.yaxis.set_major_formatter(FuncFormatter(lambda y, _: f"{y:g}"))
    ax.yaxis.set_minor_formatter(FuncFormatter(lambda y, _: f"{y:g}"))
    ax.tick_params(axis="y", which="minor", labelsize=7)
    ax.set_xlabel("spheres N")
    ax.set_ylabel("million particle-steps per second")
    ax.set_title("Settled bed, Hertz-Mindlin with history\n(skin trigger, median of repeats)",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    for variant, style in ((False, "-"), (True, ":")):
        for workers in (1, 2):
            points = sorted((r["n"], r["kdem_over_liggghts"]) for r in results["ratios"]
                            if r["workers"] == workers
                            and r.get("rebuild_every_step", False) == variant)
            if not points:
                continue
            label = (f"{workers} thread{'s' if workers > 1 else ''} / "
                     f"{workers} proc{'s' if workers > 1 else ''}"
                     + (", lists rebuilt every step" if variant else ", skin trigger"))
            ratio_ax.plot([q[0] for q in points], [q[1] for q in points], marker="o",
                          linestyle=style, color=colours.get(workers, "gray"), label=label)
    ratio_ax.axhline(1.0, color="black", linewidth=0.8)
    ratio_ax.set_xscale("log")
    ratio_ax.set_xlabel("spheres N")
    ratio_ax.set_ylabel("kdem / LIGGGHTS throughput")
    ratio_ax.set_title("Throughput ratio, same workers (> 1: kdem faster)", fontsize=10)
    ratio_ax.grid(True, which="both", alpha=0.3)
    ratio_ax.legend(fontsize=8)
    machine = results["machine"]
    fig.text(0.01, 0.01, f"measured: {machine['cpu_model']}, {machine.get('cores', '?')} cores, "
                         f"kdem {results['kdem_git']}, {results['date'][:10]}",
             fontsize=7, color="gray")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ---------------------------------------------------------------------------------------- main
def predict_seconds(previous, n, steps, warmup, repeat):
    """Time of the runs at size n, from the rates and set-up overheads of the previous size."""
    total = 0.0
    for run in previous:
        rate = run["particle_steps_per_s"]
        if rate <= 0:
            continue
        stepped = (run["warmup"] + run["repeat"] * run["steps"]) * run["n"] / rate
        overhead = max(0.0, run["wall_s"] - stepped)
        total += (warmup + repeat * steps) * n / rate + overhead * n / run["n"]
    return total


def report(run):
    log(f"  {worker_label(run['code'], run['workers'])}: "
        f"{run['particle_steps_per_s'] / 1e6:.3f} M particle-steps/s (median {run['median_s']:.3f} s"
        f" of {', '.join(f'{t:.3f}' for t in run['times_s'])}), {run['pair_contacts']} contacts, "
        f"{run['list_builds_timed']} list builds; wall {run['wall_s']} s, cpu {run['cpu_s']} s, "
        f"others {run['foreign_cpu_s']} s")


def steps_for(n, work, minimum):
    return max(minimum, int(round(work / n)))


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=float, nargs="+", default=[1e3, 1e4, 1e5, 1e6])
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--work", type=float, default=2e7,
                        help="particle-steps per timed run (steps = work / N, at least 10)")
    parser.add_argument("--warmup-work", type=float, default=2e7,
                        help="particle-steps of warm-up (at most 1000 steps, at least 10)")
    parser.add_argument("--rebuild-repeat", type=int, default=3,
                        help="repeats of the variant with lists rebuilt every step (0: none)")
    parser.add_argument("--rebuild-work", type=float, default=5e6,
                        help="particle-steps per timed run (and warm-up) of that variant")
    add_quiet_arguments(parser, retries=3)
    parser.add_argument("--budget-min", type=float, default=30,
                        help="skip sizes whose predicted time would exceed this total")
    parser.add_argument("--build-dir", default=str(ROOT / "build" / "openmp"))
    parser.add_argument("--cache-dir", default=str(ROOT / "perf" / "cache"))
    parser.add_argument("--out", default=str(ROOT / "perf" / "results" / "bench_spheres.json"))
    parser.add_argument("--plot", default=str(ROOT / "docs" / "img" / "bench_spheres.png"))
    parser.add_argument("--no-liggghts", action="store_true")
    parser.add_argument("--plot-only", action="store_true",
                        help="only redraw --plot from the results in --out")
    parser.add_argument("--table", action="store_true",
                        help="only print the results in --out as Markdown tables")
    args = parser.parse_args()
    if args.plot_only:
        plot_or_delegate(json.loads(Path(args.out).read_text()), args)
        return
    if args.table:
        print(markdown_tables(json.loads(Path(args.out).read_text())))
        return

    binary = Path(args.build_dir) / "bin" / "kdem_bench_openmp"
    if not binary.exists():
        sys.exit(f"{binary} not found: build first (make build)")
    liggghts = None if args.no_liggghts else find_liggghts()
    if not args.no_liggghts and not liggghts:
        log("LIGGGHTS not found (apt-get install liggghts, or scripts/deps.sh --bench): "
            "kdem only")
    cache_dir = Path(args.cache_dir)
    work_dir = cache_dir / "liggghts"
    started = time.time()
    budget_s = 60 * args.budget_min

    results = {
        "benchmark": "settled bed of spheres, Hertz-Mindlin with tangential history",
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "kdem_git": sh(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"]) or "unknown",
        "kdem_sources_modified": modified_sources(),
        "machine": machine_info(),
        "settings": {"repeat": args.repeat, "work_per_run": args.work,
                     "warmup_work": args.warmup_work, "threads": args.threads,
                     "rebuild_repeat": args.rebuild_repeat, "rebuild_work": args.rebuild_work,
                     "retries": args.retries, "foreign_limit": args.foreign_limit},
        "runs": [], "ratios": [], "skipped": [],
    }
    if liggghts:
        results["liggghts_binary"] = os.path.basename(liggghts)
        if mpi_launcher(2) is None:
            log("mpirun not found: LIGGGHTS runs with 1 process only")
    workers = sorted(set(args.threads))
    # The settled tile is built (and cached) once, outside the timings and the time budget.
    log("preparing the settled tile (cached in the cache folder after the first time)")
    run_kdem(binary, 1000, 0, 0, 0, max(workers), cache_dir)
    started = time.time()
    previous = []  # runs of the previous size, to predict the next one
    for size in sorted(int(s) for s in args.sizes):
        steps = steps_for(size, args.work, 10)
        warmup = min(1000, steps_for(size, args.warmup_work, 10))
        elapsed = time.time() - started - WAITED[0]
        if previous:
            predicted = 1.3 * sum(
                predict_seconds([r for r in previous if r["rebuild_every_step"] == rebuild], size,
                                steps_for(size, work, 10), min(1000, steps_for(size, work, 10)),
                                repeat)
                for rebuild, work, repeat in ((False, args.work, args.repeat),
                                              (True, args.rebuild_work, args.rebuild_repeat)))
            log(f"N = {size}: predicted {predicted / 60:.1f} min")
            if elapsed + predicted > budget_s:
                message = (f"N = {size} skipped: predicted {predicted / 60:.0f} min would exceed "
                           f"the {args.budget_min:.0f} min budget (--budget-min)")
                log(message)
                results["skipped"].append({"n": size, "reason": message})
                continue
        memory = available_memory_gib()
        needed = 2.5e-6 * size * (1 + len(workers))  # GiB: kdem ~1.2 kB, LIGGGHTS ~1 kB per sphere
        if memory is not None and needed > 0.8 * memory:
            message = f"N = {size} skipped: needs about {needed:.1f} GiB, {memory:.1f} available"
            log(message)
            results["skipped"].append({"n": size, "reason": message})
            continue
        data_file = cache_dir / f"bed_{size}.data"
        variants = [(False, steps, warmup, args.repeat)]
        if args.rebuild_repeat > 0:
            variants.append((True, steps_for(size, args.rebuild_work, 10),
                             min(1000, steps_for(size, args.rebuild_work, 10)),
                             args.rebuild_repeat))
        for rebuild, v_steps, v_warmup, v_repeat in variants:
            what = "lists rebuilt every step" if rebuild else "skin trigger"
            log(f"N = {size}, {what}: {v_warmup} warm-up steps, {v_repeat} x {v_steps} timed steps")
            pairs = {}
            for w in workers:
                record = measured_run(lambda: run_kdem(
                    binary, size, v_steps, v_warmup, v_repeat, w, cache_dir,
                    write_data=data_file if w == workers[0] and not rebuild else None,
                    rebuild=rebuild), args)
                results["runs"].append(record)
                report(record)
                pairs.setdefault(w, {})["kdem"] = record
                if not liggghts:
                    continue
                bed = dict(record["bed"], n=size)
                peer = measured_run(lambda: run_liggghts(
                    liggghts, data_file, bed, record["model"], v_steps, v_warmup, v_repeat, w,
                    work_dir, rebuild=rebuild), args)
                if peer is None:
                    log(f"  LIGGGHTS {w} procs: no mpirun, skipped")
                    continue
                results["runs"].append(peer)
                report(peer)
                pairs[w]["LIGGGHTS"] = peer
            for w, pair in pairs.items():
                if "kdem" in pair and "LIGGGHTS" in pair:
                    ratio = (pair["kdem"]["particle_steps_per_s"]
                             / pair["LIGGGHTS"]["particle_steps_per_s"])
                    results["ratios"].append({"n": size, "workers": w, "rebuild_every_step": rebuild,
                                              "kdem_over_liggghts": round(ratio, 3)})
                    log(f"  ratio kdem/LIGGGHTS with {w} worker(s): {ratio:.2f}")
            save(results, args)
        previous = [r for r in results["runs"] if r["n"] == size]
        save(results, args)
    results["total_wall_s"] = round(time.time() - started, 1)
    results["waited_for_quiet_s"] = round(WAITED[0], 1)
    save(results, args)
    plot_or_delegate(results, args)
    print(markdown_tables(results))
    log(f"wrote {args.out} and {args.plot} in {results['total_wall_s'] / 60:.1f} min")


def markdown_tables(results):
    """Throughput (million particle-steps/s, median) and kdem/LIGGGHTS ratios per variant."""
    lines = []
    for rebuild in (False, True):
        runs = [r for r in results["runs"] if r.get("rebuild_every_step", False) == rebuild]
        if not runs:
            continue
        columns = sorted({(r["code"], r["workers"]) for r in runs}, key=lambda c: (c[0] != "kdem", c[1]))
        lines.append("Lists rebuilt every step:" if rebuild else "Skin trigger (Verlet lists):")
        lines.append("")
        header = ["N", "steps x repeats"] + [worker_label(*c) for c in columns]
        ratio_workers = sorted({r["workers"] for r in results["ratios"]
                                if r.get("rebuild_every_step", False) == rebuild})
        header += [f"kdem/LIGGGHTS, {w} worker{'s' if w > 1 else ''}" for w in ratio_workers]
        header += ["contacts per sphere", "list builds timed (kdem / LIGGGHTS)"]
        lines.append("| " + " | ".join(header) + " |")
        lines.append("|" + "---|" * len(header))
        for n in sorted({r["n"] for r in runs}):
            at_n = [r for r in runs if r["n"] == n]
            row = [f"{n:,}", f"{at_n[0]['steps']} x {at_n[0]['repeat']}"]
            for code, workers in columns:
                match = [r for r in at_n if r["code"] == code and r["workers"] == workers]
                row.append(f"{match[0]['particle_steps_per_s'] / 1e6:.2f}" if match else "-")
            for w in ratio_workers:
                match = [r for r in results["ratios"] if r["n"] == n and r["workers"] == w
                         and r.get("rebuild_every_step", False) == rebuild]
                row.append(f"{match[0]['kdem_over_liggghts']:.2f}" if match else "-")
            kdem = [r for r in at_n if r["code"] == "kdem"]
            peer = [r for r in at_n if r["code"] == "LIGGGHTS"]
            row.append(f"{2 * kdem[0]['pair_contacts'] / n:.2f}" if kdem else "-")
            row.append(" / ".join(str(r[0]["list_builds_timed"]) if r else "-"
                                  for r in (kdem, peer)))
            lines.append("| " + " | ".join(row) + " |")
        lines.append("")
    return "\n".join(lines)


def plot_or_delegate(results, args):
    """Plots with matplotlib; when this interpreter has none, asks the system python3."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        system_python = "/usr/bin/python3"
        if os.path.exists(system_python) and os.path.realpath(system_python) != os.path.realpath(
                sys.executable):
            subprocess.run([system_python, __file__, "--plot-only", "--out", args.out,
                            "--plot", args.plot], check=True)
        else:
            log("matplotlib not found (apt-get install python3-matplotlib): no plot")
        return
    plot(results, Path(args.plot))


def save(results, args):
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    partial = out.with_suffix(".json.part")
    partial.write_text(json.dumps(results, indent=1) + "\n")
    partial.replace(out)


if __name__ == "__main__":
    main()
