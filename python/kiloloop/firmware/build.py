"""CMake steps of the firmware path, incremental in one work directory (default_work(): the
user's cache, outside any source tree; `--work DIR` elsewhere):

    <robot>/   the robot's export, b2b log and firmware build (examples/firmware)
    core/, prefix/
               the x86-64 core built with -fno-exceptions -fno-rtti and its install, where no kit
               is installed (a checkout's Python package run from the source tree)
    core-<target>/, prefix-<target>/, <robot>/pil-<target>/
               the same for a cross target (`kiloloop pil`: a CMake toolchain file of cmake/;
               the core alone, no URDF loader: the firmware reads the exported description)

The installed wheel carries the firmware kit (kit_prefix(): kiloloop/kit/, the static libraries
the Python module itself links, with their headers and CMake package; kiloloop/kit/source: the
sources a cross target compiles and the firmware examples), so on x86-64 nothing of the core is
compiled again: host_core() returns the kit.
"""
from __future__ import annotations

import fcntl
import os
import shutil
import subprocess
import sys
from pathlib import Path

RT_FLAGS = "-fno-exceptions -fno-rtti"
# How core/ is configured. A core/ configured otherwise (the earlier layout: RT_FLAGS for every
# target through CMAKE_CXX_FLAGS, no URDF loader) is configured again, CMAKE_CXX_FLAGS emptied.
# A unity build (8 sources per unit, as the sanitizer build): fewer compiles of the same Eigen
# templates; the back-to-back tests prove its outputs equal the wheel's, bit for bit.
CORE_OPTIONS = ["-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_CXX_FLAGS=",
                "-DCMAKE_UNITY_BUILD=ON", "-DCMAKE_UNITY_BUILD_BATCH_SIZE=8",
                "-DKILOLOOP_CORE_NO_EXCEPTIONS=ON", "-DKILOLOOP_CORE_RTTI=OFF",
                "-DKILOLOOP_BUILD_URDF=ON",
                "-DKILOLOOP_BUILD_PYTHON=OFF", "-DKILOLOOP_BUILD_BENCH=OFF",
                "-DKILOLOOP_BUILD_TESTS=OFF", "-DKILOLOOP_BUILD_FUZZ=OFF"]


class BuildError(RuntimeError):
    """A CMake step failed; the message carries the command and the tail of its output."""


def kit_prefix() -> Path | None:
    """The installed package's firmware kit (an install prefix for find_package(kiloloop)), or
    None where the package has none (run from a source tree without a wheel install)."""
    kit = Path(__file__).resolve().parents[1] / "kit"
    return kit if (kit / "lib" / "cmake" / "kiloloop" / "kiloloopConfig.cmake").is_file() else None


def _is_source_tree(d: Path) -> bool:
    cml = d / "CMakeLists.txt"
    return (cml.is_file() and "project(kiloloop " in cml.read_text()
            and (d / "examples" / "firmware").is_dir())


def source_root() -> Path:
    """The kiloloop sources the firmware path builds from: $KILOLOOP_SOURCE, else the first
    directory from the current one upwards that is a kiloloop checkout, else the installed kit's
    copy (kiloloop/kit/source)."""
    env = os.environ.get("KILOLOOP_SOURCE")
    candidates = [Path(env)] if env else [Path.cwd(), *Path.cwd().parents]
    for d in candidates:
        if _is_source_tree(d):
            return d.resolve()
    kit = kit_prefix()
    if env is None and kit is not None and _is_source_tree(kit / "source"):
        return kit / "source"
    raise BuildError(f"the kiloloop source tree (CMakeLists.txt, examples/firmware) was not found "
                     f"{'in KILOLOOP_SOURCE=' + env if env else 'and the installed package has no kit'}"
                     ": set KILOLOOP_SOURCE to a checkout, or install the kiloloop wheel")


def default_work() -> Path:
    """Where the firmware path builds by default: $XDG_CACHE_HOME/kiloloop/firmware (else
    ~/.cache/kiloloop/firmware), outside any source tree and any installed package."""
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "kiloloop" / "firmware"


def third_party_cache(source: Path, work: Path) -> Path:
    """Download cache of the third-party sources (musl, KDL, QEMU's plugin header; version pinned,
    hash checked: cmake/third_party.cmake): a checkout's build/third_party, else the work
    directory's (the kit's source may be read-only)."""
    kit = kit_prefix()
    in_kit = kit is not None and source.resolve().is_relative_to(kit)
    return work / "third_party" if in_kit else source / "build" / "third_party"


def host_core(source: Path, work: Path, jobs: int = 2) -> Path:
    """The x86-64 firmware core to build against: the installed kit, else (no kit) built and
    installed in `work` (install_rt_core)."""
    return kit_prefix() or install_rt_core(source, work, jobs=jobs)


def _tool(name: str) -> str:
    search = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    found = shutil.which(name, path=search)
    if found is None:
        raise BuildError(f"{name} not found (pip install cmake ninja)")
    return found


def _generator() -> list[str]:
    try:
        return ["-G", "Ninja", f"-DCMAKE_MAKE_PROGRAM={_tool('ninja')}"]
    except BuildError:
        return []


def _run(cmd: list) -> str:
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if proc.returncode != 0:
        raise BuildError(f"failed (exit {proc.returncode}): {' '.join(map(str, cmd))}\n"
                         f"{(proc.stdout + proc.stderr)[-4000:]}")
    return proc.stdout


FAMILIES = ("arm", "quadruped", "aerial")  # CMakeLists.txt's KILOLOOP_CORE_FAMILIES


def core_suffix(target: str, families=None) -> str:
    """The core directories' suffix of a cross target and a family subset (None: all):
    core-aarch64, core-cortex-m7-arm."""
    subset = sorted(set(families or FAMILIES), key=FAMILIES.index)
    return f"-{target}" + ("" if len(subset) == len(FAMILIES) else "-" + "-".join(subset))


def install_rt_core(source: Path, work: Path, jobs: int = 2, toolchain: Path | None = None,
                    suffix: str = "", families=None) -> Path:
    """Builds (incrementally) and installs the no-exceptions core and the URDF loader; returns
    the install prefix. toolchain: a CMake toolchain file, for a cross target (then the core
    alone, in core<suffix>/ and prefix<suffix>/). families: the robot families the core holds
    (a cross core only; None: all of them)."""
    cmake = _tool("cmake")
    core, prefix = work / f"core{suffix}", work / f"prefix{suffix}"
    work.mkdir(parents=True, exist_ok=True)
    # One build of a core directory at a time (`make test` builds the cross cores in the
    # background while pytest runs; a PIL test then waits here for it, and builds nothing more).
    with open(work / f"core{suffix}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        return _install_rt_core(cmake, source, core, prefix, jobs, toolchain,
                                third_party_cache(source, work), families)


def _install_rt_core(cmake: str, source: Path, core: Path, prefix: Path, jobs: int,
                     toolchain: Path | None, downloads: Path, families) -> Path:
    cache = core / "CMakeCache.txt"
    if cache.is_file() and _configured_source(cache) != source.resolve():
        shutil.rmtree(core)  # configured from other sources (another checkout, the kit's copy)
    options = list(CORE_OPTIONS) + [f"-DKILOLOOP_THIRD_PARTY_CACHE={downloads}"]
    kit = kit_prefix()
    if kit is not None and (kit / "include" / "eigen3" / "Eigen" / "Core").is_file():
        # Where no Eigen3 package is installed, the kit's copy of its headers.
        options.append(f"-DKILOLOOP_EIGEN_INCLUDE_DIR={kit / 'include' / 'eigen3'}")
    targets = ["kiloloop_core", "kiloloop_urdf"]
    if toolchain is not None:
        options = [o for o in options if not o.startswith("-DKILOLOOP_BUILD_URDF")]
        options += [f"-DCMAKE_TOOLCHAIN_FILE={toolchain}", "-DKILOLOOP_BUILD_URDF=OFF",
                    f"-DKILOLOOP_CORE_FAMILIES={';'.join(families or FAMILIES)}"]
        targets = ["kiloloop_core"]
    if not cache.is_file() or "KILOLOOP_CORE_NO_EXCEPTIONS:BOOL=ON" not in cache.read_text():
        _run([cmake, "-S", source, "-B", core, *_generator(), *options])
    # Only what is installed: the test helpers (alloc_counter throws bad_alloc) are no firmware
    # code, and the export tool is the Python module's.
    _run([cmake, "--build", core, "--target", *targets, "--parallel", str(jobs)])
    _run([cmake, "--install", core, "--prefix", prefix, "--component", "dev"])
    return prefix


def _cache_value(cache: Path, key: str) -> str | None:
    """A CMake cache entry's value (`KEY:TYPE=value`), None where it has none."""
    for line in cache.read_text().splitlines():
        if line.startswith(key + ":"):
            return line.split("=", 1)[1]
    return None


def _configured_source(cache: Path) -> Path | None:
    value = _cache_value(cache, "CMAKE_HOME_DIRECTORY")
    return Path(value).resolve() if value else None


def build_firmware(source: Path, prefix: Path, export_dir: Path, build_dir: Path,
                   toolchain: Path | None = None) -> Path:
    """Builds examples/firmware against `prefix` for the header in `export_dir`; the executable.
    toolchain: a CMake toolchain file, for a cross target."""
    cmake = _tool("cmake")
    cache = build_dir / "CMakeCache.txt"
    if cache.is_file() and (_configured_source(cache) != (source / "examples" / "firmware").resolve()
                            or _cache_value(cache, "CMAKE_PREFIX_PATH") != str(prefix)):
        shutil.rmtree(build_dir)  # configured for other sources or another core install
    if not cache.is_file():
        cross = [f"-DCMAKE_TOOLCHAIN_FILE={toolchain}"] if toolchain is not None else []
        _run([cmake, "-S", source / "examples" / "firmware", "-B", build_dir, *_generator(),
              "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}",
              f"-DKILOLOOP_EXPORT_DIR={export_dir}", *cross])
    _run([cmake, "--build", build_dir])
    return build_dir / "kiloloop_firmware"


def run_firmware(exe: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True)
