#!/bin/bash
# The mixed-family hopper (book Sect. 5.4.3): all six families discharging from one hopper.
# Runs kdem on mixed_families.yaml and writes results/result.json and
# results/mixed_families.png (cases/mixed_families/analyse.py).
#
# usage: cases/mixed_families/run.sh [--kdem PATH]   (default: build/openmp/bin/kdem)
# Run output goes to out/mixed_families/ (git-ignored); threads: OMP_NUM_THREADS (default 2).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
[ "${1:-}" = "--kdem" ] && KDEM="$(realpath "$2")"
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }
OUT="$ROOT/out/mixed_families"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-2}" OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
rm -rf "${OUT:?}"
"$KDEM" run "$HERE/mixed_families.yaml" --out "$OUT" --quiet
"$PYTHON" "$HERE/analyse.py" "$OUT" "$HERE/mixed_families.yaml" "$HERE/results"
