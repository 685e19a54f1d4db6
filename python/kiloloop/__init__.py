"""kiloloop: a deterministic 1 kHz robot control core (C++), bound to Python.

The compiled core lives in `kiloloop._core`; its classes are re-exported here so that
`import kiloloop as kl; kl.RobotModel.from_urdf(...)` works. The SIL plant, loop, scenarios and
CLI are pure Python around that core.

Typed: the package ships `py.typed` and `.pyi` stubs of `_core` generated from the built module
at build time (cmake/stubs.cmake), so an IDE and mypy see every class, field and signature.
When gymnasium is installed, importing the package registers its environments
(`gymnasium.make("kiloloop/QuadrupedTrot-v0")`, kiloloop/envs/): registration only.
"""
import os as _os
import typing as _typing
from importlib.resources import files as _files
from pathlib import Path as _Path

# MuJoCo picks its OpenGL platform when it is first imported: without a screen, render offscreen
# on the CPU (Debian's libosmesa6), which `--video` needs. A user's own MUJOCO_GL wins.
if not (_os.environ.get("DISPLAY") or _os.environ.get("WAYLAND_DISPLAY")):
    _os.environ.setdefault("MUJOCO_GL", "osmesa")

# `import X as X`: an explicit re-export, as type checkers want it (mypy --strict).
from ._core import *  # noqa: F401,F403
from ._core import __version__ as __version__
from ._core import qp as qp  # kl.qp.solve, kl.qp.DenseQpSolver
from ._core import detmath as detmath  # musl's sin, cos, ... as the core calls them
from .robot import Robot as Robot, RobotFileError as RobotFileError  # robot files: docs/robots.md

if _typing.TYPE_CHECKING:  # kl.sil is imported on first use (__getattr__ below)
    from . import sil as sil


def models_dir() -> _Path:
    """Directory holding the robot models (URDF + sim overlay), installed with the package."""
    return _Path(str(_files("kiloloop") / "models"))


def model_files(robot) -> tuple[_Path, dict]:
    """A robot's URDF path and its simulator sections ([sim.*] of its robot file), as the plants
    take them. `robot`: a name in models/, a robot file or directory, or a loaded `Robot`."""
    r = robot if isinstance(robot, Robot) else Robot.load(robot)
    return r.urdf, r.sim


def __getattr__(name: str) -> _typing.Any:
    # kl.sil (batch runs, the native loop) on first use: `import kiloloop` stays light.
    if name == "sil":
        import importlib

        return importlib.import_module(".sil", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _register_envs() -> None:
    """The gymnasium environments (kiloloop/envs/) into gymnasium's registry when gymnasium is
    installed, as ale_py and gymnasium_robotics do on import: `gymnasium.make("kiloloop/...")`
    then works after the usual `import kiloloop`. Registration only: the entry points are
    strings, MuJoCo and the environments' modules load when one is made. Without gymnasium
    nothing is imported (find_spec looks for it without importing it). gymnasium 1.x has no
    plugin discovery (the `gymnasium.envs` entry-point group was removed in 1.0.0), so a package
    registers on its own import."""
    from importlib.util import find_spec

    if find_spec("gymnasium") is None:
        return
    try:
        from . import envs  # noqa: F401  (registers on import)
    except ImportError as e:  # installed but broken: kiloloop itself still imports
        import warnings

        warnings.warn(f"kiloloop: gymnasium is installed but does not import ({e}); the "
                      "kiloloop/ environments are not registered", RuntimeWarning, stacklevel=2)


_register_envs()
