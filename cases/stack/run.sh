#!/bin/bash
# The vertical stack case (book Sect. 4.3.3, Fig. 4.18): writes the scene and the plate cores,
# lets kdem set the bodies up (step 0), moves them into their stacks in that checkpoint, runs the
# settling from there, and compares the contact forces with the weights above them
# (results/result.json, results/stack.png).
#
# usage: cases/stack/run.sh [--kdem PATH]   (default: build/openmp/bin/kdem)
# Run outputs go to out/stack/ (git-ignored).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
[ "${1:-}" = "--kdem" ] && KDEM="$(realpath "$2")"
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }
OUT="$ROOT/out/stack"
mkdir -p "$OUT"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
"$PYTHON" "$HERE/make_scene.py" "$OUT"
rm -rf "$OUT/step0" "$OUT/run"
# Step 0 only: the bodies as the engine creates them (apart), and their checkpoint.
"$KDEM" run "$OUT/stack.yaml" --out "$OUT/step0" --steps 0 --quiet
"$PYTHON" "$HERE/place_stack.py" "$OUT/step0" "$OUT/stacked.h5"
"$KDEM" run "$OUT/stack.yaml" --out "$OUT/run" --restart "$OUT/stacked.h5" --quiet
"$PYTHON" "$HERE/analyse.py" "$OUT/run" "$HERE/results"
