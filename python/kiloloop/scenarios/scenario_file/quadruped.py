"""A scenario file on a quadruped: the velocity profile, sampled at every tick, is the command
of the robot file's QuadrupedController in the native loop (the command changes are reference
events: nothing runs in Python per tick). The gait stands until the command first moves and
trots from then on, unless the file gives a gait per point. The run stops early when the trunk
falls to 40 % of its standing height (the built-in trotting scenarios' rule)."""
from __future__ import annotations

import numpy as np

from ...errors import InputError
from ...sil import events as sil_events
from ...sil.quadruped_family import CommandSchedule
from ..quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from ..quadruped_metrics import fell_early, heading_velocity, roll_pitch
from . import common
from .events import Payload, Push

DEFAULTS = dict(COMMON_DEFAULTS)
FALL_TILT_DEG = 45.0  # [deg] past this the trunk has fallen over (quadruped_metrics.fallen)
JOINTS = 12


def command(reference, duration: float) -> tuple[CommandSchedule, np.ndarray, np.ndarray]:
    """(schedule, per-tick command (ticks, 3) [m/s, m/s, rad/s], per-tick gait 0/1): the profile
    sampled at each tick's time; a segment starts wherever the sample changes."""
    n = max(common.ticks(duration), 1)
    t = np.arange(n) * common.CONTROL_DT
    v = np.stack([reference.sample(k, t) for k in ("vx", "vy", "yaw_rate")], axis=1)
    if reference.gait is not None:
        k = np.clip(np.searchsorted(reference.t, t, side="right") - 1, 0, len(reference.t) - 1)
        gait = np.array([1 if reference.gait[i] == "trot" else 0 for i in k])
    else:
        moving = np.any(v != 0.0, axis=1)
        gait = (np.cumsum(moving) > 0).astype(int)
    changes = [0] + [k for k in range(1, n) if gait[k] != gait[k - 1] or np.any(v[k] != v[k - 1])]
    schedule = CommandSchedule([(k * common.CONTROL_DT, int(gait[k]), v[k]) for k in changes])
    return schedule, v, gait


def run(scenario, robot, settings: dict, seed: int, duration: float, video: str | None):
    rig = rig_from_settings(dict(settings, video=video), seed, robot=robot)
    schedule, v, _ = command(scenario.reference, duration)
    base = rig.plant._base_id
    pushes, payloads = [], []
    for i, e in enumerate(scenario.events):
        if isinstance(e, (Push, Payload)):
            body = base if e.body is None else common.body_id(rig.plant.model, e.body,
                                                              f"events[{i}].body")
            if isinstance(e, Push):
                if body != base:
                    raise InputError(f"events[{i}].body: pushes act on the trunk "
                                     f"({rig.plant.base_body}) on a quadruped")
                pushes.append((e.t, sil_events.Push(e.force, e.duration)))
            else:
                payloads.append((common.ticks(e.t), body, e))
    stages = common.dropout_stages(scenario.events, {"joints": (0, 2 * JOINTS),
                                                     "imu": (2 * JOINTS, 10)})
    log = rig.run(duration, schedule, pushes, stop=fell_early(rig), stages=stages,
                  hooks=common.payload_hooks(payloads))
    return signals(log, rig, v), components(rig)


def signals(log, rig, v):
    """The quadruped's signals (signals.QUADRUPED) into the log."""
    n = len(log["t"])
    roll, pitch = roll_pitch(log["base_quat"])
    w, x, y, z = log["base_quat"].T
    yaw = np.unwrap(np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))
    hv = heading_velocity(log)
    ref = v[:n]
    tilt = np.degrees(np.arccos(np.clip(np.cos(roll) * np.cos(pitch), -1, 1)))
    fell = (log["base_pos"][:, 2] < rig.fall_height) | (tilt > FALL_TILT_DEG)
    log.put_array("roll", np.degrees(roll))
    log.put_array("pitch", np.degrees(pitch))
    log.put_array("yaw", np.degrees(yaw))
    log.put_array("height", log["base_pos"][:, 2])
    log.put_array("vx", hv[:, 0])
    log.put_array("vy", hv[:, 1])
    log.put_array("yaw_rate", log["base_omega"][:, 2])
    log.put_array("vx_ref", ref[:, 0])
    log.put_array("vy_ref", ref[:, 1])
    log.put_array("yaw_rate_ref", ref[:, 2])
    log.put_array("velocity_error", np.linalg.norm(hv - ref[:, :2], axis=1))
    log.put_array("fell", common.cumulative(fell))
    return log


def components(rig) -> dict:
    return {"tau": list(rig.controller.joint_names)}
