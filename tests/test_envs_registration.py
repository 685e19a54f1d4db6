"""`import kiloloop` registers the gymnasium environments (issue 32): registration only (MuJoCo
and the environments' modules stay unimported until one is made), nothing at all without
gymnasium, a warning instead of an ImportError when gymnasium is installed but broken, and
gymnasium.make by the short id. The old "kiloloop.envs:" prefix: tests/test_quadruped_env.py."""
import json
import os
import subprocess
import sys
import textwrap

import pytest

import kiloloop
from kiloloop.sil import native

SHORT_ID = "kiloloop/QuadrupedTrot-v0"


def _python(code: str, env: dict | None = None) -> subprocess.CompletedProcess:
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                         text=True, timeout=120, env=env)
    assert out.returncode == 0, out.stderr
    return out


def test_import_registers_without_importing_mujoco_or_the_envs():
    pytest.importorskip("gymnasium")
    out = _python("""
        import json, sys
        import kiloloop
        loaded = sorted(m for m in sys.modules if m == "mujoco" or m.startswith(
            ("mujoco.", "kiloloop.sil", "kiloloop.scenarios", "kiloloop.envs.")))
        import gymnasium
        from kiloloop.envs import ENVS
        print(json.dumps({"loaded": loaded, "ids": sorted(ENVS),
                          "registered": [i for i in ENVS if i in gymnasium.registry]}))
    """)
    got = json.loads(out.stdout.strip().splitlines()[-1])
    assert got["loaded"] == [], f"import kiloloop imported {got['loaded']}"
    assert SHORT_ID in got["ids"] and got["registered"] == got["ids"]


def test_import_without_gymnasium_or_with_a_broken_one(tmp_path):
    # Absent: sys.modules["gymnasium"] = None is how the import system says "not there".
    _python("""
        import sys
        sys.modules["gymnasium"] = None
        import kiloloop
        assert "kiloloop.envs" not in sys.modules and sys.modules["gymnasium"] is None
    """)
    # Installed but failing to import: a warning, kiloloop imports.
    (tmp_path / "gymnasium").mkdir()
    (tmp_path / "gymnasium" / "__init__.py").write_text("raise ImportError('broken on purpose')\n")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(tmp_path), env.get("PYTHONPATH", "")])
    out = _python("import kiloloop; print(kiloloop.RobotModel.__name__)", env)
    assert out.stdout.strip() == "RobotModel"
    assert "gymnasium is installed but does not import (broken on purpose)" in out.stderr


@pytest.mark.skipif(not native.available(), reason="built without the native loop")
def test_make_by_the_short_id():
    gymnasium = pytest.importorskip("gymnasium")
    assert kiloloop  # imported above: that is all make() needs
    env = gymnasium.make(SHORT_ID, episode_seconds=0.5)
    assert env.spec is not None and env.spec.id == SHORT_ID
    assert type(env.unwrapped).__name__ == "QuadrupedTrotEnv"
    obs, _ = env.reset(seed=0)
    obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
    assert obs.shape == env.observation_space.shape and not terminated
