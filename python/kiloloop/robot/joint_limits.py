"""Joint limits the URDF lacks, named, and the robot file's `[limits.<joint>]` applied to the URDF
that every model of the robot reads (robot/urdf_doc.py): the controller's and the plant's.

A continuous joint without <limit>, or a <limit> whose effort or velocity is 0 or absent (URDF's
"not given"), loads with an infinite limit: the controller never clips that joint's torque, the
plant's motor is unbounded, a trajectory may take any speed. missing() names each such joint and
what it lacks (`kiloloop robot check` warns); `[limits.<joint>]` sets any of `lower`, `upper`
([rad] or [m]), `velocity` ([rad/s] or [m/s]) and `effort` ([N m] or [N]). Position limits on a
continuous joint make it revolute: both loaders ignore a continuous joint's range.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from typing import Callable

from .errors import RobotFileError

KEYS = ("lower", "upper", "velocity", "effort")
ACTUATED = ("revolute", "continuous", "prismatic")


def _units(joint: ET.Element) -> dict[str, str]:
    linear = joint.get("type") == "prismatic"
    return {"lower": "m" if linear else "rad", "upper": "m" if linear else "rad",
            "velocity": "m/s" if linear else "rad/s", "effort": "N" if linear else "N m"}


def _given(limit: ET.Element | None, key: str) -> float | None:
    """The URDF's value, None when absent, not a number (the C++ loader's refusal) or, for
    effort and velocity, 0 (URDF's "not given")."""
    try:
        value = float(limit.get(key)) if limit is not None and limit.get(key) is not None else None
    except ValueError:
        return None
    if value is not None and key in ("effort", "velocity") and value <= 0:
        return None
    return value


def missing(root: ET.Element) -> dict[str, str]:
    """joint -> one line naming what its URDF leaves unlimited and the robot-file keys that set
    it, for each actuated joint lacking an effort or a velocity limit (document order)."""
    out = {}
    for joint in root.findall("joint"):
        if joint.get("type") not in ACTUATED:
            continue
        limit = joint.find("limit")
        lacks = [k for k in ("effort", "velocity") if _given(limit, k) is None]
        if lacks:
            name, units = joint.get("name"), _units(joint)
            why = f"{joint.get('type')} joint without <limit>" if limit is None else \
                "its <limit> gives " + ", ".join(f"{k} {limit.get(k) or 'none'}" for k in lacks)
            keys = ", ".join(f"{k} = ... [{units[k]}]" for k in lacks)
            out[name] = (f"joint '{name}': no {' and no '.join(lacks)} limit ({why}): infinite in "
                         f"the controller's model and the plant; set [limits.{name}] {keys} in "
                         f"the robot file")
    return out


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def apply(root: ET.Element, table: dict, where: Callable[[str], str]) -> list[str]:
    """Sets each `[limits.<joint>]` of `table` on `root`'s joints (in place). Returns one line per
    joint changed. An unknown joint or key, a value that is not a number, an effort or velocity
    <= 0 or a lower limit not below the upper one raises RobotFileError naming the key
    (`where(dotted key)`: the file or --set, and the key)."""
    if not isinstance(table, dict):
        raise RobotFileError(f"{where('limits')}: expected tables [limits.<joint>]")
    joints = {j.get("name"): j for j in root.findall("joint")}
    lines = []
    for name, values in table.items():
        key = f"limits.{name}"
        joint = joints.get(name)
        if joint is None or joint.get("type") not in ACTUATED:
            raise RobotFileError(f"{where(key)}: the URDF has no revolute, continuous or "
                                 f"prismatic joint named {name!r}")
        if not isinstance(values, dict):
            raise RobotFileError(f"{where(key)}: expected a table of {', '.join(KEYS)}")
        for k, v in values.items():
            if k not in KEYS:
                raise RobotFileError(f"{where(f'{key}.{k}')}: unknown key; [limits.<joint>] takes "
                                     f"{', '.join(KEYS)}")
            if not _number(v):
                raise RobotFileError(f"{where(f'{key}.{k}')}: expected a finite number, got {v!r}")
            if k in ("effort", "velocity") and v <= 0:
                raise RobotFileError(f"{where(f'{key}.{k}')}: expected > 0, got {v!r}")
        lines.append(_set(joint, values, key, where))
    return lines


def check(urdf_path, table, where: Callable[[str], str]) -> None:
    """apply() on a copy of the URDF at `urdf_path`, for its errors only (a robot file's load);
    a file that is not XML is the C++ loader's to refuse."""
    try:
        root = ET.parse(urdf_path).getroot()
    except (ET.ParseError, OSError):
        return
    apply(root, table, where)


def _set(joint: ET.Element, values: dict, key: str, where: Callable[[str], str]) -> str:
    limit = joint.find("limit")
    old = {k: _given(limit, k) for k in KEYS}
    continuous = joint.get("type") == "continuous"
    if continuous:
        old["lower"] = old["upper"] = None  # a continuous joint's range is ignored
        if ("lower" in values) != ("upper" in values):
            raise RobotFileError(f"{where(key)}: joint {joint.get('name')!r} is continuous: give "
                                 f"both lower and upper, or neither")
    new = {k: float(values[k]) if k in values else old[k] for k in KEYS}
    if new["lower"] is not None and new["upper"] is not None and not new["lower"] < new["upper"]:
        raise RobotFileError(f"{where(key)}: lower {new['lower']:g} is not below upper "
                             f"{new['upper']:g}")
    if limit is None:
        limit = ET.SubElement(joint, "limit")
    for k in KEYS:
        if k in values:
            limit.set(k, repr(float(values[k])))
    for k in ("effort", "velocity"):  # urdfdom requires both; 0 is URDF's "not given"
        if limit.get(k) is None:
            limit.set(k, "0")
    if continuous and "lower" in values:
        joint.set("type", "revolute")
    units = _units(joint)
    changes = ", ".join(f"{k} {values[k]:g} {units[k]} (URDF: "
                        f"{'none' if old[k] is None else f'{old[k]:g}'})"
                        for k in KEYS if k in values)
    made_revolute = " (continuous -> revolute)" if continuous and "lower" in values else ""
    return f"joint '{joint.get('name')}'{made_revolute}: {changes} from [{key}]"
