"""arm-track: an arm follows a quintic joint trajectory through two waypoints at 1 kHz.

Computed torque by default; `--set controller=pd_gravity` runs joint PD + gravity compensation on
the same trajectory for comparison (the same bandwidth on the diagonal of M at the start pose:
the only difference is what computed torque adds). Any arm robot file: the start pose is the
robot's work pose and the waypoints move each joint by half of its free range (at most 0.5 rad),
clear of the floor (scenarios/arm_targets.py); a robot file's [scenario.arm-track] may give them.
The loop runs in C++ (sil/rig.py).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..errors import configuring
from ..sil.arm_adapters import JointTracking
from ..sil.rig import Rig
from ..sil.signals import Signals
from .arm_controllers import controller
from .arm_targets import joint_targets, work_pose
from ..sil.native import Observe
from . import ScenarioResult, evaluate
from .plots import ARM_TRACK_PLOT

NAME = "arm-track"
DESCRIPTION = "arm follows a quintic through two waypoints (computed torque; or PD + gravity)"
DURATION = 4.5  # [s] default simulated time: trajectory (3.5 s) plus 1 s of holding
DEFAULTS = {
    "controller": "computed_torque",  # or "pd_gravity"
    "physics_dt": 0.001,  # [s] MuJoCo timestep; the control period stays 1 ms
    "measurement_delay": 0.0,  # [s] age of the controller's measurement (whole ticks, half up)
    # Plant-only joint damping [N m s/rad], Coulomb friction [N m] and rotor inertia [kg m^2] that
    # the controller does not know of; None: the robot's own (its URDF / [sim.joints]), which the
    # controller compensates.
    "damping": None,
    "frictionloss": None,
    "armature": None,
    # [rad] start and waypoints; empty: derived from the robot (work pose, half the free range).
    "q_start": [],
    "waypoint_1": [],
    "waypoint_2": [],
    "t_1": 1.5,           # [s] at waypoint 1
    "t_2": 3.5,           # [s] at waypoint 2
}
# Robot-file tables it reads (scenarios/__init__.py): the chain, the plant, the joint controller.
ROBOT_KEYS = ("chain", "sim", "controller")
SIZES = {"q_start": "nq", "waypoint_1": "nq", "waypoint_2": "nq"}  # [rad] per joint
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"physics_dt": (">", 0.0), "measurement_delay": (">=", 0.0), "t_1": (">", 0.0)}
WAYPOINT_FRACTION = 0.5  # of each joint's free range (capped at 1 rad) per waypoint
CRITERIA = {
    "max_joint_error_rad": ("<", 1e-3),
    "max_ee_error_m": ("<", 1e-3),
}


def waypoints(rig, settings) -> np.ndarray:
    """(3, nq) [rad]: start, waypoint 1, waypoint 2; what the settings leave empty is derived."""
    q0 = np.asarray(settings["q_start"], float) if len(settings["q_start"]) else work_pose(
        rig.robot, rig.model, rig.plant)
    derived = None
    rows = [q0]
    for key in ("waypoint_1", "waypoint_2"):
        if len(settings[key]):
            rows.append(np.asarray(settings[key], dtype=float))
        else:
            derived = derived or joint_targets(rig.model, rig.plant, q0, 2, WAYPOINT_FRACTION)
            rows.append(derived[len(rows) - 1])
    return np.vstack(rows)


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    del seed  # deterministic: no noise in this scenario
    robot = robot or kl.Robot.load("ur5")
    plant_only = {k: None if settings[k] in (None, "", "none") else float(settings[k])
                  for k in ("damping", "frictionloss", "armature")}
    rig = Rig(robot, Signals(measurement_delay=settings["measurement_delay"]),
              video=settings.get("video"), physics_dt=settings["physics_dt"], **plant_only)
    plant, model = rig.plant, rig.model
    points = waypoints(rig, settings)
    plant.q0 = points[0]
    plant.reset()
    with configuring(f"{NAME} t_1, t_2"):  # the times must increase
        trajectory = kl.QuinticTrajectory(points, np.array([0.0, settings["t_1"], settings["t_2"]]))
    law = settings["controller"]
    reference = JointTracking(controller(robot, model, law, points[0],
                                         measurement_delay=settings["measurement_delay"]),
                              trajectory)

    # Ground truth: the controller may see a delayed q.
    log = rig.run(DURATION if duration is None else duration, reference,
                  observe=Observe("q_true", "ee"))

    # Desired end-effector positions from the same compiled kinematics, in the world frame.
    dyn, T = kl.Dynamics(model), rig.T_world_root()
    ee_ref = np.array([(T @ dyn.forward_kinematics(q))[:3, 3] for q in log["q_ref"]])
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
    settings = dict(settings, q_start=points[0].tolist(), waypoint_1=points[1].tolist(),
                    waypoint_2=points[2].tolist())
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, settings)


def plot_signals():
    """What `--plot` draws for this scenario (scenarios/plots.py)."""
    return ARM_TRACK_PLOT
