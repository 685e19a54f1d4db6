"""arm-line: the UR5 end effector follows a Cartesian straight line with slerp orientation.

The reference is a `CartesianLine` (Corke's `ctraj`: straight line, fixed-axis rotation, quintic
time scaling) sampled at 1 kHz; the compiled `CartesianTrackingController` turns it into a joint
reference by differential IK (CLIK, damped least squares near singularities) and into torques by
computed torque. The plant is MuJoCo built from the same URDF (models/ur5/ur5.urdf + sim.toml).
The end-effector error is measured on MuJoCo's `ee_site`, against the line itself.
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil.log import SignalLog
from ..sil.loop import LoopSettings, Measurement, run_loop
from ..sil.plant import MujocoPlant
from . import ScenarioResult, evaluate

NAME = "arm-line"
DESCRIPTION = "UR5 end effector on a Cartesian straight line + slerp (differential IK + computed torque)"
DURATION = 3.0  # [s] default simulated time: 0.25 s still, 2.25 s line, 0.5 s holding the end
DEFAULTS = {
    "displacement": [0.15, 0.20, -0.15],  # [m] line end minus start, root (world) frame
    "rotation": [0.0, 0.4, 0.5],          # [rad] rotation vector from start to end orientation, root frame
    "t_start": 0.25,                      # [s] the line starts
    "line_duration": 2.25,                # [s]
    "task_gain": 50.0,                    # [1/s] CLIK gain on the differential-IK reference
    "physics_dt": 0.001,                  # [s] MuJoCo timestep
    "delay_ticks": 0,                     # measurement delay [ticks]
}
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


class CartesianTick:
    """Maps a measurement and the line sample onto the compiled controller (glue only)."""

    def __init__(self, controller, line):
        self.controller, self.line = controller, line
        self.input, self.output = controller.make_input(), controller.make_output()

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        inp = self.input
        inp.t, inp.stamp = m.t, m.stamp
        inp.q[:], inp.qd[:] = m.q, m.qd
        self.line.sample_into(m.t, inp)
        status = self.controller.step(inp, self.output)
        log.record("q", m.q)
        log.record("q_ref", self.output.q_ref)
        log.record("tau", self.output.tau)
        log.record("pose_ref", inp.pose_ref)
        log.record("ik_error", self.output.task_error)
        log.record("status", int(status))
        return self.output.tau.copy()


def make_line(model, q0, settings):
    start = kl.Dynamics(model).forward_kinematics(q0)
    end = start.copy()
    end[:3, 3] += np.asarray(settings["displacement"], dtype=float)
    end[:3, :3] = _rotation(settings["rotation"]) @ start[:3, :3]
    return kl.CartesianLine(start, end, settings["t_start"], settings["line_duration"])


def run(settings: dict, seed: int = 0, duration: float | None = None) -> ScenarioResult:
    del seed  # deterministic: no noise in this scenario
    urdf, overlay = kl.model_files("ur5")
    plant = MujocoPlant(urdf, overlay, timestep=settings["physics_dt"])
    model = kl.RobotModel.from_urdf(str(urdf))
    line = make_line(model, plant.q0, settings)
    config = kl.CartesianTrackingConfig()
    config.task_gain = np.full(6, float(settings["task_gain"]))
    config.joint.max_measurement_age = 0.005 + settings["delay_ticks"] * 0.001
    tick = CartesianTick(kl.CartesianTrackingController(model, config), line)

    def observe(p: MujocoPlant, log: SignalLog) -> None:
        pos, rot = p.ee_pose()
        log.record("ee", pos)
        log.record("ee_rot", rot)

    loop = LoopSettings(duration=DURATION if duration is None else duration,
                        delay_ticks=settings["delay_ticks"])
    log = run_loop(plant, tick, loop, observe=observe)

    ref = log["pose_ref"]
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
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    """What `--plot` draws for this scenario: (title, signal, reference or None, unit)."""
    return [("end-effector position", "ee", "ee_ref", "m"),
            ("end-effector position error", "ee_err_mm", None, "mm"),
            ("end-effector orientation error", "ee_rot_err_mrad", None, "mrad"),
            ("joint torque", "tau", None, "N m")]
