"""`kiloloop robot check FILE`: load everything a robot file names and print one screen about it.

Loads the robot file (its [scenario.<name>] tables checked against the scenarios), the URDF, the
controlled model (folded mass included), the MuJoCo plant and the family's controller; prints
joints, limits, masses, what was folded and what was derived. Any failure prints one line naming
the file and what is wrong, and exits 2 (no traceback).

It sits above robot/, sil/ and scenarios/ (it builds plants and reads scenario settings), so that
robot/ itself needs neither: loading a robot file does not import MuJoCo.
"""
from __future__ import annotations

import importlib
import sys
import warnings

import numpy as np

from .. import scenarios
from ..errors import UrdfRepairWarning
from ..robot import Robot


def _fmt(x) -> str:
    if isinstance(x, float):
        return f"{x:.4g}"
    if isinstance(x, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_fmt(float(v)) for v in np.asarray(x, dtype=float).ravel()) + "]"
    return str(x)


def family(kind: str):
    """The family's summary module (robot_check/arm.py, quadruped.py, aerial.py): summary()."""
    return importlib.import_module(f"{__package__}.{kind}")


def summary_lines(robot) -> list[str]:
    scenarios.check_scenario_tables(robot.data.get("scenario", {}), str(robot.path))
    model = robot.model()
    lines = [f"robot {robot.name} ({robot.kind})  file {robot.path}",
             f"  urdf {robot.urdf}",
             f"  model: {model.nq} joints, root '{model.root_name}' -> tip '{model.tip_name}', "
             f"total mass {model.total_mass:.4g} kg"]
    lines.append("  joints:                      lower      upper   velocity     effort")
    for name, lo, up, v, e in zip(model.joint_names, model.lower, model.upper,
                                  model.velocity_limit, model.effort_limit):
        lines.append(f"    {name:<24} {lo:>9.4g}  {up:>9.4g}  {v:>9.4g}  {e:>9.4g}")
    lines.extend(urdf_lines(robot.urdf_doc, model.joint_names))
    folded = getattr(model, "folded_links", None)
    if folded:
        lines.append("  folded into the chain as rigid mass:")
        for link, onto, mass in folded:
            lines.append(f"    {link:<24} onto {onto:<20} {mass:.4g} kg")
    fam = family(robot.kind)
    lines.extend(fam.summary(robot, model))
    return lines


def urdf_lines(doc, joints) -> list[str]:
    """What kiloloop changed in the URDF (the controller's model and the plant read it so:
    robot/urdf_doc.py) and the controlled joints whose limits it leaves infinite."""
    lines = []
    if doc.repairs:
        lines.append("  URDF changes (the controller's model and the plant alike):")
        lines.extend(f"    {line}" for line in doc.repairs)
    lines.extend(f"  warning: {doc.missing_limits[j]}" for j in joints if j in doc.missing_limits)
    return lines


def check(name_or_path, stream=sys.stdout) -> int:
    try:
        with warnings.catch_warnings():
            # Listed among the URDF changes; not said twice.
            warnings.simplefilter("ignore", UrdfRepairWarning)
            robot = Robot.load(name_or_path)
            lines = summary_lines(robot)
    except Exception as e:  # noqa: BLE001 - one clear line, whatever broke
        msg = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        print(f"kiloloop robot check: {msg}", file=sys.stderr)
        return 2
    for line in lines:
        print(line, file=stream)
    print("ok", file=stream)
    return 0
