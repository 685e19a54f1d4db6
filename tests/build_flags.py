"""What a CMake + Ninja build directory compiled: per-target object flags and the unity units'
sources (the firmware core tests: tests/test_firmware_b2b.py, tests/test_pil_aarch64.py)."""
import re
from pathlib import Path


def object_flags(build_dir: Path) -> dict[str, list[list[str]]]:
    """Compile flags per target and object, from a Ninja build directory's build.ninja."""
    ninja = (build_dir / "build.ninja").read_text()
    flags: dict[str, list[list[str]]] = {}
    for target, line in re.findall(r"^build CMakeFiles/(\w+)\.dir/\S+\.o: [^\n]*\n(?:  [^\n]*\n)*?"
                                   r"  FLAGS = ([^\n]*)$", ninja, re.MULTILINE):
        flags.setdefault(target, []).append(line.split())
    return flags


def unity_sources(build_dir: Path) -> str:
    return "".join(u.read_text() for u in (build_dir / "CMakeFiles" / "kiloloop_core.dir" /
                                           "Unity").glob("unity_*_cxx.cxx"))
