#!/usr/bin/env bash
# Whole-program checks run by ctest:
#   run_checks.sh restart  KDEM COMPARE SCENE WORKDIR   2N steps == N steps + checkpoint + restart + N
#   run_checks.sh threads  KDEM COMPARE SCENE WORKDIR   OpenMP with 1 and 2 threads, bit for bit
#   run_checks.sh backends KDEM_A KDEM_B COMPARE SCENE WORKDIR   two backends, bit for bit
#   run_checks.sh errors   KDEM ERRORS_DIR WORKDIR       every bad scene: message, exit code, no output
set -euo pipefail
mode=$1
shift
export OMP_PROC_BIND=false

fail() { echo "FAILED: $*" >&2; exit 1; }

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
      expect=$(sed -n '1s/^# expect: //p' "$scene")
      [ -n "$expect" ] || fail "$scene has no '# expect:' first line"
      out="$work/$(basename "$scene" .yaml)"
      set +e
      message=$("$kdem" run "$scene" --out "$out" --quiet 2>&1)
      code=$?
      set -e
      [ "$code" -ne 0 ] || fail "$scene: exit code 0"
      grep -qF -- "$expect" <<<"$message" || fail "$scene: message '$message' lacks '$expect'"
      [ ! -e "$out" ] || fail "$scene: output directory $out was written"
      count=$((count + 1))
    done
    [ "$count" -gt 0 ] || fail "no bad scenes in $errors"
    echo "$count bad scenes rejected with their messages"
    ;;
  *)
    fail "unknown mode $mode"
    ;;
esac
