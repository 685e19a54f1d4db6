"""CMake steps of the firmware path, incremental in one work directory (default build/firmware of
the kiloloop source tree):

    core/      the core built with -fno-exceptions -fno-rtti (no Python): every real-time
               translation unit (controllers, QP, model, dynamics) compiled as firmware compiles
               it; the URDF loader beside it keeps exceptions (init time; examples/embed uses it)
    prefix/    its install: what find_package(kiloloop) finds (one install for every robot's
               firmware and for examples/embed: the tests build the core once per session)
    <robot>/   the robot's export, b2b log and firmware build (examples/firmware)
    core-<target>/, prefix-<target>/, <robot>/pil-<target>/
               the same for a cross target (`kiloloop pil`: a CMake toolchain file of cmake/;
               the core alone, no URDF loader: the firmware reads the exported description)
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
                "-DKILOLOOP_CORE_NO_EXCEPTIONS=ON", "-DKILOLOOP_BUILD_URDF=ON",
                "-DKILOLOOP_BUILD_PYTHON=OFF", "-DKILOLOOP_BUILD_BENCH=OFF",
                "-DKILOLOOP_BUILD_TESTS=OFF", "-DKILOLOOP_BUILD_FUZZ=OFF"]


class BuildError(RuntimeError):
    """A CMake step failed; the message carries the command and the tail of its output."""


def source_root() -> Path:
    """The kiloloop source tree: $KILOLOOP_SOURCE, else the first directory from the current one
    upwards whose CMakeLists.txt is kiloloop's."""
    env = os.environ.get("KILOLOOP_SOURCE")
    candidates = [Path(env)] if env else [Path.cwd(), *Path.cwd().parents]
    for d in candidates:
        cml = d / "CMakeLists.txt"
        if cml.is_file() and "project(kiloloop " in cml.read_text() and (d / "examples/firmware").is_dir():
            return d.resolve()
    raise BuildError("the kiloloop source tree (CMakeLists.txt, examples/firmware) was not found: "
                     "run from inside it or set KILOLOOP_SOURCE")


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


def install_rt_core(source: Path, work: Path, jobs: int = 2, toolchain: Path | None = None,
                    suffix: str = "") -> Path:
    """Builds (incrementally) and installs the no-exceptions core and the URDF loader; returns
    the install prefix. toolchain: a CMake toolchain file, for a cross target (then the core
    alone, in core<suffix>/ and prefix<suffix>/)."""
    cmake = _tool("cmake")
    core, prefix = work / f"core{suffix}", work / f"prefix{suffix}"
    work.mkdir(parents=True, exist_ok=True)
    # One build of a core directory at a time (`make test` builds the cross cores in the
    # background while pytest runs; a PIL test then waits here for it, and builds nothing more).
    with open(work / f"core{suffix}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        return _install_rt_core(cmake, source, core, prefix, jobs, toolchain)


def _install_rt_core(cmake: str, source: Path, core: Path, prefix: Path, jobs: int,
                     toolchain: Path | None) -> Path:
    cache = core / "CMakeCache.txt"
    options = list(CORE_OPTIONS)
    targets = ["kiloloop_core", "kiloloop_urdf"]
    if toolchain is not None:
        options = [o for o in options if not o.startswith("-DKILOLOOP_BUILD_URDF")]
        options += [f"-DCMAKE_TOOLCHAIN_FILE={toolchain}", "-DKILOLOOP_BUILD_URDF=OFF"]
        targets = ["kiloloop_core"]
    if not cache.is_file() or "KILOLOOP_CORE_NO_EXCEPTIONS:BOOL=ON" not in cache.read_text():
        _run([cmake, "-S", source, "-B", core, *_generator(), *options])
    # Only what is installed: the test helpers (alloc_counter throws bad_alloc) are no firmware
    # code, and the export tool is the Python module's.
    _run([cmake, "--build", core, "--target", *targets, "--parallel", str(jobs)])
    _run([cmake, "--install", core, "--prefix", prefix, "--component", "dev"])
    return prefix


def build_firmware(source: Path, prefix: Path, export_dir: Path, build_dir: Path,
                   toolchain: Path | None = None) -> Path:
    """Builds examples/firmware against `prefix` for the header in `export_dir`; the executable.
    toolchain: a CMake toolchain file, for a cross target."""
    cmake = _tool("cmake")
    if not (build_dir / "CMakeCache.txt").is_file():
        cross = [f"-DCMAKE_TOOLCHAIN_FILE={toolchain}"] if toolchain is not None else []
        _run([cmake, "-S", source / "examples" / "firmware", "-B", build_dir, *_generator(),
              "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}",
              f"-DKILOLOOP_EXPORT_DIR={export_dir}", *cross])
    _run([cmake, "--build", build_dir])
    return build_dir / "kiloloop_firmware"


def run_firmware(exe: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True)
