# kdem: thin driver around scripts/deps.sh and the CMake presets.
#
#   make build         Debian packages + cached Kokkos (OpenMP) + configure/build preset "openmp"
#   make test          build, then ctest on build/openmp
#   make demo          build, run the hopper demo into out/demo and plot it
#   make bench         also install the peer codes (liggghts), then perf/run_bench.py
#   make serial        configure/build preset "serial" (build/serial)
#   make memcheck      preset "memcheck" (build/memcheck): engine data in a host space that host
#                      code may not touch outside kernels; runs the engine tests there
#   make cuda          CUDA Kokkos (sm_90) + preset "cuda" (build/cuda); compiles and links
#                      everything, runs nothing (see test-cuda)
#   make cuda-sm80     the engine and program (target kdem) for Ampere sm_80 (build/cuda-sm80)
#   make test-cuda     ctest on build/cuda (needs a GPU)
#   make perf-check    instructions per particle-step per stage (callgrind, fixed scenes) against
#                      perf/baseline/callgrind_stages.json; fails on a regression above 5 %
#   make perf-baseline write that baseline anew (after a change that is meant to cost more)
#   make gpu-check     on a machine with an NVIDIA GPU: build for it, run the tests, the backend
#                      agreement and the benchmarks; report in out/gpu-check (GPU_CHECK_PRESET=openmp:
#                      the same on the CPU, as CI runs it)
#   make fuzz          clang + libFuzzer build of the host library and a Serial engine (preset
#                      fuzz, build/fuzz, Kokkos built by clang), then each fuzz target (scene
#                      loader, mesh readers, checkpoint reader) for FUZZ_SECONDS (60) or
#                      FUZZ_RUNS executions; results in out/fuzz/results.json
#   make format        clang-format -i on the C++ sources
#   make clean         remove build/ and out/ (the Kokkos cache is kept)
#
# Variables:
#   JOBS=N             parallel build jobs (default: number of cores)
#   KOKKOS_ROOT=DIR    use your own Kokkos (3.4 or newer) instead of the cached build,
#                      e.g. `make build KOKKOS_ROOT=/opt/kokkos`; for `make cuda` it must
#                      be a CUDA-enabled Kokkos, whose bin/nvcc_wrapper becomes the compiler.
#   KOKKOS_KERNELS_ROOT=DIR  Kokkos Kernels install, if not under KOKKOS_ROOT
#   KDEM_CACHE=DIR     where scripts/deps.sh keeps its Kokkos builds (~/.cache/kdem)
#   CCACHE_DIR=DIR     the compiler cache (KDEM_CACHE/ccache; ccache is used where installed)
#   CMAKE_ARGS=...     extra arguments for the CMake configure step
#
# The configure step runs only when build/<preset> is not configured yet, the Kokkos
# install changed (then with --fresh) or CMakePresets.json changed; afterwards `cmake --build` re-runs CMake by itself when
# a CMakeLists.txt changes.

SHELL := /bin/bash
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
KOKKOS_ROOT ?=
KOKKOS_KERNELS_ROOT ?=
CMAKE_ARGS ?=
DEPS := scripts/deps.sh
# Debian's interpreter, which has the python3-* packages that scripts/deps.sh installs.
PYTHON ?= /usr/bin/python3
MAKEFLAGS += --no-print-directory
# The compiler cache (CMakeLists.txt uses ccache where it is installed) lives beside the Kokkos
# builds unless CCACHE_DIR says otherwise.
CCACHE_DIR ?= $(or $(KDEM_CACHE),$(HOME)/.cache/kdem)/ccache
export CCACHE_DIR

.PHONY: all deps deps-cuda deps-bench deps-fuzz build test demo bench serial memcheck memcheck-build \
        cuda cuda-sm80 test-cuda perf-check perf-baseline gpu-check fuzz format clean help
.DEFAULT_GOAL := build

all: build

help:
	@sed -n '2,/^$$/p' Makefile | sed 's/^# \{0,1\}//'

# --- dependencies -------------------------------------------------------------
# With KOKKOS_ROOT set only the Debian packages are checked.
ifeq ($(strip $(KOKKOS_ROOT)),)
deps:
	@$(DEPS) >/dev/null
deps-cuda:
	@$(DEPS) --cuda >/dev/null
else
deps:
	@$(DEPS) --no-kokkos
deps-cuda:
	@$(DEPS) --no-kokkos
endif

deps-bench:
	@$(DEPS) --bench --no-kokkos

ifeq ($(strip $(KOKKOS_ROOT)),)
deps-fuzz:
	@$(DEPS) --fuzz --variant fuzz >/dev/null
else
deps-fuzz:
	@$(DEPS) --fuzz --no-kokkos
endif

# --- configure + build --------------------------------------------------------
# $(call configure_build,PRESET,DEPS-VARIANT[,TARGET])
define configure_build
	@set -e; \
	if [ -n "$(KOKKOS_ROOT)" ]; then root="$(KOKKOS_ROOT)"; \
	else root=$$($(DEPS) --print-root $(2)); fi; \
	prefix="$$root"; [ -z "$(KOKKOS_KERNELS_ROOT)" ] || prefix="$$root;$(KOKKOS_KERNELS_ROOT)"; \
	bdir=build/$(1); fresh=""; \
	if [ ! -f $$bdir/CMakeCache.txt ]; then configure=1; \
	elif [ "$$(cat $$bdir/.kokkos-root 2>/dev/null)" != "$$prefix" ]; then configure=1; fresh="--fresh"; \
	elif [ CMakePresets.json -nt $$bdir/CMakeCache.txt ]; then configure=1; \
	else configure=0; fi; \
	if [ $$configure -eq 1 ]; then \
	  echo "-- configuring preset $(1) with Kokkos from $$root"; \
	  KDEM_KOKKOS_ROOT="$$root" cmake --preset $(1) $$fresh \
	    -DKokkos_ROOT="$$root" -DCMAKE_PREFIX_PATH="$$prefix" \
	    $(if $(filter cuda%,$(1)),-DCMAKE_CXX_COMPILER="$$root/bin/nvcc_wrapper") \
	    $(CMAKE_ARGS); \
	  echo "$$prefix" > $$bdir/.kokkos-root; \
	fi; \
	KDEM_KOKKOS_ROOT="$$root" cmake --build $$bdir -j $(JOBS) $(if $(3),--target $(3))
endef

build: deps
	$(call configure_build,openmp,openmp)

serial: deps
	$(call configure_build,serial,openmp)

memcheck-build: deps
	$(call configure_build,memcheck,openmp)

cuda: deps-cuda
	@$(DEPS) --find-nvcc >/dev/null || { echo "make cuda: nvcc not found" >&2; exit 1; }
	$(call configure_build,cuda,cuda-sm90)
	@scripts/check_cuda_lambdas.sh build/cuda

cuda-sm80: deps-cuda
	@$(DEPS) --find-nvcc >/dev/null || { echo "make cuda-sm80: nvcc not found" >&2; exit 1; }
	$(call configure_build,cuda-sm80,cuda-sm80,kdem)
	@scripts/check_cuda_lambdas.sh build/cuda-sm80

# --- run ----------------------------------------------------------------------
test: build
	OMP_PROC_BIND=$${OMP_PROC_BIND:-false} ctest --test-dir build/openmp --output-on-failure

# The engine suites and whole-program runs with every host access of engine data checked.
memcheck: memcheck-build
	ctest --test-dir build/memcheck --output-on-failure

test-cuda: cuda
	ctest --test-dir build/cuda --output-on-failure

perf-check: build
	$(PYTHON) perf/callgrind_stages.py --bin build/openmp/bin --scenes spheres,cubes \
	    --check perf/baseline/callgrind_stages.json --out out/perf-check/callgrind_stages.json

perf-baseline: build
	$(PYTHON) perf/callgrind_stages.py --bin build/openmp/bin \
	    --write-baseline perf/baseline/callgrind_stages.json

GPU_CHECK_PRESET ?= auto
GPU_CHECK_ARGS ?=
gpu-check: build
	$(PYTHON) perf/gpu_check.py --preset $(GPU_CHECK_PRESET) --out out/gpu-check $(GPU_CHECK_ARGS)

FUZZ_SECONDS ?= 60
FUZZ_RUNS ?= -1
FUZZ_SEED ?= 0
fuzz: deps-fuzz
	$(call configure_build,fuzz,fuzz)
	$(PYTHON) scripts/run_fuzzers.py --seconds $(FUZZ_SECONDS) --runs $(FUZZ_RUNS) --seed $(FUZZ_SEED)

demo: build
	build/openmp/bin/kdem run cases/hopper/hopper_spheres.yaml --out out/demo
	$(PYTHON) cases/hopper/plot_discharge.py out/demo
	$(PYTHON) cases/hopper/render_frame.py out/demo/checkpoint.h5 --png out/demo/hopper.png

bench: deps-bench build
	$(PYTHON) perf/run_bench.py

# --- housekeeping -------------------------------------------------------------
FORMAT_DIRS := $(wildcard src kernels shapes tests perf)
format:
	@command -v clang-format >/dev/null || { echo "clang-format not found (apt-get install clang-format)" >&2; exit 1; }
	@[ -z "$(FORMAT_DIRS)" ] || find $(FORMAT_DIRS) -type f \( -name '*.hpp' -o -name '*.cpp' \) -print0 \
	  | xargs -0 -r clang-format -i

clean:
	rm -rf build out
