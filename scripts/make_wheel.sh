#!/usr/bin/env bash
# `make wheel` after `make build` (scripts/run_tests.sh calls it directly, build/py just built):
# `pip wheel` from build/py (only the install step and the zip run) into build/wheel-raw, then
# `auditwheel repair` grafts every shared library outside the manylinux policy (urdfdom_model,
# console_bridge, tinyxml) into kiloloop.libs/ with patchelf and tags the wheel by the oldest
# glibc its symbols allow (docs/install.md). Prints the wheel, its size and the time taken.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=.venv/bin
OUT=${WHEEL_DIR:-dist}
start=$SECONDS
rm -rf build/wheel-raw
mkdir -p "$OUT"
"$BIN/python" -m pip install -q auditwheel patchelf
# The flags of `make build` (Makefile, PIP_BUILD_FLAGS): the same build/py configuration.
"$BIN/python" -m pip wheel -q --no-deps --no-build-isolation \
  --config-settings=cmake.define.KILOLOOP_BUILD_TESTS=OFF \
  --config-settings=cmake.define.KILOLOOP_BUILD_FUZZ=OFF -w build/wheel-raw .
rm -f "$OUT"/kiloloop-*.whl
PATH="$PWD/$BIN:$PATH" "$BIN/auditwheel" repair -w "$OUT" build/wheel-raw/kiloloop-*.whl
"$BIN/auditwheel" show "$OUT"/kiloloop-*.whl
wheel=$(ls "$OUT"/kiloloop-*.whl)
echo "==> wheel: $wheel, $(du -k "$wheel" | cut -f1) KiB, $((SECONDS - start)) s"
