#!/bin/bash
# The level-set wall impact case (book Sect. 5.4.1; its own data are lost, so the protocol is the
# chapter 4 impact's): writes the scenes, reads the bodies' bounding radii from one-step runs,
# places every body just above the plane, runs kdem on the level-set bodies and on the
# superquadric family's reference, and writes results/result.json and
# results/levelset_wall_impact.png.
#
# usage: cases/levelset_wall_impact/run.sh [--kdem PATH]   (default: build/openmp/bin/kdem)
# Run outputs go to out/levelset_wall_impact/ (git-ignored). About 20 s on one thread.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
[ "${1:-}" = "--kdem" ] && KDEM="$(realpath "$2")"
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }
OUT="$ROOT/out/levelset_wall_impact"
mkdir -p "$OUT"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
run_both() {
  for scene in levelset_wall_impact superquadric_reference; do
    rm -rf "${OUT:?}/$scene"
    "$KDEM" run "$OUT/$scene.yaml" --out "$OUT/$scene" --quiet
  done
}
"$PYTHON" "$HERE/make_scene.py" "$OUT"
run_both
"$PYTHON" "$HERE/bounding_radii.py" "$OUT" "$OUT/radii.json"
"$PYTHON" "$HERE/make_scene.py" "$OUT" "$OUT/radii.json"
run_both
"$PYTHON" "$HERE/analyse.py" "$OUT" "$HERE/results"
