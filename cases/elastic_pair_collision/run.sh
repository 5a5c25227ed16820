#!/bin/bash
# The elastic pair collision case (book Sect. 4.3.1, Figs. 4.11-4.12): calibrates the four shapes'
# core scales to the volume of a 20 mm sphere, writes one scene per shape (and a finer sphere),
# runs kdem on each, repeats them at a quarter of the time step, and writes results/result.json
# and results/elastic_pair_collision.png.
#
# usage: cases/elastic_pair_collision/run.sh [--kdem PATH] [--no-time-step-check]
#   (default kdem: build/openmp/bin/kdem). Run outputs go to out/elastic_pair_collision/
#   (git-ignored). About 5 minutes on one thread (2 without the time-step check).
# A run that the engine's checks stop (exit status 3, failure.json) is reported and analysed as
# such; any other failure of kdem stops this script.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
TIME_STEP_CHECK=1
while [ $# -gt 0 ]; do
  case "$1" in
    --kdem) KDEM="$(realpath "$2")"; shift 2 ;;
    --no-time-step-check) TIME_STEP_CHECK=0; shift ;;
    *) echo "unknown argument $1" >&2; exit 1 ;;
  esac
done
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }
OUT="$ROOT/out/elastic_pair_collision"
mkdir -p "$OUT"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
"$PYTHON" "$HERE/calibrate.py" "$KDEM" "$OUT"

run_all() {  # folder time_step
  rm -rf "${OUT:?}/$1"
  "$PYTHON" "$HERE/make_scene.py" "$OUT/calibration.json" "$OUT/$1" "$2"
  for scene in "$OUT/$1"/*.yaml; do
    name="$(basename "$scene" .yaml)"
    rm -rf "${OUT:?}/$1/$name"
    status=0
    "$KDEM" run "$scene" --out "$OUT/$1/$name" --quiet || status=$?
    if [ "$status" = 3 ]; then
      echo "$1/$name: stopped by the engine's checks (see failure.json)"
    elif [ "$status" != 0 ]; then
      echo "$1/$name: kdem failed with status $status" >&2; exit 1
    fi
  done
}
run_all dt1e-6 1e-6
[ "$TIME_STEP_CHECK" = 1 ] && run_all dt2.5e-7 2.5e-7
"$PYTHON" "$HERE/analyse.py" "$OUT" "$HERE/results"
