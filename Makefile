# The README's two commands: `make demo` and `make test`. Both set up everything they need:
# Debian packages (scripts/setup_system.sh), a virtual environment in .venv, and the package
# built by scikit-build-core into build/py (incremental; the C++ tests are built there too).
# mujoco is installed before the build: the native SIL loop compiles against its wheel's headers.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT := out
BUILD_DIR := build/py
PIP_BUILD_FLAGS := --no-build-isolation --config-settings=cmake.define.KILOLOOP_BUILD_TESTS=ON

.PHONY: demo test bench build system-deps clean

demo: build
	@mkdir -p $(OUT)
	$(BIN)/kiloloop run arm-track --plot $(OUT)/arm-track.png --log $(OUT)/arm-track.npz

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j2
	$(BIN)/python -m pytest -q

bench: build
	$(BIN)/kiloloop bench

system-deps:
	scripts/setup_system.sh

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

build: system-deps $(BIN)/python
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q "scikit-build-core>=0.10" "pybind11>=2.12" cmake ninja "mujoco>=3.2"
	$(BIN)/python -m pip install -q $(PIP_BUILD_FLAGS) ".[test]"

clean:
	rm -rf build $(OUT)
