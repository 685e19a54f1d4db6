"""arm-line: an arm's end effector follows a Cartesian straight line with slerp orientation.

The reference is a `CartesianLine` (Corke's `ctraj`: straight line, fixed-axis rotation, quintic
time scaling) sampled at 1 kHz; the compiled `CartesianTrackingController` turns it into a joint
reference by differential IK (CLIK, damped least squares near singularities) and into torques by
computed torque. The plant is MuJoCo built from the same robot file. The end-effector error is
measured on MuJoCo's `ee_site`, against the line itself. Any arm: the line starts at the robot's
work pose; unless given, its length is 20 % of the reach and its rotation 0.5 rad, along the first
of a fixed list of directions whose line the IK can follow within the limits
(scenarios/arm_targets.py).
The loop runs in C++ (sil/rig.py).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..errors import configuring
from ..sil.arm_adapters import CartesianTracking
from ..sil.rig import Rig
from ..sil.signals import Signals
from .arm_controllers import joint_config
from .arm_targets import line_target, work_pose
from ..sil.native import Observe
from . import ScenarioResult, evaluate
from .plots import ARM_LINE_PLOT

NAME = "arm-line"
DESCRIPTION = "arm end effector on a Cartesian straight line + slerp (differential IK + computed torque)"
DURATION = 3.0  # [s] default simulated time: 0.25 s still, 2.25 s line, 0.5 s holding the end
DEFAULTS = {
    # Empty: derived (20 % of the reach, 0.5 rad; see the module doc).
    "displacement": [],                   # [m] line end minus start, chain root frame
    "rotation": [],                       # [rad] rotation vector from start to end orientation, root frame
    "q_start": [],                        # [rad] empty: the robot's work pose
    "t_start": 0.25,                      # [s] the line starts
    "line_duration": 2.25,                # [s]
    "task_gain": 50.0,                    # [1/s] CLIK gain on the differential-IK reference
    "physics_dt": 0.001,                  # [s] MuJoCo timestep
    "measurement_delay": 0.0,             # [s] age of the controller's measurement
}
# Robot-file tables it reads (scenarios/__init__.py): the chain, the plant, the joint controller.
ROBOT_KEYS = ("chain", "sim", "controller")
SIZES = {"q_start": "nq", "displacement": 3, "rotation": 3}
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"physics_dt": (">", 0.0), "measurement_delay": (">=", 0.0), "t_start": (">=", 0.0),
          "line_duration": (">", 0.0)}
CRITERIA = {
    "max_ee_error_m": ("<", 1e-3),
    "max_ee_orientation_error_rad": ("<", 5e-3),
}


def _rotation(rotvec) -> np.ndarray:
    """Rotation matrix of a rotation vector (Rodrigues)."""
    w = np.asarray(rotvec, dtype=float)
    angle = np.linalg.norm(w)
    if angle == 0.0:
        return np.eye(3)
    k = w / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _angle(R: np.ndarray) -> float:
    """Rotation angle of R [rad]; atan2 stays accurate near 0, where arccos(trace) does not."""
    s = 0.5 * np.linalg.norm([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return float(np.arctan2(s, (np.trace(R) - 1.0) / 2.0))


def make_line(model, q0, settings):
    start = kl.Dynamics(model).forward_kinematics(q0)
    end = start.copy()
    end[:3, 3] += np.asarray(settings["displacement"], dtype=float)
    end[:3, :3] = _rotation(settings["rotation"]) @ start[:3, :3]
    return kl.CartesianLine(start, end, settings["t_start"], settings["line_duration"])


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    del seed  # deterministic: no noise in this scenario
    robot = robot or kl.Robot.load("ur5")
    rig = Rig(robot, Signals(measurement_delay=settings["measurement_delay"]),
              video=settings.get("video"), physics_dt=settings["physics_dt"])
    plant, model = rig.plant, rig.model
    q0 = np.asarray(settings["q_start"], float) if len(settings["q_start"]) else work_pose(
        robot, model, plant)
    if not len(settings["displacement"]) or not len(settings["rotation"]):
        d, r = line_target(rig, q0, settings["line_duration"])
        settings = dict(settings, displacement=settings["displacement"] or d.tolist(),
                        rotation=settings["rotation"] or r.tolist())
    plant.q0 = q0
    plant.reset()
    line = make_line(model, q0, settings)
    config = kl.CartesianTrackingConfig()
    config.task_gain = np.full(6, float(settings["task_gain"]))
    config.joint = joint_config(robot, model, q0, settings["measurement_delay"])
    with configuring(f"{NAME} controller"):
        reference = CartesianTracking(kl.CartesianTrackingController(model, config), line)

    log = rig.run(DURATION if duration is None else duration, reference,
                  observe=Observe("ee", "ee_rot"))

    # The line lives in the chain's root frame; MuJoCo's site in the world frame.
    T = rig.T_world_root()
    ref = np.einsum("ij,kjl->kil", T, log["pose_ref"])
    ee_err = np.linalg.norm(log["ee"] - ref[:, :3, 3], axis=1)
    rot_err = np.array([_angle(R_ref.T @ R) for R_ref, R in zip(ref[:, :3, :3], log["ee_rot"])])
    log.put("ee_ref", ref[:, :3, 3])
    log.put("ee_err_mm", ee_err * 1e3)
    log.put("ee_rot_err_mrad", rot_err * 1e3)
    ik_err = np.linalg.norm(log["ik_error"][:, :3], axis=1)
    statuses = log["status"]
    metrics = {
        "max_ee_error_m": float(ee_err.max()),
        "rms_ee_error_m": float(np.sqrt(np.mean(ee_err ** 2))),
        "max_ee_orientation_error_rad": float(rot_err.max()),
        "max_ik_reference_error_m": float(ik_err.max()),
        "line_length_m": float(line.length),
        "line_angle_rad": float(line.angle),
        "max_abs_torque_Nm": float(np.abs(log["tau"]).max()),
        "saturated_ticks": int(np.sum(statuses == int(kl.Status.SATURATED))),
        "failed_ticks": int(np.sum(statuses < 0)),
        "ticks": int(len(statuses)),
    }
    settings = dict(settings, q_start=q0.tolist())
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, settings)


def plot_signals():
    """What `--plot` draws for this scenario (scenarios/plots.py)."""
    return ARM_LINE_PLOT
