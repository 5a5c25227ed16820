#!/bin/bash
# Superquadric validation cases: runs kdem and the post-processing scripts.
#
# usage: cases/superquadric/run_all.sh [CASE ...] [--kdem PATH]
#   CASE: two_ellipsoids, cylinder_drop, free_rotation, ellipsoid_packing, or all (default)
#   --kdem PATH: the kdem program (default: build/openmp/bin/kdem of the repository)
# Run outputs go to out/superquadric/<case>/ (git-ignored), plots to docs/img/superquadric_*.png.
#
# Threads: the first three cases have 1 to 9 particles and run on one OpenMP thread (more
# threads only add synchronisation); the packing runs on KDEM_PACKING_THREADS (default 2).
# Set OMP_NUM_THREADS beforehand to force one count for all.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KDEM="$ROOT/build/openmp/bin/kdem"
PYTHON="${PYTHON:-/usr/bin/python3}"
CASES=()
while [ $# -gt 0 ]; do
  case "$1" in
    --kdem) KDEM="$(realpath "$2")"; shift 2 ;;
    --kdem=*) KDEM="$(realpath "${1#--kdem=}")"; shift ;;
    -h|--help) sed -n '2,11p' "${BASH_SOURCE[0]}"; exit 0 ;;
    all) CASES+=(two_ellipsoids cylinder_drop free_rotation ellipsoid_packing); shift ;;
    two_ellipsoids|cylinder_drop|free_rotation|ellipsoid_packing) CASES+=("$1"); shift ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done
[ ${#CASES[@]} -eq 0 ] && CASES=(two_ellipsoids cylinder_drop free_rotation ellipsoid_packing)
[ -x "$KDEM" ] || { echo "no kdem program at $KDEM (build it or pass --kdem PATH)" >&2; exit 1; }

OUT="$ROOT/out/superquadric"
IMG="$ROOT/docs/img"
mkdir -p "$OUT" "$IMG"
export OMP_PROC_BIND="${OMP_PROC_BIND:-false}"
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
SMALL_THREADS="${OMP_NUM_THREADS:-1}"
PACKING_THREADS="${OMP_NUM_THREADS:-${KDEM_PACKING_THREADS:-2}}"

run() {  # run THREADS SCENE OUTPUT_DIR
  echo "== kdem run $2 -> $3"
  rm -rf "$3"
  OMP_NUM_THREADS="$1" "$KDEM" run "$2" --out "$3" --quiet
}

for case in "${CASES[@]}"; do
  dir="$HERE/$case"
  out="$OUT/$case"
  mkdir -p "$out"
  case "$case" in
    two_ellipsoids)
      run "$SMALL_THREADS" "$dir/head_on.yaml" "$out/head_on"
      run "$SMALL_THREADS" "$dir/oblique.yaml" "$out/oblique"
      "$PYTHON" "$dir/plot_two_ellipsoids.py" "$out/head_on" "$out/oblique" "$IMG/superquadric_two_ellipsoids.png"
      ;;
    cylinder_drop)
      "$PYTHON" "$dir/make_scenes.py" "$dir"
      run "$SMALL_THREADS" "$dir/drop_e1.yaml" "$out/drop_e1"
      run "$SMALL_THREADS" "$dir/drop_e05.yaml" "$out/drop_e05"
      "$PYTHON" "$dir/plot_cylinder_drop.py" "$out/drop_e1" "$out/drop_e05" "$IMG/superquadric_cylinder_drop.png"
      ;;
    free_rotation)
      run "$SMALL_THREADS" "$dir/free_rotation.yaml" "$out/free_rotation"
      "$PYTHON" "$dir/plot_free_rotation.py" "$out/free_rotation" "$IMG/superquadric_free_rotation.png"
      ;;
    ellipsoid_packing)
      "$PYTHON" "$dir/make_scenes.py" "$dir"
      args=()
      for alpha in 1 1.25 1.5 2; do
        run "$PACKING_THREADS" "$dir/packing_a$alpha.yaml" "$out/packing_a$alpha"
        args+=("$alpha:$out/packing_a$alpha")
      done
      "$PYTHON" "$dir/plot_packing.py" "$IMG/superquadric_ellipsoid_packing.png" "${args[@]}"
      ;;
  esac
  echo "== $case: summary in $out/summary.txt"
done
