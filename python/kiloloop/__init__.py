"""kiloloop: a deterministic 1 kHz robot control core (C++), bound to Python.

The compiled core lives in `kiloloop._core`; its classes are re-exported here so that
`import kiloloop as kl; kl.RobotModel.from_urdf(...)` works. The SIL plant, loop, scenarios and
CLI are pure Python around that core.
"""
from importlib.resources import files as _files
from pathlib import Path as _Path

from ._core import *  # noqa: F401,F403
from ._core import __version__  # noqa: F401
from ._core import qp  # noqa: F401  (kl.qp.solve, kl.qp.DenseQpSolver)


def models_dir() -> _Path:
    """Directory holding the robot models (URDF + sim overlay), installed with the package."""
    return _Path(str(_files("kiloloop") / "models"))


def model_files(robot: str) -> tuple[_Path, _Path]:
    """A robot's URDF and its simulator overlay: models/<robot>/<robot>.urdf and sim.toml."""
    base = models_dir() / robot
    return base / f"{robot}.urdf", base / "sim.toml"
