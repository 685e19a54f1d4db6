#!/usr/bin/env python3
"""The PIL cross cores of `make test`, built from its start beside the sanitizer stage and the
package build (scripts/run_tests.sh), so that pytest's PIL tests, which run last, find them built:
    python scripts/prebuild_pil.py WORK
What they need: the aarch64 core with every family (tests/test_pil_aarch64.py runs all three)
and the Cortex-M7 core of the arm family (tests/test_pil_cortex_m7.py runs the UR5), and the
QEMU plugin. The Python package is not built yet at that point, so the firmware modules are
loaded from the source tree without the package's __init__ (which imports the compiled module):
build.py and pil.py's prebuild need only the standard library, CMake and the toolchains."""
from __future__ import annotations

import sys
import types
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WHAT_MAKE_TEST_RUNS = {"aarch64": None, "cortex-m7": ("arm",)}  # target -> families (None: all)


def _firmware_modules():
    """kiloloop.firmware.build and the prebuild of kiloloop.firmware.pil, the packages above
    them stood in by empty modules whose __path__ is the source tree's."""
    for name, path in (("kiloloop", ROOT / "python" / "kiloloop"),
                       ("kiloloop.firmware", ROOT / "python" / "kiloloop" / "firmware")):
        module = types.ModuleType(name)
        module.__path__ = [str(path)]
        sys.modules[name] = module
    stub = types.ModuleType("kiloloop.firmware.b2b")  # pil.py's SIL recording: not needed here
    stub.record_and_export = None
    sys.modules["kiloloop.firmware.b2b"] = stub
    from kiloloop.firmware import pil
    return pil


def main() -> int:
    work = Path(sys.argv[1]).resolve()
    pil = _firmware_modules()
    print("PIL cores built:", pil.prebuild(WHAT_MAKE_TEST_RUNS, work=work), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
