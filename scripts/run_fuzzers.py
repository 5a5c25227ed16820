#!/usr/bin/env python3
"""Runs kdem's libFuzzer targets (preset fuzz) and writes what they did.

Each target runs on its own working corpus (out/fuzz/corpus/<target>, kept between runs so that
later runs start from what earlier ones found), merged with the seed corpus of tests/fuzz/corpus
and the inputs that once failed (tests/fuzz/regressions), which every run thus replays under the
sanitizers.
A run stops after --runs executions or --seconds seconds, whichever comes first, or at the first
crash, hang (--timeout per input), leak or sanitizer report; the input that caused it is left in
out/fuzz/artifacts/<target>/ (copy it into tests/fuzz/regressions/<target>/ to make it a
regression test once fixed).

Writes out/fuzz/results.json (per target: executions, seconds, executions per second, peak
memory, corpus size, exit status, artifacts) and exits non-zero when any target failed.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FUZZ_DIR = ROOT / "tests" / "fuzz"
TARGETS = {
    # name: largest input in bytes (the seeds are at most 10 kB)
    "scene_loader": 16384,
    "mesh_reader": 16384,
    # edits of a real checkpoint: 16 edits of at most 16 bytes each
    "checkpoint_reader": 256,
}
# libFuzzer's per-input leak check counts mallocs against frees; HDF5 keeps freed blocks on
# lists of its own, so every checkpoint input looked like a leak and was run again under
# LeakSanitizer (a third of the time). Leaks are still found: LeakSanitizer checks the whole
# process at its end.
PER_INPUT_LEAK_CHECK = {"scene_loader": True, "mesh_reader": True, "checkpoint_reader": False}


def parse_stats(log):
    """libFuzzer's -print_final_stats lines: stat::name: value."""
    stats = {}
    for name, value in re.findall(r"^stat::(\w+):\s+(\d+)", log, re.MULTILINE):
        stats[name] = int(value)
    return stats


def regressions(name):
    """The inputs that once failed: run first, under the sanitizers, by every fuzz run."""
    folder = FUZZ_DIR / "regressions" / name
    return [str(folder)] if folder.is_dir() else []


def worker_command(binary, name, args, corpus, artifacts, runs, worker):
    return [
        str(binary),
        f"-runs={runs}",
        f"-max_total_time={args.seconds}",
        f"-timeout={args.timeout}",
        f"-rss_limit_mb={args.rss_limit_mb}",
        f"-max_len={TARGETS[name]}",
        f"-artifact_prefix={artifacts}/",
        "-print_final_stats=1",
        f"-detect_leaks={int(PER_INPUT_LEAK_CHECK[name])}",
        # libFuzzer takes 0 as "pick one"; workers with a fixed seed each get their own
        f"-seed={args.seed + worker if args.seed else 0}",
        str(corpus),
        str(FUZZ_DIR / "corpus" / name),
    ] + regressions(name)


def run_target(binary, name, args, out):
    """Runs --workers fuzzer processes on one shared working corpus (each reloads what the
    others add); --runs executions in all, shared out evenly."""
    corpus = out / "corpus" / name
    artifacts = out / "artifacts" / name
    corpus.mkdir(parents=True, exist_ok=True)
    if artifacts.exists():
        shutil.rmtree(artifacts)
    artifacts.mkdir(parents=True)
    env = dict(os.environ)
    env["KDEM_FUZZ_BASE_DIR"] = str(FUZZ_DIR / "scene_files")
    env.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=0")
    env.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
    # The targets write their scratch files here; a private folder per run.
    scratch = tempfile.mkdtemp(prefix=f"kdem-fuzz-{name}-")
    env["TMPDIR"] = scratch
    workers = args.workers
    runs = [args.runs if args.runs < 0 else args.runs // workers + (w < args.runs % workers)
            for w in range(workers)]
    logs = [out / (f"{name}.log" if workers == 1 else f"{name}.{w}.log") for w in range(workers)]
    start = time.monotonic()
    processes = []
    for w in range(workers):
        log = open(logs[w], "w")
        command = worker_command(binary, name, args, corpus, artifacts, runs[w], w)
        processes.append((subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=env),
                          log))
    # A worker that fails stops the others: its input is what the run is for.
    while any(process.poll() is None for process, _ in processes):
        if any(process.poll() not in (None, 0) for process, _ in processes):
            for process, _ in processes:
                if process.poll() is None:
                    process.terminate()
        time.sleep(0.5)
    statuses = [process.wait() for process, _ in processes]
    for _, log in processes:
        log.close()
    seconds = time.monotonic() - start
    shutil.rmtree(scratch, ignore_errors=True)
    stats = [parse_stats(path.read_text(errors="replace")) for path in logs]
    executions = sum(st.get("number_of_executed_units", 0) for st in stats)
    status = next((code for code in statuses if code != 0), 0)
    found = sorted(p.name for p in artifacts.iterdir())
    peak = [st["peak_rss_mb"] for st in stats if "peak_rss_mb" in st]
    return {
        "target": name,
        "exit_status": status,
        "workers": workers,
        "executions": executions,
        "seconds": round(seconds, 1),
        "executions_per_second": round(executions / seconds) if seconds > 0 else 0,
        "peak_rss_mb": max(peak) if peak else None,
        "corpus_files": sum(1 for _ in corpus.iterdir()),
        "artifacts": found,
        "logs": [str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p) for p in logs],
        "ok": status == 0 and not found,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", default=str(ROOT / "build" / "fuzz" / "bin"))
    parser.add_argument("--out", default=str(ROOT / "out" / "fuzz"))
    parser.add_argument("--targets", default=",".join(TARGETS))
    parser.add_argument("--seconds", type=int, default=60, help="time limit per target (0: none)")
    parser.add_argument("--runs", type=int, default=-1, help="executions per target (-1: no limit)")
    parser.add_argument("--timeout", type=int, default=10, help="seconds one input may take")
    parser.add_argument("--rss-limit-mb", type=int, default=2048)
    parser.add_argument("--seed", type=int, default=0,
                        help="random seed (0: a new one each run); CI fixes it, so that a short "
                             "run tries the same inputs every time")
    parser.add_argument("--workers", type=int, default=1,
                        help="fuzzer processes per target, sharing one corpus")
    args = parser.parse_args()
    if args.workers < 1:
        parser.error("--workers must be at least 1")
    if args.seconds <= 0 and args.runs < 0:
        parser.error("give --seconds or --runs (a run without either never ends)")
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    results = []
    for name in args.targets.split(","):
        if name not in TARGETS:
            parser.error(f"--targets: unknown target '{name}' (known: {', '.join(TARGETS)})")
        binary = Path(args.bin) / f"fuzz_{name}"
        if not binary.exists():
            sys.exit(f"{binary}: not built (make fuzz builds it)")
        result = run_target(binary, name, args, out)
        results.append(result)
        verdict = "ok" if result["ok"] else f"FAILED (exit {result['exit_status']}, see {', '.join(result['logs'])})"
        print(f"fuzz {name}: {result['executions']} executions in {result['seconds']} s "
              f"({result['executions_per_second']}/s), corpus {result['corpus_files']} files: {verdict}")
    summary = {"settings": {"seconds": args.seconds, "runs": args.runs, "timeout": args.timeout,
                            "rss_limit_mb": args.rss_limit_mb, "workers": args.workers,
                            "seed": args.seed},
               "targets": results}
    with tempfile.NamedTemporaryFile("w", dir=out, delete=False, suffix=".tmp") as tmp:
        json.dump(summary, tmp, indent=2)
    os.replace(tmp.name, out / "results.json")
    return 0 if all(r["ok"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
