#!/usr/bin/env bash
# `make test`: two stages at once on the machine's cores; both must pass.
#   1. The sanitizer stage (`make sanitize "$@"`), in the background from the start: the core, the
#      URDF loader, the C++ tests and every fuzz target built with AddressSanitizer +
#      UndefinedBehaviorSanitizer in build/asan, then ctest there. It needs no Python package, only
#      cmake and ninja from .venv. Its output goes to build/asan-stage.log (the end is printed
#      when it passes, the whole log when it fails).
#   2. In the foreground: `make build` (the Python dependencies, the package built in build/py
#      and installed into .venv, with its firmware kit: the core's archive the module links),
#      the self-contained wheel in dist/ (`make wheel-only`: scripts/make_wheel.sh), then
#      pytest (it builds every robot's firmware against the kit and replays its log through it,
#      bit for bit; it installs the wheel into a fresh virtual environment and runs it with the
#      Debian libraries hidden).
# Why at once: the sanitizer stage is the longest and needs no wheel; the dependency downloads and
# pytest (one Python process) leave a core it takes (docs/hardening.md: measured stage times).
set -uo pipefail
cd "$(dirname "$0")/.."

mkdir -p build
log=build/asan-stage.log
echo "==> sanitizer stage in the background: make sanitize $* (log: $log)"
# Each stage's wall and CPU time (bash's `time`: the children's user + sys), printed at the end.
# Each `time` runs in its own subshell: in this shell it would also count the background stage's
# CPU if that stage ended (and was reaped here) while the timed command ran.
TIMEFORMAT='%R s wall, %U s user + %S s sys CPU'
( time make --no-print-directory sanitize "$@" >"$log" 2>&1 ) 2>build/asan-stage.time &
san_pid=$!
# A stopped make test (Ctrl-C) stops the background stage too.
trap 'kill "$san_pid" 2>/dev/null' INT TERM

# The PIL targets' cross-compiled cores (aarch64; the Cortex-M7's arm family), niced, from the
# start (scripts/prebuild_pil.py: they need no Python package): they take the CPU the other
# stages leave, so that pytest's PIL tests, which run last and wait for them (a lock per core
# directory; python/kiloloop/firmware/build.py), find them built.
( ( time nice -n 10 .venv/bin/python scripts/prebuild_pil.py build/firmware ) \
    >build/pil-prebuild.log 2>&1 ) &
pil_pid=$!
trap 'kill "$san_pid" "$pil_pid" 2>/dev/null' INT TERM

( time make --no-print-directory build 2>&3 ) 3>&2 2>build/build-stage.time \
  || { echo "==> make build FAILED; stopping the sanitizer stage"; kill "$san_pid" "$pil_pid" 2>/dev/null; wait; exit 1; }
echo "==> make build: $(cat build/build-stage.time)"
# The self-contained wheel (dist/; from build/py: seconds), which tests/test_wheel.py installs
# into a fresh virtual environment and runs with the Debian libraries hidden.
( time make --no-print-directory wheel-only 2>&3 ) 3>&2 2>build/wheel-stage.time \
  || { echo "==> the wheel FAILED"; kill "$san_pid" "$pil_pid" 2>/dev/null; wait; exit 1; }
echo "==> the wheel (make wheel-only): $(cat build/wheel-stage.time)"
echo "==> Python tests (pytest; the PIL cores build beside it, log build/pil-prebuild.log)"
( time .venv/bin/python -m pytest -q --durations=15 2>&3 ) 3>&2 2>build/pytest-stage.time
py_rc=$?
wait "$pil_pid" || echo "==> the PIL core prebuild failed (the PIL tests say why): $(tail -n 3 build/pil-prebuild.log)"
echo "==> PIL cores: $(tail -n 4 build/pil-prebuild.log | tr '\n' ' ')"
echo "==> pytest: $(cat build/pytest-stage.time); waiting for the sanitizer stage"

wait "$san_pid"
san_rc=$?
if [ "$san_rc" -ne 0 ]; then
  echo "==> sanitizer stage FAILED (exit $san_rc); its log, $log:"
  cat "$log"
else
  echo "==> sanitizer stage passed: $(cat build/asan-stage.time); the end of $log:"
  tail -n 4 "$log"
fi
[ "$py_rc" -eq 0 ] && [ "$san_rc" -eq 0 ]
