#!/usr/bin/env bash
# A function template (or inline function) that holds a KOKKOS_LAMBDA must be compiled in one
# translation unit of a CUDA build: nvcc gives each unit its own hidden helper for an extended
# lambda, and where two units instantiate the same function the linker keeps one copy, which can
# call the other unit's helper before it is set (a call through a null pointer at run time).
# Lists each such function with the object files that hold it, and fails if there is any.
#   scripts/check_cuda_lambdas.sh build/cuda
set -euo pipefail
build=${1:?usage: check_cuda_lambdas.sh BUILD_DIR}
listing=$(mktemp)
objects_file=$(mktemp)
trap 'rm -f "$listing" "$objects_file"' EXIT
# The objects that the build's libraries and programs are made of (CMake's link.txt of each
# target, paths relative to its directory), not every object file lying in the build folder: one
# left from a source since removed is part of nothing.
while IFS= read -r link; do
  base=${link%%/CMakeFiles/*}
  grep -o '[^ ]*\.o\b' "$link" | sed "s|^|$base/|" >>"$objects_file" || true
done < <(find "$build" -name link.txt)
sort -u -o "$objects_file" "$objects_file"
while IFS= read -r object; do
  nm -C "$object" 2>/dev/null | grep '__nv_hdl_helper<__nv_dl_tag<' |
    sed -n 's/.*__nv_dl_tag<.*, &(\(.*\)), [0-9]*u\?>.*/\1/p' | sort -u |
    sed "s|\$|\t${object#"$build"/}|" >>"$listing" || true
done <"$objects_file"
objects=$(wc -l <"$objects_file")
[ "$objects" -gt 0 ] || { echo "check_cuda_lambdas: no object files under $build" >&2; exit 2; }
duplicated=$(cut -f1 "$listing" | sort | uniq -d)
if [ -n "$duplicated" ]; then
  echo "check_cuda_lambdas: functions holding an extended lambda compiled in more than one unit:"
  while IFS= read -r function; do
    echo "  $function"
    awk -F'\t' -v f="$function" '$1 == f {print "    " $2}' "$listing"
  done <<<"$duplicated"
  echo "Instantiate each in one unit (extern template in the header; see kernels/integrate.hpp)."
  exit 1
fi
echo "check_cuda_lambdas: $(cut -f1 "$listing" | sort -u | wc -l) functions holding extended lambdas in $objects objects, each in one unit"
