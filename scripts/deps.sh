#!/usr/bin/env bash
# Dependencies of kdem.
#
#   scripts/deps.sh                      apt packages + Kokkos/Kokkos Kernels "openmp"
#   scripts/deps.sh --cuda               ... and the "cuda-sm90" and "cuda-sm80" variants
#                                        (only where nvcc is found)
#   scripts/deps.sh --bench              ... and the peer codes used by perf/ (liggghts)
#   scripts/deps.sh --fuzz               ... and clang with libFuzzer and the "fuzz" variant
#                                        (Kokkos alone, Serial, built by clang: make fuzz)
#   scripts/deps.sh --variant V          build only variant V (openmp, cuda-sm90, cuda-sm80, fuzz)
#   scripts/deps.sh --no-apt             do not check/install Debian packages
#   scripts/deps.sh --no-kokkos          only the Debian packages (own Kokkos given elsewhere)
#   scripts/deps.sh --find-nvcc          print the nvcc that would be used (exit 1: none)
#   scripts/deps.sh --print-root V       print the install prefix of variant V and exit
#                                        (exit status 1 if it is not built yet)
#
# Kokkos 3.4.01 and Kokkos Kernels 3.4.01 come from Debian's trilinos 13.2 source
# package (only packages/kokkos and packages/kokkos-kernels are kept), patched with
# third_party/kokkos/*.patch and installed into
#   ${KDEM_CACHE:-$HOME/.cache/kdem}/kokkos-<variant>-<key>
# where <key> hashes the patches, the build recipe below and the compiler versions.
# A variant whose prefix holds the completion stamp is not rebuilt.
#
# Log output goes to stderr.  stdout receives only the install prefixes of the
# variants handled, one per line (so the last line is the last variant's prefix).
#
# Environment: KDEM_CACHE (cache folder), KDEM_DEPS_JOBS (parallel build jobs, 2),
# CUDA_ROOT (CUDA toolkit; otherwise nvcc from PATH or /usr/local/cuda/bin).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SELF="$ROOT/scripts/deps.sh"
PATCH_DIR="$ROOT/third_party/kokkos"
CACHE=${KDEM_CACHE:-$HOME/.cache/kdem}
JOBS=${KDEM_DEPS_JOBS:-2}
HOST_CXX=g++
FUZZ_CXX=clang++
STAMP=.kdem-complete

APT_PACKAGES=(g++ make cmake libeigen3-dev libhdf5-dev libvtk9-dev libgtest-dev
  libyaml-cpp-dev libqhull-dev ccache python3-matplotlib python3-h5py dpkg-dev xz-utils valgrind binutils)
BENCH_PACKAGES=(liggghts)
FUZZ_PACKAGES=(clang libclang-rt-14-dev)

log() { echo "[deps] $*" >&2; }
die() { echo "[deps] error: $*" >&2; exit 1; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"
  elif command -v sudo >/dev/null 2>&1; then sudo "$@"
  else die "need root (or sudo) to run: $*"
  fi
}

# ---------------------------------------------------------------- arguments
want_cuda=0 want_bench=0 want_fuzz=0 do_apt=1 do_kokkos=1 print_nvcc=0 print_root="" only_variant=""
while [ $# -gt 0 ]; do
  case "$1" in
    --cuda) want_cuda=1 ;;
    --bench) want_bench=1 ;;
    --fuzz) want_fuzz=1 ;;
    --no-apt) do_apt=0 ;;
    --no-kokkos) do_kokkos=0 ;;
    --find-nvcc) print_nvcc=1 ;;
    --variant) [ $# -ge 2 ] || die "--variant needs a value"; only_variant=$2; shift ;;
    --print-root) [ $# -ge 2 ] || die "--print-root needs a variant"; print_root=$2; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$SELF" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown argument: $1 (see --help)" ;;
  esac
  shift
done

find_nvcc() {
  if [ -n "${CUDA_ROOT:-}" ] && [ -x "$CUDA_ROOT/bin/nvcc" ]; then echo "$CUDA_ROOT/bin/nvcc"
  elif command -v nvcc >/dev/null 2>&1; then command -v nvcc
  elif [ -x /usr/local/cuda/bin/nvcc ]; then echo /usr/local/cuda/bin/nvcc
  else return 1
  fi
}

if [ "$print_nvcc" -eq 1 ]; then find_nvcc; exit $?; fi

check_variant_name() {
  case "$1" in
    openmp|cuda-sm90|cuda-sm80|fuzz) ;;
    *) die "unknown variant '$1' (openmp, cuda-sm90, cuda-sm80, fuzz)" ;;
  esac
}

# ------------------------------------------------------------ cache key
# The key covers everything that changes the installed bytes: the patches, the
# build recipe (the text between the BUILD RECIPE markers of this file) and the
# versions of the compilers and of CMake.
variant_key() {
  local variant=$1
  {
    echo "variant=$variant"
    cat "$PATCH_DIR"/*.patch
    sed -n '/^# >>> BUILD RECIPE/,/^# <<< BUILD RECIPE/p' "$SELF"
    "$HOST_CXX" --version | head -n1
    cmake --version | head -n1
    case "$variant" in
      cuda-*) "$(find_nvcc)" --version | tail -n2 ;;
      fuzz) "$FUZZ_CXX" --version | head -n1 ;;
    esac
  } | sha256sum | cut -c1-12
}

variant_prefix() { echo "$CACHE/kokkos-$1-$(variant_key "$1")"; }

if [ -n "$print_root" ]; then
  check_variant_name "$print_root"
  case "$print_root" in cuda-*) find_nvcc >/dev/null || die "nvcc not found" ;; esac
  prefix=$(variant_prefix "$print_root")
  echo "$prefix"
  [ -f "$prefix/$STAMP" ] || { log "warning: $prefix is not built yet (run scripts/deps.sh)"; exit 1; }
  exit 0
fi

# ---------------------------------------------------------------- apt packages
missing_packages() {
  local p st
  for p in "$@"; do
    st=$(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null || true)
    case "$st" in ii*) ;; *) echo "$p" ;; esac
  done
}

install_packages() {
  local missing
  missing=$(missing_packages "$@")
  [ -z "$missing" ] && return 0
  log "installing Debian packages: ${missing//$'\n'/ }"
  as_root apt-get update -q >&2
  # shellcheck disable=SC2086
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
    $missing >&2
}

# Debian 12: libvtk9-dev depends on python3-vtk9, which ParaView's Python module
# (python3-paraview, a recommendation of paraview) conflicts with; apt would stop on a
# resolver error. ParaView reads kdem's frames without its Python module.
refuse_paraview_conflict() {
  local vtk_missing paraview_python
  vtk_missing=$(missing_packages libvtk9-dev)
  [ -z "$vtk_missing" ] && return 0
  paraview_python=$(missing_packages python3-paraview)
  [ -n "$paraview_python" ] && return 0
  die "kdem needs libvtk9-dev, which depends on python3-vtk9, and python3-paraview (ParaView's \
Python module, installed here) conflicts with python3-vtk9. ParaView shows kdem's frames \
without it: run 'sudo apt-get remove python3-paraview' (paraview itself stays), then make \
again. See docs/build.md, 'kdem beside ParaView'."
}

if [ "$do_apt" -eq 1 ]; then
  refuse_paraview_conflict
  pkgs=("${APT_PACKAGES[@]}")
  [ "$want_bench" -eq 1 ] && pkgs+=("${BENCH_PACKAGES[@]}")
  [ "$want_fuzz" -eq 1 ] && pkgs+=("${FUZZ_PACKAGES[@]}")
  install_packages "${pkgs[@]}"
fi

[ "$do_kokkos" -eq 1 ] || exit 0

# ---------------------------------------------------------------- variants
variants=()
if [ -n "$only_variant" ]; then
  check_variant_name "$only_variant"
  variants=("$only_variant")
else
  variants=(openmp)
  [ "$want_fuzz" -eq 1 ] && variants+=(fuzz)
  if [ "$want_cuda" -eq 1 ]; then
    if find_nvcc >/dev/null; then variants+=(cuda-sm90 cuda-sm80)
    else log "nvcc not found (PATH, CUDA_ROOT, /usr/local/cuda/bin): skipping the CUDA variants"
    fi
  fi
fi
for v in "${variants[@]}"; do
  case "$v" in cuda-*) find_nvcc >/dev/null || die "variant $v needs nvcc" ;; esac
done

todo=()
for v in "${variants[@]}"; do
  [ -f "$(variant_prefix "$v")/$STAMP" ] || todo+=("$v")
done

# ------------------------------------------------------- Kokkos sources
SRC_DIR="$CACHE/src/trilinos-13.2"   # pristine packages/kokkos + packages/kokkos-kernels
DL_DIR="$CACHE/download"

have_deb_src() {
  grep -rqsE '^[[:space:]]*deb-src[[:space:]]|^Types:.*deb-src' \
    /etc/apt/sources.list /etc/apt/sources.list.d/ 2>/dev/null
}

# deb822 stanza(s) for bookworm sources, mirroring the binary entries.
write_deb_src() {
  local file=/etc/apt/sources.list.d/kdem-deb-src.sources content
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    content=$(sed -E 's/^Types:.*/Types: deb-src/' /etc/apt/sources.list.d/debian.sources)
  else
    content="Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg"
  fi
  log "adding $file"
  printf '%s\n' "$content" | as_root tee "$file" >/dev/null
}

orig_tarball() {
  local f
  for f in "$DL_DIR"/trilinos_13.2*.orig.tar.*; do
    [ -f "$f" ] && { echo "$f"; return 0; }
  done
  return 0
}

fetch_sources() {
  [ -f "$SRC_DIR/$STAMP" ] && return 0
  local updated=0
  if ! have_deb_src; then write_deb_src; as_root apt-get update -q >&2; updated=1; fi
  if [ -z "$(apt-cache showsrc trilinos 2>/dev/null)" ] && [ "$updated" -eq 0 ]; then
    as_root apt-get update -q >&2
  fi
  mkdir -p "$DL_DIR"
  local orig
  orig=$(orig_tarball)
  if [ -z "$orig" ]; then
    log "downloading Debian source package trilinos (about 170 MB)"
    local sandbox=()   # as root, apt cannot drop privileges into a folder it does not own
    [ "$(id -u)" -eq 0 ] && sandbox=(-o APT::Sandbox::User=root)
    (cd "$DL_DIR" && apt-get "${sandbox[@]}" source --download-only trilinos >&2) \
      || die "apt-get source trilinos failed (is a bookworm deb-src entry configured?)"
    orig=$(orig_tarball)
    [ -n "$orig" ] || die "no trilinos 13.2 orig tarball in $DL_DIR"
  fi
  log "extracting packages/kokkos and packages/kokkos-kernels from $(basename "$orig")"
  rm -rf "$SRC_DIR" "$SRC_DIR.tmp"
  mkdir -p "$SRC_DIR.tmp"
  tar -xf "$orig" -C "$SRC_DIR.tmp" --strip-components=2 --wildcards \
    '*/packages/kokkos/*' '*/packages/kokkos-kernels/*'
  grep -q 'set(Kokkos_VERSION_MINOR 4)' "$SRC_DIR.tmp/kokkos/CMakeLists.txt" \
    || die "the trilinos source does not contain Kokkos 3.4"
  touch "$SRC_DIR.tmp/$STAMP"
  mv "$SRC_DIR.tmp" "$SRC_DIR"
  # only the two extracted folders are kept
  rm -f "$DL_DIR"/trilinos_*
}

# >>> BUILD RECIPE (hashed into the cache key)
run_logged() {  # run_logged LOGFILE CMD...
  local logf=$1; shift
  if ! "$@" >>"$logf" 2>&1; then
    tail -n 40 "$logf" >&2
    die "command failed (full log: $logf): $*"
  fi
}

# Kokkos Kernels (only the tests use it): headers + a small library; every explicit
# instantiation off (KokkosBatched is header-only templates), no BLAS/LAPACK/cuBLAS/cuSPARSE.
build_kokkos_kernels() {  # build_kokkos_kernels WORK PREFIX CXX
  local work=$1 prefix=$2 cxx=$3
  run_logged "$work/kernels.log" cmake -S "$work/kokkos-kernels" -B "$work/build-kernels" \
    -DCMAKE_CXX_COMPILER="$cxx" "${common[@]}" -DKokkos_ROOT="$prefix" \
    -DKokkosKernels_ENABLE_TESTS=OFF -DKokkosKernels_ENABLE_EXAMPLES=OFF \
    -DKokkosKernels_ADD_DEFAULT_ETI=OFF \
    -DKokkosKernels_INST_DOUBLE=OFF -DKokkosKernels_INST_FLOAT=OFF \
    -DKokkosKernels_INST_COMPLEX_DOUBLE=OFF -DKokkosKernels_INST_COMPLEX_FLOAT=OFF \
    -DKokkosKernels_INST_LAYOUTLEFT=OFF -DKokkosKernels_INST_LAYOUTRIGHT=OFF \
    -DKokkosKernels_INST_OFFSET_INT=OFF -DKokkosKernels_INST_OFFSET_SIZE_T=OFF \
    -DKokkosKernels_INST_ORDINAL_INT=OFF -DKokkosKernels_INST_ORDINAL_INT64_T=OFF \
    -DKokkosKernels_INST_EXECSPACE_SERIAL=OFF -DKokkosKernels_INST_EXECSPACE_OPENMP=OFF \
    -DKokkosKernels_INST_EXECSPACE_CUDA=OFF -DKokkosKernels_INST_MEMSPACE_HOSTSPACE=OFF \
    -DKokkosKernels_INST_MEMSPACE_CUDASPACE=OFF -DKokkosKernels_INST_MEMSPACE_CUDAUVMSPACE=OFF \
    -DKokkosKernels_ENABLE_TPL_BLAS=OFF -DKokkosKernels_ENABLE_TPL_LAPACK=OFF \
    -DKokkosKernels_ENABLE_TPL_CUBLAS=OFF -DKokkosKernels_ENABLE_TPL_CUSPARSE=OFF
  run_logged "$work/kernels.log" cmake --build "$work/build-kernels" -j "$JOBS"
  run_logged "$work/kernels.log" cmake --install "$work/build-kernels"
}

build_variant() {
  local variant=$1 prefix work cxx arch="" t0
  prefix=$(variant_prefix "$variant")
  work="$CACHE/build/$(basename "$prefix")"
  t0=$(date +%s)
  log "building Kokkos + Kokkos Kernels 3.4.01 ($variant) -> $prefix"
  rm -rf "$work" "$prefix"
  mkdir -p "$work"
  cp -r "$SRC_DIR/kokkos" "$SRC_DIR/kokkos-kernels" "$work/"
  local p
  for p in "$PATCH_DIR"/*.patch; do
    (cd "$work" && patch -p1 --forward --quiet <"$p") >&2 || die "patch $(basename "$p") failed"
  done

  local common=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix"
    -DCMAKE_INSTALL_LIBDIR=lib -DCMAKE_POSITION_INDEPENDENT_CODE=ON
    -DCMAKE_CXX_STANDARD=17 -DCMAKE_CXX_EXTENSIONS=OFF)
  local kokkos_opts=(-DKokkos_CXX_STANDARD=17 -DKokkos_ENABLE_SERIAL=ON
    -DKokkos_ENABLE_OPENMP=ON -DKokkos_ENABLE_TESTS=OFF -DKokkos_ENABLE_EXAMPLES=OFF)
  case "$variant" in
    openmp) cxx=$HOST_CXX ;;
    # The fuzz targets' engine: Serial alone, by the compiler of libFuzzer (the sanitizers
    # instrument kdem's code and the Kokkos headers it compiles, not this library).
    fuzz) cxx=$FUZZ_CXX; kokkos_opts+=(-DKokkos_ENABLE_OPENMP=OFF) ;;
    cuda-sm90) arch=sm_90; kokkos_opts+=(-DKokkos_ARCH_HOPPER90=ON) ;;
    cuda-sm80) arch=sm_80; kokkos_opts+=(-DKokkos_ARCH_AMPERE80=ON) ;;
  esac
  if [ -n "$arch" ]; then
    local nvcc
    nvcc=$(find_nvcc)
    export CUDA_ROOT=${CUDA_ROOT:-$(dirname "$(dirname "$nvcc")")}
    export PATH="$CUDA_ROOT/bin:$PATH"
    export NVCC_WRAPPER_DEFAULT_COMPILER=$HOST_CXX NVCC_WRAPPER_DEFAULT_ARCH=$arch
    cxx="$work/kokkos/bin/nvcc_wrapper"
    kokkos_opts+=(-DKokkos_ENABLE_CUDA=ON -DKokkos_ENABLE_CUDA_LAMBDA=ON
      -DCUDAToolkit_ROOT="$CUDA_ROOT")
  fi

  run_logged "$work/kokkos.log" cmake -S "$work/kokkos" -B "$work/build-kokkos" \
    -DCMAKE_CXX_COMPILER="$cxx" "${common[@]}" "${kokkos_opts[@]}"
  run_logged "$work/kokkos.log" cmake --build "$work/build-kokkos" -j "$JOBS"
  run_logged "$work/kokkos.log" cmake --install "$work/build-kokkos"
  log "  Kokkos done after $(($(date +%s) - t0)) s"

  if [ -n "$arch" ]; then cxx="$prefix/bin/nvcc_wrapper"; fi
  [ "$variant" = fuzz ] || build_kokkos_kernels "$work" "$prefix" "$cxx"

  # The installed nvcc_wrapper defaults to this variant's architecture, so that
  # projects compiled with it agree with Kokkos even before Kokkos' flags apply.
  if [ -n "$arch" ] && [ -f "$prefix/bin/nvcc_wrapper" ]; then
    sed -i "s/NVCC_WRAPPER_DEFAULT_ARCH:-\"sm_90\"/NVCC_WRAPPER_DEFAULT_ARCH:-\"$arch\"/" \
      "$prefix/bin/nvcc_wrapper"
  fi
  cp "$work"/*.log "$prefix/"
  rm -rf "$work"
  echo "built in $(($(date +%s) - t0)) s on $(nproc) cores" >"$prefix/$STAMP"
  log "  $variant done in $(($(date +%s) - t0)) s"
}
# <<< BUILD RECIPE

if [ ${#todo[@]} -gt 0 ]; then
  mkdir -p "$CACHE"
  exec 9>"$CACHE/.lock"
  flock 9
  fetch_sources
  for v in "${todo[@]}"; do
    # another process may have finished it while we waited for the lock
    [ -f "$(variant_prefix "$v")/$STAMP" ] || ( build_variant "$v" )
  done
fi

for v in "${variants[@]}"; do variant_prefix "$v"; done
