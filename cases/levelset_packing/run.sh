#!/bin/bash
# The level-set packing case (book Sect. 5.4.2): writes the meshes and the scene, calibrated so
# that every body has the volume of a 40 mm sphere (levelset_scene.py), runs kdem, and writes
# results/result.json and results/levelset_packing.png (analyse.py).
#
# usage: cases/levelset_packing/run.sh [--kdem PATH] [--count N] [--width W] [--height H]
#                                     [--duration T]
#   defaults: build/openmp/bin/kdem, 135 bodies in a 0.25 x 0.25 m container placed up to 4 m, 2 s.
# Run outputs go to out/levelset_packing/ (git-ignored); threads: OMP_NUM_THREADS (default 2).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
COUNT=135
DURATION=2.0
HEIGHT=4.0
WIDTH=0.25
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
OUT="$ROOT/out/levelset_packing"
SETUP="$OUT/setup"
RUN="$OUT/run_$COUNT"
mkdir -p "$SETUP"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-2}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
"$PYTHON" "$HERE/levelset_scene.py" "$KDEM" "$SETUP" "$SETUP/packing_$COUNT.yaml" \
  --count "$COUNT" --duration "$DURATION" --height "$HEIGHT" --width "$WIDTH"
"$KDEM" check "$SETUP/packing_$COUNT.yaml" | tee "$OUT/check_$COUNT.txt"
rm -rf "$RUN"
"$KDEM" run "$SETUP/packing_$COUNT.yaml" --out "$RUN" --quiet
"$PYTHON" "$HERE/analyse.py" "$RUN" "$SETUP" "$HERE/results" "$WIDTH"
