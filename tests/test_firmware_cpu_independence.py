"""CPU independence on x86-64 (issue 31, item 4): a SIL log recorded here, with glibc's FMA and
AVX2 code paths enabled, replays bit for bit through the firmware binary with those paths
disabled at run time (glibc tunables), for one robot of each family. Before the deterministic
math (musl's behind the libm names, docs/firmware.md) the ur5's replay differed at tick 1242 of
8 s, and within the 2 s here.
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from kiloloop.firmware.b2b import run_b2b

ROOT = Path(__file__).resolve().parents[1]
WORK = ROOT / "build" / "firmware"
NO_FMA = dict(os.environ, GLIBC_TUNABLES="glibc.cpu.hwcaps=-AVX2,-FMA")
# glibc's own sin over 200,000 arguments: its digest changes under NO_FMA on a CPU with FMA
# (the control: the tunable does reach the code paths this test is about).
_LIBM_DIGEST = """
import ctypes, hashlib, struct
libm = ctypes.CDLL("libm.so.6"); libm.sin.restype = ctypes.c_double
libm.sin.argtypes = [ctypes.c_double]
h = hashlib.sha256()
for i in range(200000):
    h.update(struct.pack("<d", libm.sin(0.5 + i * 1e-4)))
print(h.hexdigest())
"""


def _libm_digest(env) -> str:
    return subprocess.run([sys.executable, "-c", _LIBM_DIGEST], env=env, capture_output=True,
                          text=True, check=True).stdout.strip()


@pytest.fixture(scope="module")
def tunables_change_glibc():
    if "fma" not in Path("/proc/cpuinfo").read_text():
        pytest.skip("this CPU has no FMA: glibc has no FMA code path to disable")
    if _libm_digest(os.environ) == _libm_digest(NO_FMA):
        pytest.skip("GLIBC_TUNABLES does not change glibc's sin here (another libc or glibc)")


@pytest.mark.parametrize("robot,duration", [("ur5", 2.0), ("quadruped", 1.0),
                                            ("aerial_manipulator", 1.0)])
def test_replay_without_fma_and_avx2_is_bit_identical(firmware_prefix, tunables_change_glibc,
                                                      robot, duration):
    result = run_b2b(robot, duration=duration, work=WORK, prefix=firmware_prefix,
                     echo=lambda *_: None)
    ticks = int(round(duration * 1000))
    assert result.replay_output == f"bit-identical: {ticks} ticks"
    here = WORK / robot
    proc = subprocess.run([str(here / "build" / "kiloloop_firmware"), "replay",
                           str(here / "b2b.log")], env=NO_FMA, capture_output=True, text=True)
    assert proc.stdout.strip() == f"bit-identical: {ticks} ticks", proc.stdout + proc.stderr
