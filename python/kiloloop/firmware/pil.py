"""`kiloloop pil ROBOT --target aarch64|cortex-m7`: processor-in-the-loop. The SIL run is recorded
on this x86-64 machine (as `kiloloop b2b` records it), the robot exported, the firmware cross-
compiled for the target (a CMake toolchain file of cmake/) and its replay run on the target's
instruction set under QEMU: "bit-identical: N ticks" against the x86-64 SIL outputs, or the first
differing tick and field. Besides the bits, what the target would spend: the executable's static
sizes (text, data, bss), the heap init holds, the steps' stack high-water mark (examples/firmware
footprint.hpp), and the guest instructions of each controller step, counted by a QEMU plugin
(cpp/pil/insn_counter.c) between two marker calls, with the step time they imply at a stated clock
and a stated cycles-per-instruction assumption (QEMU counts instructions, not cycles).
"""
from __future__ import annotations

import fcntl
import shutil
import subprocess
from dataclasses import asdict, dataclass
from pathlib import Path

from . import build
from .b2b import record_and_export

STEP_BUDGET_US = 1000.0  # [us] one tick at 1 kHz


@dataclass(frozen=True)
class Target:
    """A processor the firmware is cross-built for and run on under QEMU."""
    name: str            # --target
    toolchain: str       # the CMake toolchain file, in cmake/
    tools: str           # the cross binutils' prefix (nm, size)
    emulator: str        # the QEMU program
    packages: str        # Debian's packages that provide compiler and emulator
    processor: str       # the processor the step time is stated for
    clock_hz: float      # [Hz] its clock
    cpi: float           # cycles per instruction assumed (QEMU counts instructions only)
    cpi_why: str
    # A QEMU machine for a bare-metal target (system emulation; the firmware's stdio, argv and
    # files through semihosting: examples/firmware/cortex_m7/); "": a Linux user-mode target.
    machine: str = ""

    @property
    def programs(self) -> tuple[str, ...]:
        """What a PIL run calls besides CMake and the compilers: the emulator, nm and size."""
        return (self.emulator, self.tools + "nm", self.tools + "size")

    def command(self, exe: Path, args: list, plugin: str) -> list[str]:
        if not self.machine:
            return [self.emulator, "-plugin", plugin, str(exe), *map(str, args)]
        # argv goes to the firmware as one command line split at spaces (startup.c); QEMU's
        # option syntax takes a comma in a value as ",,".
        argv = ["kiloloop_firmware", *map(str, args)]
        if any(" " in a for a in argv):
            raise build.BuildError(f"the {self.name} firmware's arguments cannot hold spaces: "
                                   f"{argv}")
        semihosting = ",".join(["enable=on", "target=native",
                                *(f"arg={a.replace(',', ',,')}" for a in argv)])
        return [self.emulator, "-M", self.machine, "-nographic",
                "-semihosting-config", semihosting, "-plugin", plugin, "-kernel", str(exe)]


TARGETS = {
    # A Cortex-A72 (Raspberry Pi 4 class, 1.5 GHz): a 3-wide out-of-order core; the controllers'
    # scalar double arithmetic is dependency-bound, so about one instruction per cycle.
    "aarch64": Target("aarch64", "toolchain-aarch64-linux-gnu.cmake", "aarch64-linux-gnu-",
                      "qemu-aarch64", "g++-aarch64-linux-gnu qemu-user", "Cortex-A72", 1.5e9,
                      1.0, "scalar double arithmetic, dependency-bound on a 3-wide core"),
    # A Cortex-M7 with the double-precision FPU (STM32H7 class, 480 MHz), bare metal: QEMU's
    # MPS2-AN500 machine, the log streamed from the host's file through semihosting. A
    # dual-issue in-order core, but its FPU issues one double operation at a time with a
    # latency of several cycles (divide and square root far more), and the steps' scalar double
    # arithmetic waits on it: 1.5 cycles per instruction assumed, code and data in cache or
    # tightly coupled memory.
    "cortex-m7": Target("cortex-m7", "toolchain-cortex-m7.cmake", "arm-none-eabi-",
                        "qemu-system-arm", "gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib "
                        "qemu-system-arm", "Cortex-M7", 480e6, 1.5,
                        "in-order; double-precision FPU operations of several cycles' latency",
                        machine="mps2-an500"),
}

# The budget a Cortex-M7 target is checked against: an STM32H7's flash and RAM [bytes]
# (the linker script, examples/firmware/cortex_m7/mps2_an500.ld, holds the link to them).
M7_FLASH_BYTES = 2 * 1024 * 1024
M7_RAM_BYTES = 1024 * 1024


@dataclass
class PilResult:
    robot: str
    family: str
    target: str
    ticks: int
    log_sha256: str
    replay_output: str          # the firmware's identity line
    identical: bool
    text_bytes: int
    data_bytes: int
    bss_bytes: int
    heap_init_bytes: int
    stack_step_bytes: int
    steps_counted: int
    instructions_median: int
    instructions_max: int
    processor: str
    clock_hz: float
    cpi: float
    step_us_median: float       # implied at clock_hz and cpi
    step_us_worst: float
    budget_met: bool

    def as_dict(self) -> dict:
        return asdict(self)


def _need(program: str, target: Target) -> str:
    found = shutil.which(program)
    if found is None:
        raise build.BuildError(f"{program} not found: the {target.name} PIL needs Debian's "
                               f"{target.packages} (scripts/setup_system.sh)")
    return found


def build_plugin(source: Path, work: Path) -> Path:
    """The instruction-counting QEMU plugin (host code), built once in <work>/pil-plugin."""
    cmake = build._tool("cmake")
    out = work / "pil-plugin"
    work.mkdir(parents=True, exist_ok=True)
    with open(work / "pil-plugin.lock", "w") as lock:  # prebuild() may be at it (make test)
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (out / "CMakeCache.txt").is_file():
            build._run([cmake, "-S", source / "cpp" / "pil", "-B", out, *build._generator(),
                        f"-DKILOLOOP_THIRD_PARTY_CACHE={build.third_party_cache(source, work)}"])
        build._run([cmake, "--build", out])
    return out / "libkiloloop_insn_counter.so"


def prebuild(targets=None, work=None, jobs: int = 2) -> list[str]:
    """Builds the firmware cores of the targets whose tools this machine has and the QEMU
    plugin, ahead of the PIL runs: `make test` runs it in the background from its start
    (scripts/prebuild_pil.py), and its PIL tests come last. targets: name -> the families its
    core holds (None: all; default: every target, all families). The names built."""
    source = build.source_root()
    work = Path(work) if work else build.default_work()
    built = []
    for name, families in (targets or dict.fromkeys(TARGETS)).items():
        t = TARGETS[name]
        if not all(shutil.which(p) for p in t.programs):
            continue
        build.install_rt_core(source, work, jobs=jobs, toolchain=source / "cmake" / t.toolchain,
                              suffix=build.core_suffix(t.name, families), families=families)
        built.append(name)
    if built:
        build_plugin(source, work)
    return built


def core_for(target: Target, family: str, work: Path) -> tuple[str, tuple | None]:
    """The cross core a PIL run of `family` builds against: the whole core where the work
    directory has one (`make pil`, make test's aarch64 runs), else the family's own, which
    compiles only what its firmware links. (suffix, families)."""
    if (work / f"core-{target.name}" / "CMakeCache.txt").is_file():
        return build.core_suffix(target.name), None
    return build.core_suffix(target.name, (family,)), (family,)


def symbol_address(target: Target, exe: Path, name: str) -> int:
    out = build._run([_need(target.tools + "nm", target), exe])
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[2] == name:
            return int(parts[0], 16)
    raise build.BuildError(f"{exe}: no symbol {name} (footprint.hpp's step markers)")


def static_sizes(target: Target, exe: Path) -> tuple[int, int, int]:
    """text, data, bss [bytes] as the target's `size` (Berkeley format) prints them."""
    out = build._run([_need(target.tools + "size", target), exe]).splitlines()
    text, data, bss = (int(v) for v in out[1].split()[:3])
    return text, data, bss


def _field(lines: list[str], prefix: str) -> int:
    for line in lines:
        if line.startswith(prefix):
            return int(line[len(prefix):].replace("at least", "").split()[0])
    raise build.BuildError(f"the firmware printed no '{prefix}' line: {lines}")


def run_pil(robot_arg, *, target: str, duration: float | None = None, seed: int | None = None,
            sets: dict | None = None, work=None, echo=print,
            scenario: str | None = None) -> PilResult:
    """SIL run (x86-64) -> log -> export -> cross build -> replay on `target` under QEMU."""
    if target not in TARGETS:
        raise build.BuildError(f"unknown target '{target}' (one of {', '.join(TARGETS)})")
    t = TARGETS[target]
    for program in t.programs:
        _need(program, t)
    source = build.source_root()
    work = Path(work) if work else build.default_work()
    r = record_and_export(robot_arg, duration=duration, seed=seed, sets=sets, work=work,
                          echo=echo, scenario=scenario, what_for=f"pil ({t.name})",
                          subdir=f"pil-{t.name}")
    toolchain = source / "cmake" / t.toolchain
    suffix, families = core_for(t, r.family.name, work)
    prefix = build.install_rt_core(source, work, toolchain=toolchain, suffix=suffix,
                                   families=families)
    exe = build.build_firmware(source, prefix, r.header.parent, r.here / "build",
                               toolchain=toolchain)
    echo(f"  firmware: {exe} ({t.name}, -fno-exceptions -fno-rtti)")
    plugin = build_plugin(source, work)
    counts = r.here / "instructions.txt"
    counts.unlink(missing_ok=True)
    begin = symbol_address(t, exe, "kiloloop_pil_step_begin")
    end = symbol_address(t, exe, "kiloloop_pil_step_end")
    proc = subprocess.run(t.command(exe, ["pil", r.log],
                                    f"{plugin},begin={begin:#x},end={end:#x},out={counts}"),
                          capture_output=True, text=True)
    if proc.returncode not in (0, 1) or not counts.is_file():
        raise build.BuildError(f"the {t.name} replay failed (exit {proc.returncode}): "
                               f"{(proc.stdout + proc.stderr).strip()[-2000:]}")
    lines = proc.stdout.strip().splitlines()
    line = lines[-1]
    heap = _field(lines, "heap held by init: ")
    stack = _field(lines, "stack high-water of the steps: ")
    stats = counts.read_text().split()
    steps, median, worst = int(stats[1]), int(stats[5]), int(stats[7])
    text, data, bss = static_sizes(t, exe)
    per_us = t.cpi / t.clock_hz * 1e6  # [us] per instruction
    result = PilResult(
        r.robot.name, r.family.name, t.name, r.ticks, r.log_sha256, line,
        proc.returncode == 0 and line.startswith("bit-identical"), text, data, bss, heap, stack,
        steps, median, worst, t.processor, t.clock_hz, t.cpi, median * per_us, worst * per_us,
        worst * per_us <= STEP_BUDGET_US)
    echo(f"  footprint: text {text} B, data {data} B, bss {bss} B (the whole executable); "
         f"heap held by init {heap} B; stack high-water of the steps {stack} B")
    if t.machine:  # bare metal: the whole program is the firmware, in the board's memories
        echo(f"  {t.processor} budget: flash {text + data} of {M7_FLASH_BYTES} B (text + data); "
             f"RAM {data + bss + heap + stack} of {M7_RAM_BYTES} B (data + bss + heap held by "
             f"init + the steps' stack)")
    echo(f"  instructions per step ({steps} steps, QEMU plugin): median {median}, max {worst}")
    echo(f"  implied step time on a {t.processor} at {t.clock_hz / 1e9:g} GHz, {t.cpi:g} cycles "
         f"per instruction assumed ({t.cpi_why}): median {result.step_us_median:.1f} us, "
         f"worst {result.step_us_worst:.1f} us against the {STEP_BUDGET_US:g} us tick: "
         f"{'met' if result.budget_met else 'MISSED'}")
    echo(line)
    return result
