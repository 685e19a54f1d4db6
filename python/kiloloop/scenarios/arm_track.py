"""arm-track: the UR5 follows a quintic joint trajectory through three waypoints at 1 kHz.

Computed torque by default; `--set controller=pd_gravity` runs joint PD + gravity compensation on
the same trajectory for comparison. The plant is MuJoCo built from the same URDF as the
controller's model (models/ur5/ur5.urdf + sim.toml).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil.loop import LoopSettings, Measurement, run_loop
from ..sil.log import SignalLog
from ..sil.plant import MujocoPlant
from . import ScenarioResult, evaluate

NAME = "arm-track"
DESCRIPTION = "UR5 follows a quintic through three waypoints (computed torque; or PD + gravity)"
DURATION = 4.5  # [s] default simulated time: trajectory (3.5 s) plus 1 s of holding
DEFAULTS = {
    "controller": "computed_torque",  # or "pd_gravity"
    "kp": [],             # empty: the controller's default gains (see below)
    "kd": [],
    "physics_dt": 0.001,  # [s] MuJoCo timestep; the control period stays 1 ms
    "delay_ticks": 0,     # measurement delay [ticks]
    "damping": 0.0,       # plant-only joint damping [N m s/rad] (unmodelled by the controller)
    "frictionloss": 0.0,  # plant-only Coulomb friction [N m]
    "armature": 0.0,      # plant-only rotor inertia [kg m^2]
    # Waypoints after the overlay's start configuration q0 [rad], and their times [s].
    "waypoint_1": [0.8, -1.0, 1.2, -1.8, -1.2, 0.6],
    "waypoint_2": [-0.5, -1.8, 2.0, -1.0, -1.8, -0.5],
    "t_1": 1.5,
    "t_2": 3.5,
}
# Error dynamics e'' + kd e' + kp e = 0 for computed torque: omega_n = 30 rad/s, critically
# damped. PD + gravity gets the same bandwidth per joint at the start configuration,
# kp_i = M_ii(q0) omega_n^2 and kd_i = 2 M_ii(q0) omega_n: a fair comparison in which the only
# difference is what computed torque adds (inertia coupling, Coriolis, configuration changes).
OMEGA_N = 30.0  # [rad/s]
CONTROLLERS = ("computed_torque", "pd_gravity")
CRITERIA = {
    "max_joint_error_rad": ("<", 1e-3),
    "max_ee_error_m": ("<", 1e-3),
}


def _default_gains(kind, model, q0):
    if kind == "computed_torque":
        return [OMEGA_N ** 2], [2.0 * OMEGA_N]
    m_diag = np.diag(kl.Dynamics(model).mass_matrix(q0))
    return m_diag * OMEGA_N ** 2, m_diag * 2.0 * OMEGA_N


def _make_controller(model, settings, q0):
    kind = settings["controller"]
    if kind not in CONTROLLERS:
        raise ValueError(f"controller: expected one of {CONTROLLERS}, got {kind!r}")
    kp, kd = _default_gains(kind, model, q0)
    config = kl.ComputedTorqueConfig() if kind == "computed_torque" else kl.JointPdGravityConfig()
    config.kp = np.asarray(settings["kp"] if len(settings["kp"]) else kp, dtype=float)
    config.kd = np.asarray(settings["kd"] if len(settings["kd"]) else kd, dtype=float)
    # A delayed measurement is still fresh enough to use.
    config.max_measurement_age = 0.005 + settings["delay_ticks"] * 0.001
    if kind == "computed_torque":
        return kl.ComputedTorqueController(model, config)
    return kl.JointPdGravityController(model, config)


class JointTrackingTick:
    """Maps a measurement and the trajectory sample onto the compiled controller (glue only)."""

    def __init__(self, controller, trajectory):
        self.controller, self.trajectory = controller, trajectory
        self.input, self.output = controller.make_input(), controller.make_output()

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        inp = self.input
        inp.t, inp.stamp = m.t, m.stamp
        inp.q[:], inp.qd[:] = m.q, m.qd
        self.trajectory.sample_into(m.t, inp.q_ref, inp.qd_ref, inp.qdd_ref)
        status = self.controller.step(inp, self.output)
        log.record("q", m.q)
        log.record("qd", m.qd)
        log.record("q_ref", inp.q_ref)
        log.record("tau", self.output.tau)
        log.record("status", int(status))
        return self.output.tau.copy()


def run(settings: dict, seed: int = 0, duration: float | None = None) -> ScenarioResult:
    del seed  # deterministic: no noise in this scenario
    urdf, overlay = kl.model_files("ur5")
    plant = MujocoPlant(urdf, overlay, timestep=settings["physics_dt"], damping=settings["damping"],
                        frictionloss=settings["frictionloss"], armature=settings["armature"])
    model = kl.RobotModel.from_urdf(str(urdf))
    waypoints = np.vstack([plant.q0, settings["waypoint_1"], settings["waypoint_2"]])
    trajectory = kl.QuinticTrajectory(waypoints, np.array([0.0, settings["t_1"], settings["t_2"]]))
    tick = JointTrackingTick(_make_controller(model, settings, plant.q0), trajectory)

    def observe(p: MujocoPlant, log: SignalLog) -> None:
        log.record("q_true", p.q())  # ground truth: the controller may see a delayed q
        log.record("ee", p.ee_pose()[0])

    loop = LoopSettings(duration=DURATION if duration is None else duration,
                        delay_ticks=settings["delay_ticks"])
    log = run_loop(plant, tick, loop, observe=observe)

    # Desired end-effector positions from the same compiled kinematics (base frame = world).
    dyn = kl.Dynamics(model)
    ee_ref = np.array([dyn.forward_kinematics(q)[:3, 3] for q in log["q_ref"]])
    log.put("ee_ref", ee_ref)
    log.put("q_err", log["q_ref"] - log["q_true"])
    ee_err = np.linalg.norm(log["ee"] - ee_ref, axis=1)
    log.put("ee_err_mm", ee_err * 1e3)
    joint_err = np.abs(log["q_err"])
    statuses = log["status"]
    metrics = {
        "max_joint_error_rad": float(joint_err.max()),
        "rms_joint_error_rad": float(np.sqrt(np.mean(joint_err ** 2))),
        "max_ee_error_m": float(ee_err.max()),
        "rms_ee_error_m": float(np.sqrt(np.mean(ee_err ** 2))),
        "max_abs_torque_Nm": float(np.abs(log["tau"]).max()),
        "saturated_ticks": int(np.sum(statuses == int(kl.Status.SATURATED))),
        "failed_ticks": int(np.sum(statuses < 0)),
        "ticks": int(len(statuses)),
    }
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    """What `--plot` draws for this scenario: (title, signal, reference or None, unit)."""
    return [("joint position", "q_true", "q_ref", "rad"),
            ("joint error q_ref - q", "q_err", None, "rad"),
            ("joint torque", "tau", None, "N m"),
            ("end-effector position error", "ee_err_mm", None, "mm")]
