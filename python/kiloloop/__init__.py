"""kiloloop: a deterministic 1 kHz robot control core (C++), bound to Python.

The compiled core lives in `kiloloop._core`; its classes are re-exported here so that
`import kiloloop as kl; kl.RobotModel.from_urdf(...)` works. The SIL plant, loop, scenarios and
CLI are pure Python around that core.
"""
import os as _os
from importlib.resources import files as _files
from pathlib import Path as _Path

# MuJoCo picks its OpenGL platform when it is first imported: without a screen, render offscreen
# on the CPU (Debian's libosmesa6), which `--video` needs. A user's own MUJOCO_GL wins.
if not (_os.environ.get("DISPLAY") or _os.environ.get("WAYLAND_DISPLAY")):
    _os.environ.setdefault("MUJOCO_GL", "osmesa")

from ._core import *  # noqa: F401,F403
from ._core import __version__  # noqa: F401
from ._core import qp  # noqa: F401  (kl.qp.solve, kl.qp.DenseQpSolver)
from ._core import detmath  # noqa: F401  (musl's sin, cos, ... as the core calls them)
from .robot import Robot, RobotFileError  # noqa: F401  (robot files: docs/robots.md)


def models_dir() -> _Path:
    """Directory holding the robot models (URDF + sim overlay), installed with the package."""
    return _Path(str(_files("kiloloop") / "models"))


def model_files(robot) -> tuple[_Path, dict]:
    """A robot's URDF path and its simulator sections ([sim.*] of its robot file), as the plants
    take them. `robot`: a name in models/, a robot file or directory, or a loaded `Robot`."""
    r = robot if isinstance(robot, Robot) else Robot.load(robot)
    return r.urdf, r.sim


def __getattr__(name: str):
    # kl.sil (batch runs, the native loop) on first use: `import kiloloop` stays light.
    if name == "sil":
        import importlib

        return importlib.import_module(".sil", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
