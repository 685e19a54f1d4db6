"""examples/embed: the firmware path, end to end, and its bit identity with the Python module.

Builds the standalone examples/embed project against the firmware path's installed core (conftest's
firmware_prefix: kiloloop_core with -fno-exceptions -fno-rtti and the URDF loader, configured with
CMake without Python and benches, built once per session and shared with the back-to-back tests)
through find_package(kiloloop), runs embed_demo on the UR5 and compares its 1000 x 6 torques and
statuses with the Python twin (examples/embed/embed_twin.py) run in-process: they must be equal to
the last bit.
"""
import importlib.util
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "embed"
URDF = ROOT / "models" / "ur5" / "ur5.urdf"
TICKS = 1000
NQ = 6


def _tool(name):
    # The virtual environment's cmake/ninja (pip's) first, then whatever PATH offers.
    search = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    return shutil.which(name, path=search)


def _run(cmd, timeout=900):
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        pytest.fail(f"command failed (exit {proc.returncode}): {' '.join(map(str, cmd))}\n"
                    f"--- stdout (tail) ---\n{proc.stdout[-4000:]}\n"
                    f"--- stderr (tail) ---\n{proc.stderr[-4000:]}")
    return proc


@pytest.fixture(scope="module")
def embed_demo(tmp_path_factory, firmware_prefix):
    """Path of embed_demo, built against the session's installed kiloloop (once per module)."""
    cmake = _tool("cmake")
    if cmake is None:
        pytest.fail("cmake not found (neither beside the Python interpreter nor on PATH): "
                    "install it, e.g. `pip install cmake ninja` in the virtual environment")
    ninja = _tool("ninja")
    generator = ["-G", "Ninja", f"-DCMAKE_MAKE_PROGRAM={ninja}"] if ninja else []

    prefix, example = firmware_prefix, tmp_path_factory.mktemp("embed") / "example"
    _run([cmake, "-S", EXAMPLE, "-B", example, *generator, "-DCMAKE_BUILD_TYPE=Release",
          f"-DCMAKE_PREFIX_PATH={prefix}"])
    _run([cmake, "--build", example, "--parallel"])

    # The example must have found the installed package, not anything from the source tree.
    cache = (example / "CMakeCache.txt").read_text()
    found = re.search(r"^kiloloop_DIR:PATH=(.*)$", cache, re.MULTILINE)
    assert found and Path(found.group(1)).resolve().is_relative_to(prefix.resolve()), found
    return example / "embed_demo"


def _parse(stdout):
    """'tick tau_0 .. tau_5 status' lines -> list of (tick, [tau], status); %a parsed exactly."""
    rows = []
    for line in stdout.splitlines():
        fields = line.split()
        assert len(fields) == NQ + 2, f"malformed line: {line!r}"
        rows.append((int(fields[0]), [float.fromhex(f) for f in fields[1:-1]], int(fields[-1])))
    return rows


def _load_twin():
    spec = importlib.util.spec_from_file_location("embed_twin", EXAMPLE / "embed_twin.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_embed_demo_bit_identical_to_python_twin(embed_demo):
    proc = subprocess.run([embed_demo, URDF], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    cpp = _parse(proc.stdout)
    twin = _load_twin().run(URDF)

    assert len(cpp) == len(twin) == TICKS
    assert [r[0] for r in cpp] == list(range(TICKS))
    for (tick, tau_cpp, status_cpp), (tick_py, tau_py, status_py) in zip(cpp, twin):
        assert tick == tick_py
        assert all(math.isfinite(t) for t in tau_cpp), f"tick {tick}: non-finite torque {tau_cpp}"
        # Exact equality, compared as bit patterns (also tells -0.0 from 0.0).
        assert [t.hex() for t in tau_cpp] == [t.hex() for t in tau_py], f"tick {tick}"
        assert status_cpp == status_py, f"tick {tick}"
        assert status_cpp == 0, f"tick {tick}: status {status_cpp}"
    # The replay is not trivial: the torques move (a constant output would prove little).
    assert len({tuple(tau) for _, tau, _ in cpp}) == TICKS


def test_embed_demo_closed_loop_tracks(embed_demo):
    proc = subprocess.run([embed_demo, URDF, "--plant"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    rows = _parse(proc.stdout)
    assert len(rows) == TICKS
    assert all(math.isfinite(t) for _, tau, _ in rows for t in tau)
    assert all(status == 0 for _, _, status in rows)
    # Computed torque on a plant that is the model itself: only the 1 ms discretization is left.
    error = float(re.search(r"max tracking error (\S+) rad", proc.stderr).group(1))
    assert error < 1e-3, proc.stderr


def test_embed_demo_rejects_a_missing_model(embed_demo, tmp_path):
    proc = subprocess.run([embed_demo, tmp_path / "missing.urdf"], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 1
    assert "cannot open" in proc.stderr and proc.stdout == ""
