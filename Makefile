# The README's two commands: `make demo` and `make test`. Both set up everything they need:
# Debian packages (scripts/setup_system.sh), a virtual environment in .venv, and the package
# built by scikit-build-core into build/py (incremental; a unity build: pyproject.toml).
# `make test` (CI's command, .ci/run; scripts/run_tests.sh) runs two stages at once: the
# sanitizer stage (the C++ tests and short runs of every fuzz target built with ASan + UBSan in
# build/asan, then ctest there) in the background, and `make build` then pytest in the foreground.
# `make cpp-test`: the same C++ tests at -O2 without sanitizers (build/cpp; the allocation proof
# with the malloc interposer); `make fuzz`: 1,000,000 inputs per fuzz target from that build;
# `make sanitize`: the sanitizer stage alone, with the test code instrumented too (docs/hardening.md).
# mujoco is installed before the build: the native SIL loop compiles against its wheel's headers.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT := out
BUILD_DIR := build/py
WHEEL_DIR := dist
# The wheel carries no C++ tests (`make test` builds them under the sanitizers, `make cpp-test`
# at -O2). OFF explicitly: an older build/py's CMake cache may say ON.
PIP_BUILD_FLAGS := --no-build-isolation --config-settings=cmake.define.KILOLOOP_BUILD_TESTS=OFF \
                   --config-settings=cmake.define.KILOLOOP_BUILD_FUZZ=OFF
SAN_DIR := build/asan
CPP_DIR := build/cpp
FUZZ_INPUTS ?= 1000000
FUZZ_SEED ?= 1
SAN_FUZZ_INPUTS ?= 20000
# Unity build of the sanitizer build: SAN_UNITY_BATCH sources per translation unit (each unit
# instruments its own copy of the same Eigen templates; docs/hardening.md has the measured cost).
SAN_UNITY ?= ON
SAN_UNITY_BATCH ?= 8
# kiloloop_core_rt (every core source with -fno-exceptions -fno-rtti, -O0) and its smoke program in
# the sanitizer build. OFF after `make test`: pytest's firmware tests already compile the installed
# core that way (-O2) and replay through it bit for bit (tests/test_firmware_b2b.py).
SAN_RT ?= ON
# Optimization and debug info of the sanitizer build. -O1: the sanitizers' usual level; -g1: line
# numbers in reports. `make test` passes -g0 (a quarter less compile CPU, measured; reports keep
# function names: rerun `make sanitize` for lines).
SAN_OPT ?= -O1 -g1
# Instrument the test programs' own sources too (ON), or only the code under test (OFF: what
# `make test` runs; KILOLOOP_SANITIZE_TEST_CODE in CMakeLists.txt says what is left out).
SAN_TEST_CODE ?= ON
# Leave out the UBSan checks AddressSanitizer covers (ON: what `make test` runs;
# KILOLOOP_SANITIZE_UB_LEAN in CMakeLists.txt lists them and the measured cost).
SAN_UB_LEAN ?= OFF
JOBS ?= 2
# LeakSanitizer on; any UB report is fatal (also compiled in: -fno-sanitize-recover=undefined).
SAN_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1 \
           UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
           LSAN_OPTIONS=suppressions=$(abspath tests/lsan.supp)

.PHONY: demo test wheel wheel-only cpp-build cpp-test bench pil build system-deps clean robot-matrix matrix matrix-seeds quadruped-robots zoo fuzz sanitize \
        b2b firmware-loop

demo: build
	@echo "==> demo: the UR5 follows a quintic in MuJoCo (arm-track); plot and log into $(OUT)/"
	@mkdir -p $(OUT)
	$(BIN)/kiloloop run arm-track --plot $(OUT)/arm-track.png --log $(OUT)/arm-track.npz

# The sanitizer stage (`make sanitize`, the test code not instrumented, -g0, no SAN_RT; log in
# build/asan-stage.log) in the background from the start, `make build` and pytest in the
# foreground (scripts/run_tests.sh); fails if either fails. Measured stage times: docs/hardening.md.
test: system-deps $(BIN)/cmake
	scripts/run_tests.sh SAN_RT=OFF SAN_TEST_CODE=OFF SAN_UB_LEAN=ON SAN_OPT="-O1 -g0"

# The C++ tests and the fuzz harness at -O2 without sanitizers (plain CMake, a unity build, in
# build/cpp): the allocation proof with the malloc interposer at the shipped optimization level
# (under ASan, `make test` counts with ASan's hook instead).
cpp-build: system-deps $(BIN)/cmake
	$(BIN)/cmake -S . -B $(CPP_DIR) -G Ninja -DCMAKE_MAKE_PROGRAM=$(abspath $(BIN)/ninja) \
	  -DCMAKE_BUILD_TYPE=Release -DKILOLOOP_BUILD_TESTS=ON -DKILOLOOP_BUILD_PYTHON=OFF \
	  -DKILOLOOP_BUILD_BENCH=OFF -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8
	$(BIN)/cmake --build $(CPP_DIR) -j $(JOBS)

cpp-test: cpp-build
	ctest --test-dir $(CPP_DIR) --output-on-failure -j $(JOBS)

bench: build
	$(BIN)/kiloloop bench

# Real arms of example-robot-data from minimal robot files x the arm scenarios (long: not part
# of `make test`, which runs a representative subset); output kept in bench/robot_matrix.txt.
robot-matrix: build
	$(BIN)/python scripts/robot_matrix.py | tee bench/robot_matrix.txt

# Quadruped robot x scenario x delay table (minutes; not part of `make test`), with the ideal
# sensors (the scenarios' default) and with the realistic ones (ideal_sensors=false).
matrix: build
	$(BIN)/python -m kiloloop.bench.quadruped_matrix bench
	$(BIN)/python -m kiloloop.bench.quadruped_matrix bench --realistic

# The realistic table over seeds 0-4 (bench/quadruped_matrix_realistic_seeds.md): how many seeds
# pass each cell, the worst one, and the criteria the failing ones miss. About 30 s on 2 cores.
matrix-seeds: build
	$(BIN)/python -m kiloloop.bench.quadruped_matrix bench --realistic --seeds 5

# Every quadruped in example-robot-data from a minimal robot file (stand, trot, push, slope,
# tilt-stop at 10 ms, realistic sensors): bench/quadruped_robots.{md,json}, about 15 s.
quadruped-robots: build
	$(BIN)/python -m kiloloop.bench.quadruped_robots bench

# The zoo (docs/zoo.md): every arm, quadruped and multirotor of example-robot-data from a minimal
# robot file (python/kiloloop/bench/zoo_robots.py) x every scenario of its family, seeds 0-4; the
# quadrupeds at 10 and 35 ms: 1290 runs, bench/zoo.{md,json}. Measured with --jobs 1 on the
# shared 2-core machine (load 8-10): 2334 s in all; arms 250 runs, 307 s (mean 1.2 s a run),
# multirotors 140, 77 s (0.5 s), quadrupeds 900, 1937 s (2.2 s; rough ground at 35 ms up to 85 s).
# ZOO_JOBS=2 (the default, JOBS) about halves it where two cores are free. Filters:
# ZOO_ARGS="--robots go1,arm --scenarios quadruped-trot --seeds 0 --delays 35" (a rerun merges
# into bench/zoo.json). tests/test_zoo.py runs four of its cells in `make test`.
ZOO_JOBS ?= $(JOBS)
ZOO_ARGS ?=
zoo: build
	$(BIN)/python -m kiloloop.bench.zoo bench --jobs $(ZOO_JOBS) $(ZOO_ARGS)

# The firmware path for our three robots: SIL log -> export -> firmware build (-fno-exceptions
# -fno-rtti, build/firmware/) -> replay, bit for bit (docs/firmware.md).
b2b: build
	for robot in ur5 quadruped aerial_manipulator; do $(BIN)/kiloloop b2b $$robot --work build/firmware || exit 1; done

# Processor-in-the-loop, the whole set (scripts/pil_matrix.py): ur5, quadruped, aerial_manipulator
# and example-robot-data's ur3, go1 and iris, 2 s each, on every target `kiloloop pil` knows;
# `make test` runs the three families on 0.3 s logs (tests/test_pil_*.py).
pil: build
	$(BIN)/python scripts/pil_matrix.py --duration 2

# The firmware example's fixed-rate loop, 10 s at 1 kHz on this machine (figures: bench/).
firmware-loop: build
	$(BIN)/kiloloop b2b quadruped --work build/firmware
	build/firmware/quadruped/build/kiloloop_firmware run build/firmware/quadruped/b2b.log 10 \
	  | tee bench/firmware_loop.txt

# Every fuzz target, FUZZ_INPUTS inputs each; prints inputs, bad outputs, missed statuses and
# crashes per target and fails on any of them.
fuzz: cpp-build
	$(CPP_DIR)/kiloloop_fuzz --inputs $(FUZZ_INPUTS) --seed $(FUZZ_SEED)

# ASan + UBSan build of the core, the URDF loader, the C++ tests and the fuzz harness (plain
# CMake, SAN_OPT; a unity build: SAN_UNITY), plus kiloloop_core_rt
# (-fno-exceptions -fno-rtti; SAN_RT); runs ctest there (the tests, SAN_FUZZ_INPUTS inputs per
# fuzz target, the no-exceptions smoke program). Incremental. Any report fails the run: UBSan
# halts (-fno-sanitize-recover=undefined), ASan aborts, LeakSanitizer is on (tests/lsan.supp:
# third-party leaks only). The allocation tests count with ASan's malloc hook here
# (cpp/testing/alloc_counter.cpp); the malloc interposer's proof is build/cpp's (`make cpp-test`).
sanitize: system-deps $(BIN)/cmake
	$(BIN)/cmake -S . -B $(SAN_DIR) -G Ninja -DCMAKE_MAKE_PROGRAM=$(abspath $(BIN)/ninja) \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$(SAN_OPT) -DNDEBUG" \
	  -DKILOLOOP_SANITIZE=ON -DKILOLOOP_RT_NO_EXCEPTIONS=$(SAN_RT) -DKILOLOOP_BUILD_TESTS=ON \
	  -DKILOLOOP_SANITIZE_TEST_CODE=$(SAN_TEST_CODE) -DKILOLOOP_SANITIZE_UB_LEAN=$(SAN_UB_LEAN) \
	  -DKILOLOOP_BUILD_PYTHON=OFF -DKILOLOOP_BUILD_BENCH=OFF \
	  -DKILOLOOP_FUZZ_SHORT_INPUTS=$(SAN_FUZZ_INPUTS) \
	  -DCMAKE_UNITY_BUILD=$(SAN_UNITY) -DCMAKE_UNITY_BUILD_BATCH_SIZE=$(SAN_UNITY_BATCH)
	$(BIN)/cmake --build $(SAN_DIR) -j $(JOBS)
	$(SAN_ENV) ctest --test-dir $(SAN_DIR) --output-on-failure -j $(JOBS)

$(BIN)/cmake: | $(BIN)/python
	$(BIN)/python -m pip install -q cmake ninja

system-deps:
	scripts/setup_system.sh

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

# --no-compile: no .pyc files written at install (Python compiles a module when it is first
# imported): the test dependencies (Ray, Pinocchio, ...) are thousands of modules never imported.
# pip's whole output (a failure's cause: "Could not install packages due to an OSError" is
# followed by the error itself, "[Errno 28] No space left on device" for one), printed in part.
PIP_LOG := build/pip-install.log
# The first build compiles about 90 C++ sources in 30 build steps (unity units and links; about 5.5
# minutes on 2 idle cores, pip included: 332 s in CI): its progress lines
# ([n/N] Building ...) are shown, the rest of pip's output is not.
build: system-deps $(BIN)/python
	@echo "==> kiloloop: Python build tools into $(VENV)"
	@$(BIN)/python -m pip install -q --upgrade pip
	@$(BIN)/python -m pip install -q "scikit-build-core>=0.10" "pybind11>=2.12" cmake ninja "mujoco>=3.2" "pybind11-stubgen>=3.0"
	@echo "==> kiloloop: building the C++ core and the Python module into $(BUILD_DIR)"
	@echo "    (incremental; the first build takes about 5.5 minutes on 2 cores), then installing"
	@echo "    the Python dependencies (mujoco, numpy, pinocchio and example-robot-data for tests...)"
	@mkdir -p build; set -o pipefail; $(BIN)/python -m pip install -v --no-compile $(PIP_BUILD_FLAGS) ".[test]" 2>&1 \
	  | tee $(PIP_LOG) \
	  | grep --line-buffered -E '^ *\[[0-9]+/[0-9]+\] (Building|Linking)|^ERROR|error:|Successfully installed' \
	  | sed -u -E 's/^ *(\[[0-9]+\/[0-9]+\]) (Building|Linking) CXX (object|executable|static library|shared module) /    \1 /; s/\.o$$//' \
	  || { echo "build failed; the end of pip's log ($(PIP_LOG)), then the free disk space:"; \
	       tail -n 25 $(PIP_LOG); df -h . /tmp; exit 1; }
	@echo "==> kiloloop: built"

# The self-contained wheel in dist/ (scripts/make_wheel.sh: pip wheel from build/py, seconds,
# then auditwheel repair; docs/install.md). Prints the wheel, its size and the time taken.
wheel: build
	@$(MAKE) --no-print-directory wheel-only

# The wheel from build/py as it is, without `make build` first (make test runs it right after).
wheel-only:
	WHEEL_DIR=$(WHEEL_DIR) PIP_BUILD_FLAGS="$(PIP_BUILD_FLAGS)" scripts/make_wheel.sh

clean:
	rm -rf build $(OUT) $(WHEEL_DIR)
