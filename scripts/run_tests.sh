#!/usr/bin/env bash
# The test stage of `make test` (after `make build`): pytest on the installed package and, at the
# same time, the C++ tests and short fuzz runs built with AddressSanitizer + UndefinedBehaviorSanitizer
# (`make sanitize SAN_RT=OFF`: build/asan). Why at the same time: pytest drives MuJoCo on one core
# most of its run, so on a 2-core machine the sanitizer build gets the other one almost for free
# (docs/hardening.md: the measured cost). The sanitizer stage writes its log to build/asan.log;
# its ctest summary is printed at the end, its whole log tail on a failure. Exit 0 only when both pass.
set -uo pipefail
cd "$(dirname "$0")/.."

san_log=build/asan.log
mkdir -p build
echo "==> C++ tests under ASan + UBSan: make sanitize SAN_RT=OFF (in the background; log: $san_log)"
start=$SECONDS
( make --no-print-directory sanitize SAN_RT=OFF > "$san_log" 2>&1 ) &
san_pid=$!

echo "==> Python tests (pytest)"
.venv/bin/python -m pytest -q
py_rc=$?

wait "$san_pid"
san_rc=$?
echo "==> C++ tests under ASan + UBSan ($((SECONDS - start)) s since the start of both stages)"
if [ "$san_rc" -eq 0 ]; then
  grep -E "tests passed|tests failed|Total Test time" "$san_log"
else
  echo "sanitizer stage FAILED (exit $san_rc); the end of $san_log:"
  tail -n 200 "$san_log"
fi
[ "$py_rc" -eq 0 ] || echo "pytest FAILED (exit $py_rc)"
[ "$py_rc" -eq 0 ] && [ "$san_rc" -eq 0 ]
