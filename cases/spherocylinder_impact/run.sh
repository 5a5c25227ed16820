#!/bin/bash
# The spherocylinder impact case: writes the scenes (restitution 0.85 and 1), runs kdem, compares
# with the book's Eqs. 3.30-3.31 and writes results/result.json and results/spherocylinder_impact.png.
#
# usage: cases/spherocylinder_impact/run.sh [--kdem PATH]   (default: build/openmp/bin/kdem)
# Run outputs go to out/spherocylinder_impact/ (git-ignored). About 40 s on 2 cores.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
[ "${1:-}" = "--kdem" ] && KDEM="$(realpath "$2")"
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }
OUT="$ROOT/out/spherocylinder_impact"
mkdir -p "$OUT"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
for e in 0.85 1; do
  "$PYTHON" "$HERE/make_scene.py" "$OUT/spherocylinder_e$e.yaml" "$e"
  rm -rf "$OUT/e$e"
  "$KDEM" run "$OUT/spherocylinder_e$e.yaml" --out "$OUT/e$e" --quiet
done
"$PYTHON" "$HERE/analyse.py" "$OUT/e0.85" "$OUT/e1" "$HERE/results"
