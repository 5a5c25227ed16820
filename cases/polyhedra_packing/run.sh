#!/bin/bash
# The packing case of the book's Sect. 4.3.3 (Figs. 4.19-4.20): writes the cores (make_meshes.py),
# scales them to the volume of a 40 mm sphere (calibrate.py), writes the scene (make_scene.py),
# runs kdem, and writes results/result.json, results/polyhedra_packing_energy.png (analyse.py) and
# results/polyhedra_packing.png (render_packing.py).
#
# usage: cases/polyhedra_packing/run.sh [--kdem PATH] [--count N] [--width W] [--height H]
#                                      [--duration T]
#   defaults: build/openmp/bin/kdem and the book's set-up: 2000 particles in the 0.6 x 0.6 m
#   container, placed over its full 2 m, 4 s. The run reported in README.md:
#   --count 250 --width 0.3 --height 1.4 --duration 1.0 (about 15 min on one thread).
# Run outputs go to out/polyhedra_packing/ (git-ignored). One thread (OMP_NUM_THREADS=1 unless
# set); see README.md for the wall time.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
COUNT=2000
DURATION=4.0
HEIGHT=2.0
WIDTH=0.6
while [ $# -gt 0 ]; do
  case "$1" in
    --kdem) KDEM="$(realpath "$2")"; shift 2 ;;
    --count) COUNT="$2"; shift 2 ;;
    --duration) DURATION="$2"; shift 2 ;;
    --height) HEIGHT="$2"; shift 2 ;;
    --width) WIDTH="$2"; shift 2 ;;
    *) echo "unknown argument $1" >&2; exit 1 ;;
  esac
done
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }
OUT="$ROOT/out/polyhedra_packing"
SETUP="$OUT/setup"
RUN="$OUT/run_$COUNT"
mkdir -p "$SETUP"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
"$PYTHON" "$HERE/make_meshes.py" "$SETUP"
"$PYTHON" "$HERE/calibrate.py" "$KDEM" "$SETUP"
"$PYTHON" "$HERE/make_scene.py" "$SETUP/calibration.json" "$SETUP/packing_$COUNT.yaml" \
  --count "$COUNT" --duration "$DURATION" --height "$HEIGHT" --width "$WIDTH"
"$KDEM" check "$SETUP/packing_$COUNT.yaml" | tee "$OUT/check_$COUNT.txt"
rm -rf "$RUN"
"$KDEM" run "$SETUP/packing_$COUNT.yaml" --out "$RUN" --quiet
"$PYTHON" "$HERE/analyse.py" "$RUN" "$SETUP" "$HERE/results" "$WIDTH"
"$PYTHON" "$HERE/render_packing.py" "$RUN" "$SETUP" "$HERE/results/polyhedra_packing.png" \
  --box-width "$WIDTH"
