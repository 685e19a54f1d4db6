"""arm-estop: the emergency stop is pressed while an arm moves fast; the arm supervisor (C++)
brings it to a controlled stop within the planned time and distance, then holds it.

Computed torque tracks a synchronized trapezoid (joints at up to `velocity_scale` of their URDF
limits); its torque goes through ArmSupervisor to the MuJoCo motors. At `t_estop` the e-stop
input goes high: every joint ramps its velocity down at `stop_deceleration` (stop time
max |qd| / a, distance qd^2 / (2 a) per joint), then the supervisor holds the final position.
Stop time, distance and hold drift are measured on MuJoCo's ground truth. Any arm: from the work
pose to a goal 90 % of each joint's free range away (at most 0.9 rad, clear of the floor); the
e-stop comes half-way through the motion (at cruise speed), unless the robot file says otherwise.
The loop runs in C++ (sil/rig.py; the e-stop is a scheduled event).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..errors import configuring
from ..robot import arm as arm_defaults
from ..sil.arm_adapters import Supervised
from ..sil.rig import Rig
from .arm_controllers import controller
from .arm_targets import joint_targets, work_pose
from ..sil.native import Observe
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import ARM_ESTOP_PLOT

NAME = "arm-estop"
DESCRIPTION = "arm: e-stop during a fast motion -> controlled stop in bounded time/distance, hold"
DURATION = 3.0  # [s]
DEFAULTS = {
    "q_start": [],              # [rad] empty: the robot's work pose
    "q_goal": [],               # [rad] empty: derived (see the module doc)
    "velocity_scale": 0.7,      # of the URDF velocity limits
    "acceleration": 4.0,        # [rad/s^2] of the trapezoid
    "t_estop": -1.0,            # [s] e-stop pressed; < 0: half-way through the motion
    "stop_deceleration": 5.0,   # [rad/s^2] supervisor's a_stop
    "stopped_speed": 0.01,      # [rad/s] "stopped" when every |qd| is below this
}
CRITERIA = {
    "stopped": (">=", 1),                       # every |qd| fell below stopped_speed
    "stop_time_over_plan_s": ("<", 0.05),       # stopped no later than planned + 50 ms
    "stop_distance_over_bound_rad": ("<", 0.01),  # no joint beyond qd^2/(2a) + 0.01 rad
    "hold_drift_rad": ("<", 1e-3),              # then holds
    "holding_at_end": (">=", 1),
    "trips_before_estop": ("<", 1),
    "speed_at_estop_fraction": (">", 0.9),      # the stop happened at cruise speed
}
# Robot-file tables it reads (scenarios/__init__.py): the chain, the plant, the joint controller.
ROBOT_KEYS = ("chain", "sim", "controller")
SIZES = {"q_start": "nq", "q_goal": "nq"}  # [rad] per joint
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"velocity_scale": (">", 0.0), "acceleration": (">", 0.0),
          "stop_deceleration": (">", 0.0), "stopped_speed": (">", 0.0)}
GOAL_FRACTION = 0.9  # of each joint's free range (capped at 1 rad)


def motion(rig, settings):
    """(q_start, q_goal [rad], the trapezoid, t_estop [s], cruise [rad/s]: the fastest the
    trapezoid gets, sampled) for the settings; what they leave empty is derived (module doc)."""
    robot, plant, model = rig.robot, rig.plant, rig.model
    q_start = np.asarray(settings["q_start"], float) if len(settings["q_start"]) else work_pose(
        robot, model, plant)
    q_goal = np.asarray(settings["q_goal"], float) if len(settings["q_goal"]) else joint_targets(
        model, plant, q_start, 1, GOAL_FRACTION)[0]
    v_max = np.asarray(model.velocity_limit) * settings["velocity_scale"]
    a_max = np.full(model.nq, float(settings["acceleration"]))
    trajectory = kl.TrapezoidTrajectory(np.vstack([q_start, q_goal]), v_max, a_max)
    t_estop = float(settings["t_estop"]) if settings["t_estop"] >= 0 else 0.5 * trajectory.end_time
    cruise = max(float(np.abs(trajectory.sample(t)[1]).max())
                 for t in np.linspace(0.0, trajectory.end_time, 201))
    return q_start, q_goal, trajectory, t_estop, cruise


def min_duration(settings, robot=None) -> float:
    """[s] a run must see the stop through: the e-stop, the planned stop from cruise speed with
    the time its criterion allows over the plan, then a judged hold (the motion derived as run()
    derives it, on a plant of its own)."""
    rig = Rig(robot or kl.Robot.load("ur5"))
    _, _, _, t_estop, cruise = motion(rig, settings)
    a = float(settings["stop_deceleration"])
    stop = cruise / a if a > 0 else 0.0  # a <= 0: refused by the supervisor, with its own line
    return t_estop + stop + CRITERIA["stop_time_over_plan_s"][1] + JUDGED_WINDOW


def _stop_metrics(t, q, qd, k0: int, a: float, cruise: float, settings) -> dict:
    """The stop's figures from the e-stop tick k0 on (ground truth q, qd). Never below
    stopped_speed: judged at the run's end (the time a lower bound, the drift that of the last
    JUDGED_WINDOW), and `stopped` is 0."""
    q0, v0 = q[k0], qd[k0]
    planned = float(np.abs(v0).max() / a)
    still = np.where(np.abs(qd[k0:]).max(axis=1) < settings["stopped_speed"])[0]
    k1 = k0 + int(still[0]) if len(still) else len(t) - 1
    distance = np.abs(q[k1:] - q0).max(axis=0)  # furthest each joint got after the e-stop
    bound = v0 ** 2 / (2 * a)
    hold_from = k1 if len(still) else int(np.searchsorted(t, t[-1] - JUDGED_WINDOW))
    return {
        "speed_at_estop_rad_s": float(np.abs(v0).max()),
        "speed_at_estop_fraction": float(np.abs(v0).max() / cruise),
        "planned_stop_time_s": planned,
        "stopped": int(len(still) > 0),
        "speed_at_end_rad_s": float(np.abs(qd[-1]).max()),
        "stop_time_s": float(t[k1] - t[k0]),
        "stop_time_over_plan_s": float(t[k1] - t[k0]) - planned,
        "max_stop_distance_rad": float(distance.max()),
        "stop_distance_over_bound_rad": float((distance - bound).max()),
        "hold_drift_rad": float(np.abs(q[hold_from:] - q[hold_from]).max()),
    }


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    del seed  # deterministic
    robot = robot or kl.Robot.load("ur5")
    rig = Rig(robot, video=settings.get("video"))
    plant, model = rig.plant, rig.model
    q_start, q_goal, trajectory, t_estop, cruise = motion(rig, settings)
    plant.q0 = q_start
    plant.reset()
    settings = dict(settings, q_start=q_start.tolist(), q_goal=q_goal.tolist(), t_estop=t_estop)
    config = kl.ArmSupervisorConfig()
    config.stop_deceleration = np.array([float(settings["stop_deceleration"])])
    # The stop and hold are computed torque too: where friction raised the joint controller's
    # bandwidth (robot/arm.py friction_bandwidth), the supervisor's gains follow (one for all
    # joints: the highest, critically damped); a frictionless arm keeps the config's.
    kp, _ = arm_defaults.joint_gains(robot, model, "computed_torque", q_start)
    w = float(arm_defaults.controller_settings(robot)["bandwidth"])
    if float(kp.max()) > max(w * w, config.stop_kp):
        config.stop_kp = float(kp.max())
        config.stop_kd = max(config.stop_kd, 2.0 * float(np.sqrt(config.stop_kp)))
    with configuring(f"{NAME} supervisor"):
        supervisor = kl.ArmSupervisor(model, config)
    reference = Supervised(controller(robot, model, "computed_torque", q_start), supervisor,
                           trajectory, t_estop)

    log = rig.run(DURATION if duration is None else duration, reference,
                  observe=Observe("q_true", "qd_true"))
    t, q, qd, mode = log["t"], log["q_true"], log["qd_true"], log["mode"]
    a = float(settings["stop_deceleration"])
    k0 = int(np.searchsorted(t, t_estop))
    metrics = {"trips_before_estop": int(np.sum(mode[:k0] != 0))}
    pressed = k0 < len(t)  # the CLI's minimum duration sees it is; an API caller may not
    if pressed:
        metrics.update(_stop_metrics(t, q, qd, k0, a, cruise, settings))
    else:  # no stop to judge: `stopped` fails, the stop's own criteria are not evaluated
        metrics["stopped"] = 0
    metrics.update({
        "holding_at_end": int(mode[-1] == int(kl.SupervisorMode.HOLDING)),
        "estop_status_ticks": int(np.sum(log["status"] == int(kl.Status.EMERGENCY_STOP))),
        "max_abs_torque_Nm": float(np.abs(log["tau"]).max()),
        "min_manipulability": float(np.min(log["manipulability"])),
        "ticks": int(len(t)),
    })
    # Without an e-stop in the run only `stopped` and what needs no stop are judged (never NaN).
    judged = {k: c for k, c in CRITERIA.items() if k in metrics}
    return ScenarioResult(NAME, metrics, evaluate(judged, metrics), log, dict(settings))


def plot_signals():
    """What `--plot` draws for this scenario (scenarios/plots.py)."""
    return ARM_ESTOP_PLOT
