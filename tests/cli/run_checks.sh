#!/usr/bin/env bash
# Whole-program checks run by ctest:
#   run_checks.sh restart  KDEM COMPARE SCENE WORKDIR   2N steps == N steps + checkpoint + restart + N
#   run_checks.sh threads  KDEM COMPARE SCENE WORKDIR   OpenMP with 1 and 2 threads, bit for bit
#   run_checks.sh backends KDEM_A KDEM_B COMPARE SCENE WORKDIR   two backends, bit for bit
#   run_checks.sh errors   KDEM ERRORS_DIR WORKDIR       every bad scene: message, exit code, no output
#   run_checks.sh failures KDEM FAILURES_DIR WORKDIR     every run gone wrong: stopped with exit code
#                                                       3, its message, the state dump, no run.json
#   run_checks.sh leaving  KDEM SCENE WORKDIR           particles leaving the domain: removed,
#                                                       counted in run.json and series.csv, warned
set -euo pipefail
mode=$1
shift
export OMP_PROC_BIND=false

fail() { echo "FAILED: $*" >&2; exit 1; }

# The message a bad or failing scene must give: its first line, "# expect: MESSAGE".
expected_message() {
  local expect
  expect=$(sed -n '1s/^# expect: //p' "$1")
  [ -n "$expect" ] || fail "$1 has no '# expect:' first line"
  echo "$expect"
}

# Runs KDEM run SCENE --out OUT --quiet; sets `message` (stdout and stderr) and `code`.
run_capturing() {
  set +e
  message=$("$1" run "$2" --out "$3" --quiet 2>&1)
  code=$?
  set -e
}

case "$mode" in
  restart)
    kdem=$1 compare=$2 scene=$3 work=$4
    rm -rf "$work" && mkdir -p "$work"
    "$kdem" run "$scene" --out "$work/straight" --quiet
    steps=$(python3 -c "import json;print(json.load(open('$work/straight/run.json'))['steps'])")
    half=$((steps / 2))
    "$kdem" run "$scene" --out "$work/first_half" --steps "$half" --quiet
    "$kdem" run "$scene" --out "$work/second_half" --restart "$work/first_half/checkpoint.h5" --quiet
    "$compare" "$work/straight/checkpoint.h5" "$work/second_half/checkpoint.h5"
    ;;
  threads)
    kdem=$1 compare=$2 scene=$3 work=$4
    rm -rf "$work" && mkdir -p "$work"
    OMP_NUM_THREADS=1 "$kdem" run "$scene" --out "$work/one" --quiet
    OMP_NUM_THREADS=2 "$kdem" run "$scene" --out "$work/two" --quiet
    "$compare" "$work/one/checkpoint.h5" "$work/two/checkpoint.h5"
    ;;
  backends)
    kdem_a=$1 kdem_b=$2 compare=$3 scene=$4 work=$5
    rm -rf "$work" && mkdir -p "$work"
    OMP_NUM_THREADS=2 "$kdem_a" run "$scene" --out "$work/a" --quiet
    OMP_NUM_THREADS=2 "$kdem_b" run "$scene" --out "$work/b" --quiet
    "$compare" "$work/a/checkpoint.h5" "$work/b/checkpoint.h5"
    ;;
  errors)
    kdem=$1 errors=$2 work=$3
    rm -rf "$work" && mkdir -p "$work"
    count=0
    for scene in "$errors"/*.yaml; do
      expect=$(expected_message "$scene")
      out="$work/$(basename "$scene" .yaml)"
      run_capturing "$kdem" "$scene" "$out"
      [ "$code" -ne 0 ] || fail "$scene: exit code 0"
      grep -qF -- "$expect" <<<"$message" || fail "$scene: message '$message' lacks '$expect'"
      [ ! -e "$out" ] || fail "$scene: output directory $out was written"
      count=$((count + 1))
    done
    [ "$count" -gt 0 ] || fail "no bad scenes in $errors"
    echo "$count bad scenes rejected with their messages"
    ;;
  failures)
    kdem=$1 failures=$2 work=$3
    rm -rf "$work" && mkdir -p "$work"
    count=0
    for scene in "$failures"/*.yaml; do
      expect=$(expected_message "$scene")
      out="$work/$(basename "$scene" .yaml)"
      mkdir -p "$out" && echo '{"stale": true}' >"$out/run.json"
      run_capturing "$kdem" "$scene" "$out"
      [ "$code" -eq 3 ] || fail "$scene: exit code $code, expected 3; message: $message"
      grep -qF -- "$expect" <<<"$message" || fail "$scene: message '$message' lacks '$expect'"
      for file in failure_checkpoint.h5 failure_particles.vtu failure.json series.csv; do
        [ -s "$out/$file" ] || fail "$scene: no $file written"
      done
      [ ! -e "$out/run.json" ] || fail "$scene: a run.json is left in $out"
      python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['trigger'] and d['particles'] and d['likely_causes']" \
        "$out/failure.json" || fail "$scene: failure.json incomplete"
      count=$((count + 1))
    done
    [ "$count" -gt 0 ] || fail "no failing scenes in $failures"
    echo "$count runs gone wrong stopped with their messages"
    ;;
  leaving)
    kdem=$1 scene=$2 work=$3
    rm -rf "$work" && mkdir -p "$work"
    message=$("$kdem" run "$scene" --out "$work" 2>&1 >/dev/null)
    grep -q "left the domain by t = .* and were removed (ids " <<<"$message" ||
      fail "no warning naming the lost particles in: $message"
    python3 - "$work" <<'PY'
import csv, json, sys
out = sys.argv[1]
run = json.load(open(out + "/run.json"))
lost = run["extra"]["lost_count"]
assert lost > 0, "nothing counted as lost"
assert run["particles"] + lost == 20, (run["particles"], lost)
rows = list(csv.DictReader(open(out + "/series.csv")))
assert float(rows[-1]["lost_count"]) == lost, rows[-1]
assert float(rows[-1]["lost_mass"]) > 0
print(f"{lost} of 20 particles left the domain, removed and counted")
PY
    ;;
  *)
    fail "unknown mode $mode"
    ;;
esac
