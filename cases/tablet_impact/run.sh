#!/bin/bash
# The tablet impact case: writes the core mesh and the scene, runs kdem, compares with the book's
# Eqs. 4.25-4.27 and writes results/result.json and results/tablet_impact.png.
#
# usage: cases/tablet_impact/run.sh [--kdem PATH]   (default: build/openmp/bin/kdem)
# Run outputs go to out/tablet_impact/ (git-ignored). About 10 s on one thread.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
[ "${1:-}" = "--kdem" ] && KDEM="$(realpath "$2")"
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }
OUT="$ROOT/out/tablet_impact"
mkdir -p "$OUT"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
"$PYTHON" "$HERE/make_tablet.py" "$OUT/tablet.obj"
"$PYTHON" "$HERE/make_scene.py" "$OUT/tablet_impact.yaml"
rm -rf "$OUT/run"
"$KDEM" run "$OUT/tablet_impact.yaml" --out "$OUT/run" --quiet
"$PYTHON" "$HERE/analyse.py" "$OUT/run" "$HERE/results"
