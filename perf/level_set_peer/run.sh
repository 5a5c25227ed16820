#!/bin/bash
# kdem's level-set bodies beside Yade's level-set DEM (docs/performance.md, section 29), one
# thread each: (1) the accuracy bench's 300 pairs per shape, static; (2) two bodies colliding,
# 10 eccentric elastic collisions per shape; (3) a small packing of 36 bodies, at three time steps
# in each code. (2) and (3) run the same scenes in kdem's exact superquadric family as the
# reference. Writes
# perf/results/level_set_peer_{pairs_kdem,pairs_yade,impact,packing}.json.
#
# usage: perf/level_set_peer/run.sh [pairs] [impact] [packing]   (default: all three)
# Needs build/openmp (kdem, kdem_bench_level_set_accuracy) and Debian's `yade`
# (apt-get install yade). Runs go to out/level_set_peer/ (git-ignored). About 25 minutes (Yade's three packings: 15).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
BIN="$ROOT/build/openmp/bin"
PYTHON="${PYTHON:-/usr/bin/python3}"
RESULTS="$ROOT/perf/results"
OUT="$ROOT/out/level_set_peer"
for tool in "$BIN/kdem" "$BIN/kdem_bench_level_set_accuracy"; do
  [ -x "$tool" ] || { echo "no $tool: build the OpenMP preset first" >&2; exit 1; }
done
command -v yade > /dev/null || { echo "no yade: apt-get install yade (Debian 12: 2023.02a)" >&2; exit 1; }
export OMP_NUM_THREADS=1 OMP_PROC_BIND=false
mkdir -p "$OUT"

yade_run() { yade -j1 -n -x "$@" > "$OUT/yade.log" 2>&1 || { tail -20 "$OUT/yade.log" >&2; exit 1; }; }

# Runs every kdem scene PREFIX_<scene>.yaml of the folder.
kdem_runs() {
  local folder="$1" prefix="$2"; shift 2
  for scene in "$@"; do
    rm -rf "${folder:?}/${prefix}_$scene"
    "$BIN/kdem" run "$folder/${prefix}_$scene.yaml" --out "$folder/${prefix}_$scene" --quiet
  done
}

# Writes the scenes, reads the engine's bounding radii from one-step runs, writes them again
# with every body placed by those radii, and runs them.
placed_runs() {
  local script="$1" folder="$2" prefix="$3"; shift 3
  mkdir -p "$folder"
  "$PYTHON" "$HERE/$script" scenes "$folder"
  kdem_runs "$folder" "$prefix" "$@"
  "$PYTHON" "$HERE/$script" radii "$folder" "$folder/radii.json"
  "$PYTHON" "$HERE/$script" scenes "$folder" "$folder/radii.json"
  kdem_runs "$folder" "$prefix" "$@"
}

pairs() {
  "$BIN/kdem_bench_level_set_accuracy" --quick --repeat 3 --pairs 300 \
    --out "$RESULTS/level_set_peer_pairs_kdem.json" --pairs-out "$OUT/pairs.json"
  yade_run "$HERE/yade_pairs.py" "$OUT/pairs.json" "$RESULTS/level_set_peer_pairs_yade.json" 3
}

impact() {
  local folder="$OUT/impact"
  placed_runs impact.py "$folder" impact level_set exact exact_stiff
  yade_run "$HERE/yade_impact.py" "$folder/impact_case.json" "$folder/yade_impact.json"
  "$PYTHON" "$HERE/impact.py" analyse "$folder" "$folder/yade_impact.json" \
    "$RESULTS/level_set_peer_impact.json" > /dev/null
}

packing() {
  local folder="$OUT/packing" factors="1.0 0.9 0.8"
  placed_runs packing.py "$folder" packing $(for f in $factors; do echo level_set_$f exact_$f; done)
  for f in $factors; do
    yade_run "$HERE/yade_packing.py" "$folder/packing_case.json" "$folder/yade_packing_$f.json" "$f"
  done
  "$PYTHON" "$HERE/packing.py" poses "$folder" "$folder/poses.txt"
  "$BIN/kdem_bench_level_set_accuracy" --pairs-in "$folder/poses.txt" \
    --pairs-eval-out "$folder/poses_evaluated.csv"
  "$PYTHON" "$HERE/packing.py" analyse "$folder" "$folder/poses.txt" \
    "$folder/poses_evaluated.csv" "$RESULTS/level_set_peer_packing.json" > /dev/null
}

for part in ${@:-pairs impact packing}; do
  case "$part" in
    pairs | impact | packing) "$part"; echo "$part: done" ;;
    *) echo "unknown part $part (pairs, impact, packing)" >&2; exit 2 ;;
  esac
done
