"""Processor-in-the-loop on aarch64 (issue 31, item 3; `kiloloop pil ROBOT --target aarch64`): the
SIL log recorded here on x86-64 replays bit for bit through the firmware cross-compiled for
aarch64 and run under qemu-aarch64, one robot of each family on a short log (`make pil`: 2 s each,
and example-robot-data's robots). Beside the bits, the footprint and the instruction counts the
run reports must be there and plausible. Skipped where Debian's g++-aarch64-linux-gnu or
qemu-user is missing (scripts/setup_system.sh installs both; CI has them).
"""
import shutil
import subprocess
from pathlib import Path

import pytest

from kiloloop.firmware.pil import TARGETS, run_pil

from build_flags import object_flags, unity_sources

ROOT = Path(__file__).resolve().parents[1]
WORK = ROOT / "build" / "firmware"
DURATION = 0.3  # [s] 300 ticks

pytestmark = pytest.mark.skipif(
    not all(shutil.which(p) for p in ("aarch64-linux-gnu-g++", "qemu-aarch64",
                                      "aarch64-linux-gnu-nm")),
    reason="the aarch64 PIL needs g++-aarch64-linux-gnu and qemu-user (scripts/setup_system.sh)")


@pytest.mark.parametrize("robot", ["ur5", "quadruped", "aerial_manipulator"])
def test_aarch64_replay_is_bit_identical_with_the_x86_sil_run(robot):
    r = run_pil(robot, target="aarch64", duration=DURATION, work=WORK, echo=lambda *_: None)
    ticks = int(round(DURATION * 1000))
    assert r.replay_output == f"bit-identical: {ticks} ticks"
    assert r.identical and r.ticks == ticks
    # One count per step, between the two markers: a step is thousands of instructions, and no
    # step costs more than a few times the median (no allocation, no solver blow-up).
    assert r.steps_counted == ticks
    assert 1000 < r.instructions_median <= r.instructions_max < 20 * r.instructions_median
    assert 0 < r.stack_step_bytes < 48 * 1024   # below the painted depth: a measured figure
    assert r.heap_init_bytes > 0
    assert r.text_bytes > 0 and r.step_us_worst == pytest.approx(
        r.instructions_max * TARGETS["aarch64"].cpi / TARGETS["aarch64"].clock_hz * 1e6)


def test_a_differing_log_is_reported_with_its_tick_and_field(tmp_path):
    """The comparison can fail: one output bit flipped in the log is found at its tick."""
    r = run_pil("ur5", target="aarch64", duration=0.05, work=WORK, echo=lambda *_: None)
    assert r.identical
    here = WORK / "ur5" / "pil-aarch64"
    log = (here / "b2b.log").read_bytes()
    tampered = bytearray(log)
    tampered[-1] ^= 0x01  # the last tick's last output word: the lowest bit of its top byte
    bad = tmp_path / "tampered.log"
    bad.write_bytes(bytes(tampered))
    proc = subprocess.run([TARGETS["aarch64"].emulator, str(here / "build" / "kiloloop_firmware"),
                           "replay", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 1
    assert proc.stdout.startswith("differs at tick 49: output field "), proc.stdout


def test_the_cross_core_is_compiled_without_exceptions_and_rtti():
    """The no-RTTI proof of every core source (the x86-64 kit keeps RTTI for the bindings):
    each kiloloop_core object of the aarch64 core is compiled -fno-exceptions -fno-rtti."""
    run_pil("ur5", target="aarch64", duration=0.05, work=WORK, echo=lambda *_: None)
    core = WORK / "core-aarch64"
    flags = object_flags(core)
    assert flags.get("kiloloop_core"), sorted(flags)
    assert all("-fno-exceptions" in f and "-fno-rtti" in f for f in flags["kiloloop_core"])
    sources = [p for p in (ROOT / "cpp" / "src").rglob("*.cpp") if not p.name.endswith("_test.cpp")]
    units = unity_sources(core)
    assert len(sources) > 30 and all(f'"{p.resolve()}"' in units for p in sources)
