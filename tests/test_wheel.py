"""The self-contained wheel (`make wheel`: dist/kiloloop-*-manylinux_*.whl), installed into a fresh
virtual environment and run where the Debian libraries it was built against do not exist.

How they are made unavailable: the commands run in a private mount namespace (`unshare -rm`, a
user namespace whose root may mount), in which /dev/null is bind-mounted over every file of
urdfdom, console_bridge, tinyxml, Orocos KDL and kdl_parser in /usr/lib/x86_64-linux-gnu (a
process that loads one finds no ELF file), and an empty directory over Eigen's and KDL's headers
in /usr/include (the firmware builds must take the kit's). Outside the namespace nothing changes.
There, with the current directory outside any checkout and KILOLOOP_SOURCE unset:
- `ldd` of the installed `_core` resolves no library from those packages (auditwheel grafted
  them into kiloloop.libs/);
- `kiloloop run arm-track` and `kiloloop run quadruped-trot --robot <Go1 robot file>` pass;
- `kiloloop b2b ur5` builds the firmware against the wheel's kit and replays bit for bit;
- docs/firmware.md's minimal main.cpp and CMakeLists.txt, as written, build against
  `kiloloop --cmake-prefix` and run.
The wheel is the newest in dist/ (scripts/run_tests.sh runs `make wheel` before pytest); without
one the test is skipped with the command that makes it.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).parent))
import quadruped_robots  # noqa: E402  (the example-robot-data Go1's minimal robot file)

# The Debian packages' shared libraries the module was linked against, and the headers a firmware
# build could otherwise pick up from the system.
HIDDEN_LIBRARIES = ("liburdfdom", "libconsole_bridge", "libtinyxml", "liborocos-kdl", "libkdl_parser")
HIDDEN_HEADERS = ("/usr/include/eigen3", "/usr/include/kdl", "/usr/share/eigen3")
LIBDIR = Path("/usr/lib/x86_64-linux-gnu")


def _wheel() -> Path:
    wheels = sorted((ROOT / "dist").glob("kiloloop-*-manylinux_*_x86_64.whl"),
                    key=lambda p: p.stat().st_mtime)
    if not wheels:
        pytest.skip("no repaired wheel in dist/: `make wheel` builds it")
    return wheels[-1]


def _doc_blocks() -> tuple[str, str]:
    """docs/firmware.md's minimal firmware: its ```cpp and ```cmake blocks, verbatim."""
    text = (ROOT / "docs" / "firmware.md").read_text()
    section = text.split("## Your own firmware", 1)[1].split("\n## ", 1)[0]
    cpp = re.search(r"```cpp\n(.*?)```", section, re.S).group(1)
    cmake = re.search(r"```cmake\n(.*?)```", section, re.S).group(1)
    return cpp, cmake


def _run(cmd, **kw) -> subprocess.CompletedProcess:
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    assert proc.returncode == 0, (f"{' '.join(map(str, cmd))}: exit {proc.returncode}\n"
                                  f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc


def test_wheel_contents_are_self_contained():
    """The wheel carries the kit (headers, static libraries, CMake package, sources) and every
    non-system shared library; auditwheel finds nothing outside the manylinux policy."""
    wheel = _wheel()
    names = zipfile.ZipFile(wheel).namelist()
    for needed in ("kiloloop/kit/lib/libkiloloop_core.a", "kiloloop/kit/lib/libkiloloop_kdl.a",
                   "kiloloop/kit/lib/cmake/kiloloop/kiloloopConfig.cmake",
                   "kiloloop/kit/include/kiloloop/status.hpp", "kiloloop/kit/include/kdl/frames.hpp",
                   "kiloloop/kit/include/eigen3/Eigen/Core", "kiloloop/kit/source/CMakeLists.txt",
                   "kiloloop/kit/source/examples/firmware/main.cpp"):
        assert needed in names, f"{wheel.name} lacks {needed}"
    grafted = [n for n in names if n.startswith("kiloloop.libs/")]
    assert any("urdfdom_model" in n for n in grafted), grafted
    assert not any(n.endswith("_test.cpp") for n in names)
    auditwheel = Path(sys.executable).with_name("auditwheel")
    if not auditwheel.exists():
        pytest.skip("auditwheel is not installed (`make wheel` installs it)")
    out = _run([auditwheel, "show", wheel]).stdout
    assert re.search(r"consistent\s+with\s+the\s+following\s+platform\s+tag:\s*\"manylinux_\d+_\d+_x86_64\"",
                     out), out


@pytest.fixture(scope="module")
def fresh_venv(tmp_path_factory) -> Path:
    """A new virtual environment (no system site-packages) with the wheel, its dependencies
    from the package index, and cmake + ninja (what `kiloloop b2b` needs besides a compiler)."""
    wheel = _wheel()
    venv = tmp_path_factory.mktemp("wheel") / "venv"
    _run([sys.executable, "-m", "venv", venv])
    _run([venv / "bin" / "python", "-m", "pip", "install", "-q", "--no-compile", wheel, "cmake",
          "ninja"],
         timeout=600)
    return venv


def test_wheel_runs_without_the_debian_libraries(fresh_venv, tmp_path):
    if shutil.which("unshare") is None:
        pytest.skip("no unshare(1) to hide the Debian libraries")
    probe = subprocess.run(["unshare", "-rm", "true"], capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"no private mount namespace here (`unshare -rm`: {probe.stderr.strip()})")
    go1 = quadruped_robots.go1_robot_file(tmp_path)
    if go1 is None:
        pytest.skip("example-robot-data is not installed (the Go1 robot file)")
    core = next((fresh_venv / "lib").glob("python3*/site-packages/kiloloop/_core*.so"))
    cpp, cmake = _doc_blocks()
    fw = tmp_path / "fw"
    fw.mkdir()
    (fw / "main.cpp").write_text(cpp)
    (fw / "CMakeLists.txt").write_text(cmake)
    hidden = sorted(str(p) for p in LIBDIR.iterdir() if p.name.startswith(HIDDEN_LIBRARIES))
    assert hidden, f"none of {HIDDEN_LIBRARIES} in {LIBDIR}: nothing to hide"
    bin_ = fresh_venv / "bin"
    script = f"""set -e
for f in {' '.join(hidden)}; do mount --bind /dev/null "$f"; done
empty=$(mktemp -d)
for d in {' '.join(HIDDEN_HEADERS)}; do if [ -d "$d" ]; then mount --bind "$empty" "$d"; fi; done
unset KILOLOOP_SOURCE PYTHONPATH
export HOME={tmp_path}/home PATH={bin_}:/usr/bin:/bin
cd {tmp_path}
ldd {core} > ldd.txt
{bin_}/kiloloop run arm-track > arm-track.txt
{bin_}/kiloloop run quadruped-trot --robot {go1} > quadruped-trot.txt
{bin_}/kiloloop b2b ur5 > b2b.txt
cd fw
{bin_}/kiloloop export ur5 --out export > /dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$({bin_}/kiloloop --cmake-prefix)" > configure.txt
cmake --build build > build.txt
build/my_firmware > run.txt
"""
    proc = subprocess.run(["unshare", "-rm", "bash", "-c", script], capture_output=True,
                          text=True, timeout=900)
    outputs = {p.name: p.read_text() for p in [*tmp_path.glob("*.txt"), *fw.glob("*.txt")]}
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr[-4000:]}\n{outputs}"

    ldd = outputs["ldd.txt"]
    assert "not found" not in ldd, ldd
    for line in ldd.splitlines():
        if line.strip().startswith(HIDDEN_LIBRARIES):
            assert "kiloloop.libs" in line, f"resolved outside the wheel: {line}"
    assert "kiloloop.libs" in ldd, ldd
    assert "PASSED" in outputs["arm-track.txt"], outputs["arm-track.txt"]
    assert "PASSED" in outputs["quadruped-trot.txt"], outputs["quadruped-trot.txt"]
    assert "bit-identical" in outputs["b2b.txt"], outputs["b2b.txt"]
    assert str(tmp_path / "home" / ".cache" / "kiloloop" / "firmware") in outputs["b2b.txt"]
    # The kit's Eigen, not the system's (hidden): the configure found kiloloop in the venv.
    cache = (fw / "build" / "CMakeCache.txt").read_text()
    assert f"kiloloop_DIR:PATH={fresh_venv}" in cache.replace(str(fresh_venv.resolve()), str(fresh_venv))
    assert re.match(r"ur5: 1000 ticks, last status ok, tau\[1\] = -?\d+\.\d{3} N m",
                    outputs["run.txt"]), outputs["run.txt"]
