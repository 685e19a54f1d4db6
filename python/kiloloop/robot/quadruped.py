"""Quadruped robot files: what the file does not say, derived from its URDF.

The controller derives the rest itself at configure (stand height and pose, composite inertia,
gains and thresholds from masses, inertias, effort limits and the actuation delay; see
QuadrupedConfig); this module adds what needs the URDF's collision geometry (the foot sphere's
radius and centre), maps the file's [legs] and [controller] tables onto kl.QuadrupedConfig, and
gives the plant its start pose. `kiloloop robot check FILE` prints what it derived
(robot_check/quadruped.py).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np

from .foot_geometry import foot_contact as _foot_contact
from .urdf_joints import urdf_joints

# Nested config structs of kl.QuadrupedConfig (robot-file tables [controller.gait] ...).
_NESTED = ("gait", "contact", "estimator", "force")
_KNEES = {"auto": "AUTO", "backward": "BACKWARD", "forward": "FORWARD"}


def _fields(obj) -> list[str]:
    return [k for k in dir(obj) if not k.startswith("_") and not callable(getattr(obj, k))]


def controller_schema() -> dict:
    """Accepted [controller] keys: the fields of kl.QuadrupedConfig (nested tables for its
    sub-structs), generated so that the schema cannot drift from the C++ struct."""
    from .. import _core

    config = _core.QuadrupedConfig()
    out = {}
    for key in _fields(config):
        out[key] = ({k: None for k in _fields(getattr(config, key))} if key in _NESTED else None)
    return out


def foot_contact(robot) -> tuple[np.ndarray, float]:
    """The first foot's contact sphere, (centre in the foot link's frame [m] (3,), radius [m])
    (robot/foot_geometry.py: a sphere reaching lowest gives itself, offset or not; meshes,
    cylinders and boxes a sphere about the origin down to their lowest point); a point foot at
    the origin when [legs] names no feet."""
    legs = robot.section("legs")
    feet = legs.get("feet") or []
    if not feet:
        return np.zeros(3), 0.0
    base = legs.get("base")
    if not base:  # the URDF's root link
        root = ET.fromstring(robot.urdf_text())
        children = {j.find("child").get("link") for j in root.findall("joint") if j.find("child") is not None}
        base = next((l.get("name") for l in root.findall("link") if l.get("name") not in children), "")
    return _foot_contact(robot.urdf, feet[0], base, robot.package_dirs)


def _assign(obj, key: str, value, where: str) -> None:
    """obj.key = value converted to the field's type; `where` prefixes an error (the file or
    --set, and the key's table). A list field takes one number for every entry or one per entry
    (a per-joint field: 12 on a 12-joint robot)."""
    from .. import _core
    from .errors import RobotFileError

    if not hasattr(obj, key):
        raise RobotFileError(f"{where}{key}: not a controller setting")
    current = getattr(obj, key)
    if key == "knees":
        values = value if isinstance(value, list) else [value] * 4
        try:
            value = [getattr(_core.KneeDirection, _KNEES[str(v).lower()]) for v in values]
        except KeyError:
            raise RobotFileError(f"{where}knees: expected auto, backward or forward") from None
    elif isinstance(current, np.ndarray):
        count = current.size if current.ndim == 1 else "x".join(map(str, current.shape))
        try:
            if isinstance(value, (str, bool)) or (isinstance(value, list) and any(
                    isinstance(v, (str, bool)) for v in value)):
                raise TypeError
            value = np.broadcast_to(np.asarray(value, dtype=float), current.shape).copy()
        except (TypeError, ValueError):
            given = f"{len(value)} values" if isinstance(value, list) else repr(value)
            raise RobotFileError(f"{where}{key}: expected 1 or {count} numbers, got "
                                 f"{given}") from None
    elif isinstance(current, bool):
        if not isinstance(value, bool):
            raise RobotFileError(f"{where}{key}: expected true or false, got {value!r}")
    elif isinstance(current, (int, float)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or (
                isinstance(current, int) and value != int(value)):
            kind = "a whole number" if isinstance(current, int) else "a number"
            raise RobotFileError(f"{where}{key}: expected {kind}, got {value!r}")
        value = type(current)(value)
    setattr(obj, key, value)


def controller_config(robot, actuation_delay: float | None = None):
    """kl.QuadrupedConfig for the robot: trunk and feet from [legs], the foot sphere (centre and
    radius) from the URDF, the declared actuation delay, then the file's [controller] table
    (which wins)."""
    from .. import _core
    from .errors import RobotFileError

    config = _core.QuadrupedConfig()
    legs = robot.section("legs")
    if legs.get("base"):
        config.trunk_link = legs["base"]
    if legs.get("feet"):
        if len(legs["feet"]) != 4:
            raise RobotFileError(f"{robot.path}: legs.feet: expected 4 links (FL, FR, RL, RR), "
                                 f"got {len(legs['feet'])}")
        config.feet = list(legs["feet"])
    config.foot_offset, config.foot_radius = foot_contact(robot)
    if actuation_delay is not None:
        config.actuation_delay = float(actuation_delay)
    for key, value in robot.section("controller").items():
        if key in _NESTED and isinstance(value, dict):
            sub = getattr(config, key)
            for k, v in value.items():
                _assign(sub, k, v, _where(robot, f"controller.{key}.{k}"))
            setattr(config, key, sub)
        else:
            _assign(config, key, value, _where(robot, f"controller.{key}"))
    try:
        config.validate()
    except ValueError as e:  # the C++ check of the values: the file (or a --set) gave them
        raise RobotFileError(f"{robot.path}{' (with --set)' if robot.overrides else ''}: "
                             f"{str(e).strip().splitlines()[0]}") from None
    return config


def _where(robot, dotted: str) -> str:
    """The prefix _assign's errors take: `--set controller.` or `FILE: controller.`."""
    return robot.where(dotted)[: -len(dotted.rsplit(".", 1)[-1])]


def plant_overlay(robot, controller) -> dict:
    """The plant's [sim] sections with what the robot file leaves out: the joints start in the
    controller's standing pose (URDF order), the IMU on the base, the feet from [legs] with the
    controller's foot sphere centre (the point the plant reports as each foot's position)."""
    sim = robot.sim
    joints = sim.setdefault("joints", {})
    if joints.get("q0") is None:
        names, _ = urdf_joints(robot.urdf)
        stand = dict(zip(controller.joint_names, np.asarray(controller.stand_pose)))
        joints["q0"] = [float(stand.get(n, 0.0)) for n in names]
    legs = robot.section("legs")
    imu = sim.setdefault("imu", {})
    if not imu.get("body") and legs.get("base"):
        imu["body"] = legs["base"]
    feet = sim.setdefault("feet", {})
    if not feet.get("bodies") and legs.get("feet"):
        feet["bodies"] = list(legs["feet"])
    if feet.get("offset") is None:
        feet["offset"] = [float(x) for x in np.asarray(controller.config.foot_offset)]
    return sim
