"""arm-estop: the emergency stop is pressed while the UR5 moves fast; the arm supervisor (C++)
brings it to a controlled stop within the planned time and distance, then holds it.

Computed torque tracks a synchronized trapezoid (joints at up to `velocity_scale` of their URDF
limits); its torque goes through ArmSupervisor to the MuJoCo motors. At `t_estop` the e-stop
input goes high: every joint ramps its velocity down at `stop_deceleration` (stop time
max |qd| / a, distance qd^2 / (2 a) per joint), then the supervisor holds the final position.
Stop time, distance and hold drift are measured on MuJoCo's ground truth.
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil.log import SignalLog
from ..sil.loop import LoopSettings, Measurement, run_loop
from ..sil.plant import MujocoPlant
from . import ScenarioResult, evaluate

NAME = "arm-estop"
DESCRIPTION = "UR5: e-stop during a fast motion -> controlled stop in bounded time/distance, hold"
DURATION = 3.0  # [s]
DEFAULTS = {
    "q_goal": [1.6, -0.6, 0.6, -2.2, -0.8, 1.5],  # [rad] from the overlay's q0
    "velocity_scale": 0.7,      # of the URDF velocity limits
    "acceleration": 4.0,        # [rad/s^2] of the trapezoid
    "t_estop": 0.65,            # [s] e-stop pressed (mid-motion, at cruise speed)
    "stop_deceleration": 5.0,   # [rad/s^2] supervisor's a_stop
    "stopped_speed": 0.01,      # [rad/s] "stopped" when every |qd| is below this
}
CRITERIA = {
    "stop_time_over_plan_s": ("<", 0.05),       # stopped no later than planned + 50 ms
    "stop_distance_over_bound_rad": ("<", 0.01),  # no joint beyond qd^2/(2a) + 0.01 rad
    "hold_drift_rad": ("<", 1e-3),              # then holds
    "holding_at_end": (">=", 1),
    "trips_before_estop": ("<", 1),
    "speed_at_estop_rad_s": (">", 1.0),         # the stop happened at speed
}


class SupervisedTick:
    """Trajectory -> computed torque -> supervisor -> motors (glue only)."""

    def __init__(self, controller, supervisor, trajectory, t_estop):
        self.c, self.s, self.traj, self.t_estop = controller, supervisor, trajectory, t_estop
        self.cin, self.cout = controller.make_input(), controller.make_output()
        self.sin, self.sout = supervisor.make_input(), supervisor.make_output()

    def __call__(self, m: Measurement, log: SignalLog) -> np.ndarray:
        cin, sin = self.cin, self.sin
        cin.t, cin.stamp = m.t, m.stamp
        cin.q[:], cin.qd[:] = m.q, m.qd
        self.traj.sample_into(m.t, cin.q_ref, cin.qd_ref, cin.qdd_ref)
        self.c.step(cin, self.cout)
        sin.t, sin.stamp = m.t, m.stamp
        sin.q[:], sin.qd[:] = m.q, m.qd
        sin.tau_command[:] = self.cout.tau
        sin.estop = m.t >= self.t_estop
        status = self.s.step(sin, self.sout)
        log.record("q", m.q)
        log.record("qd", m.qd)
        log.record("q_ref", cin.q_ref)
        log.record("tau", self.sout.tau)
        log.record("mode", int(self.sout.mode))
        log.record("status", int(status))
        log.record("manipulability", self.sout.singularity.manipulability)
        return self.sout.tau.copy()


def run(settings: dict, seed: int = 0, duration: float | None = None) -> ScenarioResult:
    del seed  # deterministic
    urdf, overlay = kl.model_files("ur5")
    plant = MujocoPlant(urdf, overlay)
    model = kl.RobotModel.from_urdf(str(urdf))
    v_max = np.asarray(model.velocity_limit) * settings["velocity_scale"]
    a_max = np.full(model.nq, float(settings["acceleration"]))
    trajectory = kl.TrapezoidTrajectory(np.vstack([plant.q0, settings["q_goal"]]), v_max, a_max)
    config = kl.ArmSupervisorConfig()
    config.stop_deceleration = np.array([float(settings["stop_deceleration"])])
    supervisor = kl.ArmSupervisor(model, config)
    tick = SupervisedTick(kl.ComputedTorqueController(model), supervisor, trajectory,
                          settings["t_estop"])

    def observe(p: MujocoPlant, log: SignalLog) -> None:
        log.record("q_true", p.q())
        log.record("qd_true", p.qd())

    log = run_loop(plant, tick, LoopSettings(duration=DURATION if duration is None else duration),
                   observe=observe)
    t, q, qd, mode = log["t"], log["q_true"], log["qd_true"], log["mode"]
    a = float(settings["stop_deceleration"])
    k0 = int(np.searchsorted(t, settings["t_estop"]))
    metrics = {"trips_before_estop": int(np.sum(mode[:k0] != 0))}
    pressed = k0 < len(t)  # the e-stop may lie beyond the simulated time
    if pressed:
        q0, v0 = q[k0], qd[k0]
        planned = float(np.abs(v0).max() / a)
        metrics.update({"speed_at_estop_rad_s": float(np.abs(v0).max()),
                        "planned_stop_time_s": planned})
    still = np.where(np.abs(qd[k0:]).max(axis=1) < settings["stopped_speed"])[0] if pressed else []
    if len(still):
        k1 = k0 + int(still[0])
        stop_time = float(t[k1] - t[k0])
        distance = np.abs(q[k1:] - q0).max(axis=0)  # furthest each joint got after the e-stop
        bound = v0 ** 2 / (2 * a)
        metrics.update({
            "stop_time_s": stop_time,
            "stop_time_over_plan_s": stop_time - planned,
            "max_stop_distance_rad": float(distance.max()),
            "stop_distance_over_bound_rad": float((distance - bound).max()),
            "hold_drift_rad": float(np.abs(q[k1:] - q[k1]).max()),
        })
    metrics.update({
        "holding_at_end": int(mode[-1] == int(kl.SupervisorMode.HOLDING)),
        "estop_status_ticks": int(np.sum(log["status"] == int(kl.Status.EMERGENCY_STOP))),
        "max_abs_torque_Nm": float(np.abs(log["tau"]).max()),
        "min_manipulability": float(np.min(log["manipulability"])),
        "ticks": int(len(t)),
    })
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return [("joint velocity", "qd_true", None, "rad/s"),
            ("joint position", "q_true", "q_ref", "rad"),
            ("supervisor mode (0 normal, 1 stopping, 2 holding)", "mode", None, "-"),
            ("joint torque", "tau", None, "N m")]
