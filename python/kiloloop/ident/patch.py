"""The robot-file patch `identify` writes: a complete robot file, the nominal one's tables with the
identified values in their places, so that `--robot PATCH.toml` applies it with no new loader:

    [sim.joints] damping, frictionloss, armature     (an arm's, or a multirotor's arm)
    [scenario.<name>] measurement_delay / motor_delay (every scenario of the family that has it;
                                                       robot files hold delays there, declared.py)
    [[rotors]] thrust_max, torque_coefficient, time_constant  (a multirotor)
    urdf = "PATCH.urdf"                               (a payload: the nominal URDF with it merged
                                                       into the last link, payload_urdf.py)

Paths the nominal file gives relative to itself (urdf, package_dirs) are rewritten relative to the
patch. The estimates, their standard errors and the residual head the file as comments.
"""
from __future__ import annotations

import copy
import os
from pathlib import Path

from .declared import DELAY_KEY, delay_scenarios
from .toml_out import dumps


def _relative(path: Path, to_dir: Path) -> str:
    try:
        return os.path.relpath(path.resolve(), to_dir.resolve())
    except ValueError:  # another drive
        return str(path.resolve())


def _rounded(values, digits: int = 6) -> list:
    return [float(f"{float(v):.{digits}g}") for v in values]


def robot_data(robot, out_path: Path) -> dict:
    """A copy of the robot file's tables with its paths relative to out_path's directory."""
    data = copy.deepcopy(robot.data)
    data["urdf"] = _relative(robot.urdf, out_path.parent)
    if "package_dirs" in data:
        data["package_dirs"] = [_relative(robot.dir / d, out_path.parent)
                                for d in data["package_dirs"]]
    return data


def set_delay(data: dict, kind: str, delay: float) -> None:
    """The family's delay setting in every scenario table that takes it."""
    key = DELAY_KEY[kind]
    for name in delay_scenarios(kind):
        data.setdefault("scenario", {}).setdefault(name, {})[key] = float(delay)


def set_joints(data: dict, damping, frictionloss, armature) -> None:
    joints = data.setdefault("sim", {}).setdefault("joints", {})
    joints["damping"] = _rounded(damping)
    joints["frictionloss"] = _rounded(frictionloss)
    joints["armature"] = _rounded(armature)


def write(data: dict, out_path, header: list[str]) -> Path:
    out = Path(out_path)
    out.parent.mkdir(parents=True, exist_ok=True)
    text = "".join(f"# {line}\n" if line else "#\n" for line in header)
    out.write_text(text + "\n" + dumps(data))
    return out
