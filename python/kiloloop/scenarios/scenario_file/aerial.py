"""A scenario file on a multirotor (with or without an arm): the position setpoints become the
per-tick reference table of the robot file's AerialController in the native loop (position,
the segment's velocity as feed-forward, yaw; the arm held at its start pose). The vehicle starts
at rest at the first setpoint, its rotors at the hover share."""
from __future__ import annotations

import numpy as np

from ...errors import InputError
from ...sil.events import Push, RotorFault
from ..aerial_settings import COMMON_DEFAULTS, rig_from_settings
from ..aerial_metrics import rotation_vector_error
from ...sil.aerial_signals import reference_row
from . import common
from .events import Payload
from .events import Push as PushEvent
from .events import RotorFault as RotorFaultEvent

DEFAULTS = dict(COMMON_DEFAULTS)
DIVERGED_TILT_DEG = 60.0  # [deg] the controller's own safe-stop tilt


class SetpointTable:
    """The reference as the aerial adapter's table (one row per tick, AerialAdapter::Ref;
    sil/aerial_signals.reference_table takes a command's own table())."""

    def __init__(self, reference, q0):
        self.reference, self.q0 = reference, np.asarray(q0, float)

    def table(self, controller, ticks: int) -> np.ndarray:
        inp = controller.make_input()
        inp.q_ref[:] = self.q0
        rows = np.tile(reference_row(inp, controller.nq), (ticks, 1))
        t = np.arange(ticks) * common.CONTROL_DT
        rows[:, 0:3] = self.reference.sample("xyz", t)
        rows[:, 3:6] = self.reference.slope("xyz", t)
        rows[:, 9] = self.reference.sample("yaw", t)
        return rows


def run(scenario, robot, settings: dict, seed: int, duration: float, video: str | None):
    rig = rig_from_settings(dict(settings, video=video), seed, robot=robot)
    start = scenario.reference.values["xyz"][0]
    rig.plant.reset(base_pos=start)
    rig.hover_pos = np.asarray(start, float).copy()
    command = SetpointTable(scenario.reference, rig.plant.q0.copy()[rig.to_ctrl])
    base = rig.plant._base_id
    events, payloads = [], []
    for i, e in enumerate(scenario.events):
        if isinstance(e, PushEvent):
            if e.body is not None and common.body_id(rig.plant.model, e.body,
                                                     f"events[{i}].body") != base:
                raise InputError(f"events[{i}].body: pushes act at the vehicle's CoM on a "
                                 f"multirotor")
            events.append((e.t, Push(e.force, e.duration)))
        elif isinstance(e, RotorFaultEvent):
            if e.rotor >= rig.n_rotors:
                raise InputError(f"events[{i}].rotor: {e.rotor} is not a rotor of "
                                 f"{robot.name} (0..{rig.n_rotors - 1})")
            events.append((e.t, RotorFault(e.rotor, e.efficiency)))
        elif isinstance(e, Payload):
            body = base if e.body is None else common.body_id(rig.plant.model, e.body,
                                                              f"events[{i}].body")
            payloads.append((common.ticks(e.t), body, e))
    nq = rig.plant.nq
    # y = [position (3); velocity (3); gyro; accel; quat; q (nq); qd (nq)] (sil/aerial_family.py)
    stages = common.dropout_stages(scenario.events, {"position": (0, 6), "imu": (6, 10),
                                                     "joints": (16, 2 * nq)})
    log = rig.run(duration, command, events, stages=stages, hooks=common.payload_hooks(payloads))
    return signals(log, rig), components(rig)


def signals(log, rig):
    """The multirotor's signals (signals.AERIAL) into the log."""
    n = len(log["t"])
    diverged_at = n if "diverged" not in log else n - 1   # the native loop stops on a NaN state
    pos = log["base_pos"]
    att = np.degrees(np.linalg.norm(rotation_vector_error(log["base_quat"], log["quat_des"]), axis=1))
    w, x, y, z = log["base_quat"].T
    tilt = np.degrees(np.arccos(np.clip(1 - 2 * (x * x + y * y), -1.0, 1.0)))
    bad = (~np.all(np.isfinite(pos), axis=1)) | (log["safe_stop"] > 0) | (tilt > DIVERGED_TILT_DEG)
    bad[diverged_at:] = True
    log.put_array("position", pos)
    log.put_array("position_ref", log["pos_ref"])
    log.put_array("position_error", np.linalg.norm(pos - log["pos_ref"], axis=1))
    log.put_array("attitude_error", att)
    log.put_array("tilt", tilt)
    log.put_array("diverged", common.cumulative(bad))
    return log


def components(rig) -> dict:
    xyz = ["x", "y", "z"]
    joints = list(rig.model.joint_names) if rig.controller.nq else []
    return {"position": xyz, "position_ref": xyz, "q": joints, "tau": joints,
            "thrust": [f"rotor{k}" for k in range(rig.n_rotors)]}
