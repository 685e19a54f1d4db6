"""Processor-in-the-loop on a Cortex-M7 (issue 31, item 3; `kiloloop pil ROBOT --target
cortex-m7`): the SIL log recorded here on x86-64 replays bit for bit through the firmware built
bare metal for a Cortex-M7 with its double-precision FPU and run on QEMU's MPS2-AN500 machine,
the log streamed through semihosting; the firmware fits an STM32H7's 2 MB flash and 1 MB RAM.
One family on a short log (the arm: the cross core build is minutes, the replay a second).
Skipped where Debian's gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib or qemu-system-arm is
missing (`scripts/setup_system.sh` installs them; CI has them).
"""
import shutil
import subprocess
from pathlib import Path

import pytest

from kiloloop.firmware.pil import M7_FLASH_BYTES, M7_RAM_BYTES, TARGETS, run_pil

ROOT = Path(__file__).resolve().parents[1]
WORK = ROOT / "build" / "firmware"
DURATION = 0.3  # [s] 300 ticks

pytestmark = pytest.mark.skipif(
    not all(shutil.which(p) for p in ("arm-none-eabi-gcc", "arm-none-eabi-g++",
                                      "arm-none-eabi-nm", "arm-none-eabi-size",
                                      "qemu-system-arm")),
    reason="the Cortex-M7 PIL needs gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib and "
           "qemu-system-arm (scripts/setup_system.sh)")


def test_cortex_m7_replay_is_bit_identical_and_fits_an_stm32h7():
    r = run_pil("ur5", target="cortex-m7", duration=DURATION, work=WORK, echo=lambda *_: None)
    ticks = int(round(DURATION * 1000))
    assert r.replay_output == f"bit-identical: {ticks} ticks"
    assert r.identical and r.ticks == ticks
    assert r.steps_counted == ticks
    assert 1000 < r.instructions_median <= r.instructions_max < 20 * r.instructions_median
    assert 0 < r.stack_step_bytes < 48 * 1024   # below the painted depth: a measured figure
    assert r.heap_init_bytes > 0
    # The budget: code and constants (and .data's initial values) in flash; .data, .bss, the heap
    # init holds and the steps' stack in RAM.
    assert r.text_bytes + r.data_bytes <= M7_FLASH_BYTES
    assert r.data_bytes + r.bss_bytes + r.heap_init_bytes + r.stack_step_bytes <= M7_RAM_BYTES
    m7 = TARGETS["cortex-m7"]
    assert r.step_us_worst == pytest.approx(r.instructions_max * m7.cpi / m7.clock_hz * 1e6)


def test_a_differing_log_is_reported_on_the_cortex_m7(tmp_path):
    """The comparison can fail there too: one output bit flipped in the log is found at its tick,
    and QEMU exits with the firmware's exit code (semihosting)."""
    r = run_pil("ur5", target="cortex-m7", duration=DURATION, work=WORK, echo=lambda *_: None)
    assert r.identical
    here = WORK / "ur5" / "pil-cortex-m7"
    tampered = bytearray((here / "b2b.log").read_bytes())
    tampered[-1] ^= 0x01  # the last tick's last output word: the lowest bit of its top byte
    bad = tmp_path / "tampered.log"
    bad.write_bytes(bytes(tampered))
    m7 = TARGETS["cortex-m7"]
    cmd = [a for a in m7.command(here / "build" / "kiloloop_firmware", ["replay", bad], "x")]
    i = cmd.index("-plugin")
    del cmd[i:i + 2]  # no instruction counting here
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert proc.stdout.startswith(f"differs at tick {int(round(DURATION * 1000)) - 1}: "
                                  "output field "), proc.stdout
