#!/usr/bin/env bash
# `make wheel` after `make build` (`make wheel-only`: build/py as it is, what scripts/run_tests.sh
# runs right after `make build`):
# `pip wheel` from build/py (only the install step and the zip run) into build/wheel-raw, then
# `auditwheel repair` grafts every shared library outside the manylinux policy (urdfdom_model,
# console_bridge, tinyxml) into kiloloop.libs/ with patchelf and tags the wheel by the oldest
# glibc its symbols allow (docs/install.md). Prints the wheel, its size and the time taken.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=.venv/bin
OUT=${WHEEL_DIR:-dist}
: "${PIP_BUILD_FLAGS:?run through make: make wheel or make wheel-only}"
start=$SECONDS
rm -rf build/wheel-raw
mkdir -p "$OUT"
"$BIN/python" -m pip install -q auditwheel patchelf
# PIP_BUILD_FLAGS: `make build`'s (the Makefile passes them), so build/py is configured as it was.
# shellcheck disable=SC2086
"$BIN/python" -m pip wheel -q --no-deps $PIP_BUILD_FLAGS -w build/wheel-raw .
rm -f "$OUT"/kiloloop-*.whl
PATH="$PWD/$BIN:$PATH" "$BIN/auditwheel" repair -w "$OUT" build/wheel-raw/kiloloop-*.whl
"$BIN/auditwheel" show "$OUT"/kiloloop-*.whl
wheel=$(ls "$OUT"/kiloloop-*.whl)
echo "==> wheel: $wheel, $(du -k "$wheel" | cut -f1) KiB, $((SECONDS - start)) s"
