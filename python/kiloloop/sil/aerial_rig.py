"""SIL rig for multirotors (with or without an arm) from a robot file: MuJoCo plant
(aerial_plant.py) + sensor non-idealities + the compiled AerialController, at 1 kHz. Scenarios (scenarios/aerial_*.py) script the references
and disturbances and judge the log; this file only moves data (no control logic).

What the controller sees: the IMU (gyro with noise, orientation with a small noise standing in for
an attitude estimator), the arm encoders (quantized), and the body position and velocity from a
motion-capture-like source (ground truth plus white noise). Commands travel through a short
transport delay (MotorDelay) before the plant; the rotors add their own first-order lag.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

import kiloloop as kl

from ..robot import aerial as aerial_robot
from .aerial_plant import AerialPlant
from .log import SignalLog
from .nonideal import MotorDelay, NonIdealities, SensorModel
from .video import maybe_recorder

CONTROL_DT = 0.001  # [s]
DEFAULT_ROBOT = "aerial_manipulator"


def load_robot(robot=None):
    """A loaded kl.Robot: `robot` itself, or a name / file, or kiloloop's aerial manipulator."""
    from ..robot import Robot

    return robot if isinstance(robot, Robot) else Robot.load(robot or DEFAULT_ROBOT)


def aerial_paths():
    return kl.model_files(DEFAULT_ROBOT)


def rotor_config(robot=None) -> "kl.RotorAllocationConfig":
    """The controller's rotor settings from the robot file's [[rotors]] (the one place they live)."""
    return aerial_robot.rotor_config(load_robot(robot))


@dataclass
class AerialRigSettings:
    physics_dt: float = 0.001
    nonideal: NonIdealities = field(default_factory=lambda: NonIdealities(
        quat_sigma=0.002, motor_delay=0.002))
    position_sigma: float = 0.001   # [m] motion-capture position noise per axis
    velocity_sigma: float = 0.005   # [m/s]
    joint_friction: bool = True     # the overlay's arm friction (False: frictionless plant)
    lag_compensation: bool = False  # rotor-lag lead in the controller's allocation
    friction_compensation: bool = True  # the controller knows the arm's joint friction
    config: object = None           # kl.AerialConfig; None = derived from the robot file
    video: str | None = None        # an .mp4 path: record the run


# command(t, input): sets the references on the controller input for time t.
CommandFn = Callable[[float, object], None]


class AerialRig:
    def __init__(self, settings: AerialRigSettings, seed: int = 0, robot=None):
        robot = load_robot(robot)
        self.robot = robot
        self.settings = settings
        kw = {} if settings.joint_friction else {"damping": 0.0, "frictionloss": 0.0}
        self.plant = AerialPlant.from_robot(robot, timestep=settings.physics_dt,
                                            visual=bool(settings.video), **kw)
        self.model = aerial_robot.model(robot)
        config = (settings.config if settings.config is not None
                  else aerial_robot.config(robot))
        config.dt = CONTROL_DT
        if settings.joint_friction and settings.friction_compensation and self.plant.nq:
            # The arm's friction as identified: the robot file's values (what the plant simulates).
            joints = robot.sim.get("joints", {})
            for field_name, key in (("arm_viscous", "damping"), ("arm_coulomb", "frictionloss")):
                value = joints.get(key)
                if value is not None:
                    setattr(config, field_name, np.atleast_1d(np.asarray(value, dtype=float)))
        rotors = config.rotors
        rotors.lag_compensation = settings.lag_compensation
        config.rotors = rotors
        self.config = config
        self.controller = kl.AerialController(self.model, config)
        self.n_rotors = self.controller.n_rotors
        plant_index = {name: i for i, name in enumerate(self.plant.joint_names)}
        names = list(self.model.joint_names) if self.controller.nq else []
        self.to_ctrl = np.array([plant_index[n] for n in names], dtype=int)
        self.to_plant = np.argsort(self.to_ctrl)
        self.sensors = SensorModel(settings.nonideal, seed=seed)
        # A second stream for the motion-capture noise keeps the IMU's stream seed-stable.
        self.rng = np.random.default_rng(None if seed is None else seed + 1_000_003)
        self.motors = MotorDelay(settings.nonideal, control_dt=CONTROL_DT,
                                 n=self.n_rotors + self.plant.nq, initial="first")
        self.substeps = max(1, round(CONTROL_DT / self.plant.timestep))
        self.input, self.output = self.controller.make_input(), self.controller.make_output()
        self.hover_pos = self.plant.base_pos0.copy()

    def run(self, duration: float, command: CommandFn, events=(),
            log: SignalLog | None = None, disturbance=None) -> SignalLog:
        """events: (time [s], action(plant)) pairs, each run once when its time comes;
        disturbance(t, plant, log): called every tick before the controller (wind, pushes)."""
        log = SignalLog() if log is None else log
        recorder = maybe_recorder(self.settings.video, self.plant.model,
                                  body=self.plant._base_id)
        try:
            return self._run(duration, command, events, log, disturbance, recorder)
        finally:
            if recorder is not None:
                recorder.close()

    def _run(self, duration, command, events, log, disturbance, recorder):
        pending = sorted(events, key=lambda e: e[0])
        inp, out, plant = self.input, self.output, self.plant
        noisy = self.settings.nonideal.enabled
        n = self.n_rotors
        for k in range(int(round(duration / CONTROL_DT))):
            t = k * CONTROL_DT
            while pending and pending[0][0] <= t + 1e-12:
                pending.pop(0)[1](plant)
            if disturbance is not None:
                disturbance(t, plant, log)
            imu, q, qd = self.sensors.apply(plant.imu(), plant.q(), plant.qd())
            pos, quat = plant.base_pose()
            vel, omega = plant.base_velocity()
            inp.t = inp.stamp = t
            inp.position[:] = pos + (self.settings.position_sigma * self.rng.standard_normal(3)
                                     if noisy else 0.0)
            inp.velocity[:] = vel + (self.settings.velocity_sigma * self.rng.standard_normal(3)
                                     if noisy else 0.0)
            inp.quat[:], inp.gyro[:], inp.accel[:] = imu["quat"], imu["gyro"], imu["accel"]
            inp.q[:], inp.qd[:] = q[self.to_ctrl], qd[self.to_ctrl]
            command(t, inp)
            status = self.controller.step(inp, out)
            cmd = self.motors.push(np.concatenate([out.thrust, out.tau[self.to_plant]]))
            plant.set_thrust(cmd[:n])
            plant.set_torque(cmd[n:])
            self._record(log, t, status, pos, quat, vel, omega)
            plant.step(self.substeps)
            if recorder is not None:
                recorder.capture(plant.data)
            if not np.all(np.isfinite(plant.data.qpos)):
                log.record("diverged", 1.0)
                break
        return log

    def _record(self, log, t, status, pos, quat, vel, omega):
        out, inp = self.output, self.input
        log.record("t", t)
        log.record("status", int(status))
        log.record("base_pos", pos)
        log.record("com", self.plant.com())
        log.record("base_quat", quat)
        log.record("base_vel", vel)
        log.record("base_omega", omega)
        log.record("pos_ref", inp.position_ref)
        log.record("quat_des", out.quat_des)
        log.record("tilt", out.tilt)
        log.record("safe_stop", float(out.safe_stop))
        log.record("thrust_cmd", out.thrust)
        log.record("thrust", self.plant.rotor_thrust())
        log.record("rotors_saturated", float(out.rotors_saturated))
        log.record("tau", out.tau)
        log.record("reaction", out.reaction)
        log.record("q", self.plant.q()[self.to_ctrl])
        log.record("q_ref", out.q_ref)
        ee_pos, ee_rot = self.plant.ee_pose()
        log.record("ee_pos", ee_pos)
        log.record("ee_rot", ee_rot)


def quat_angle(q_a: np.ndarray, q_b: np.ndarray) -> np.ndarray:
    """Rotation angle [rad] between rows of two (N, 4) w, x, y, z quaternion arrays."""
    dot = np.abs(np.sum(q_a * q_b, axis=1))
    return 2.0 * np.arccos(np.clip(dot, -1.0, 1.0))


def rotation_vector_error(q: np.ndarray, q_ref: np.ndarray) -> np.ndarray:
    """Body-frame rotation vector (N, 3) [rad] of q_ref^-1 q (w, x, y, z rows)."""
    w1, v1 = q_ref[:, :1], -q_ref[:, 1:]
    w2, v2 = q[:, :1], q[:, 1:]
    w = w1 * w2 - np.sum(v1 * v2, axis=1, keepdims=True)
    v = w1 * v2 + w2 * v1 + np.cross(v1, v2)
    sign = np.where(w < 0, -1.0, 1.0)
    w, v = w * sign, v * sign
    angle = 2.0 * np.arctan2(np.linalg.norm(v, axis=1, keepdims=True), w)
    norm = np.linalg.norm(v, axis=1, keepdims=True)
    return np.where(norm > 1e-12, v / np.maximum(norm, 1e-300) * angle, 2.0 * v)


def diverged(log, max_tilt_deg: float = 60.0) -> str:
    """'' when the run stayed sane, else why it did not (for the sweep's failure column)."""
    if "diverged" in log:
        return "non-finite simulation state"
    if np.any(log["safe_stop"] > 0):
        return "attitude > 60 deg (safe stop)"
    if np.any(np.degrees(log["tilt"]) > max_tilt_deg):
        return "attitude > 60 deg"
    if np.any(log["status"] == int(kl.Status.SOLVER_FAILED)):
        return "solver failure"
    if np.any(log["status"] == int(kl.Status.NON_FINITE_MEASUREMENT)):
        return "NaN/Inf measurement"
    return ""


# Settings every aerial scenario accepts (`kiloloop run aerial-... --set key=value`).
COMMON_DEFAULTS = {
    "nonideal": True,          # IMU noise, encoder quantization, command delay on
    "gyro_sigma": 0.02,        # [rad/s]
    "accel_sigma": 0.05,       # [m/s^2]
    "quat_sigma": 0.002,       # [rad] attitude-estimate noise
    "position_sigma": 0.001,   # [m] motion capture
    "velocity_sigma": 0.005,   # [m/s]
    "motor_delay": 0.002,      # [s] command transport (ESC) delay, on top of the rotor lag
    "physics_dt": 0.001,       # [s]
    "law": "quaternion_pd",    # or "geometric_so3"
    "feedforward": True,       # arm reaction feed-forward
    "lag_compensation": False, # rotor-lag lead in the allocation (all thrusts)
    "reaction_lead": None,     # [s] lead on the fed-forward reaction torque; None: derived
                               # (the rotor time constant, robot/aerial.py)
    "hold_com": True,          # the position loop holds the vehicle's CoM (not the body origin)
    # The controller compensates the arm's (identified) joint friction (the overlay's values).
    "friction_compensation": True,
    "att_kp": 0.0,             # 0: the controller's default (roll/pitch) [1/s^2]
    "att_kd": 0.0,             # 0: default [1/s]
    "att_ki": 0.0,             # roll/pitch integral [1/s^3]
    "pos_kp": 0.0,             # 0: default (x, y) [1/s^2]
    "pos_kd": 0.0,             # 0: default [1/s]
}

LAWS = {"quaternion_pd": "QUATERNION_PD", "geometric_so3": "GEOMETRIC_SO3"}


def config_from_settings(settings: dict, robot=None) -> "kl.AerialConfig":
    """The robot file's derived configuration with the scenario settings on top."""
    config = aerial_robot.config(load_robot(robot))
    if settings["law"] not in LAWS:
        raise ValueError(f"law: expected one of {sorted(LAWS)}, got {settings['law']!r}")
    config.attitude.law = getattr(kl.AttitudeLaw, LAWS[settings["law"]])
    config.reaction_feedforward = bool(settings["feedforward"])
    if settings["reaction_lead"] is not None:
        config.reaction_lead = float(settings["reaction_lead"])
    config.hold_com = bool(settings["hold_com"])
    gains = config.attitude.gains
    kp, kd, ki = np.array(gains.kp), np.array(gains.kd), np.array(gains.ki)
    if settings["att_kp"] > 0:
        kp[:2] = settings["att_kp"]
    if settings["att_kd"] > 0:
        kd[:2] = settings["att_kd"]
    ki[:2] = settings["att_ki"]
    gains.kp, gains.kd, gains.ki = kp, kd, ki
    config.attitude.gains = gains
    pos = config.position
    pkp, pkd = np.array(pos.kp), np.array(pos.kd)
    if settings["pos_kp"] > 0:
        pkp[:2] = settings["pos_kp"]
    if settings["pos_kd"] > 0:
        pkd[:2] = settings["pos_kd"]
    pos.kp, pos.kd = pkp, pkd
    config.position = pos
    return config


def rig_from_settings(settings: dict, seed: int, config=None, robot=None) -> AerialRig:
    nonideal = NonIdealities(enabled=settings["nonideal"], gyro_sigma=settings["gyro_sigma"],
                             accel_sigma=settings["accel_sigma"],
                             quat_sigma=settings["quat_sigma"],
                             motor_delay=settings["motor_delay"])
    nonideal.validate()
    robot = load_robot(robot)
    config = config_from_settings(settings, robot) if config is None else config
    rig = AerialRig(AerialRigSettings(physics_dt=settings["physics_dt"], nonideal=nonideal,
                                      position_sigma=settings["position_sigma"],
                                      velocity_sigma=settings["velocity_sigma"],
                                      lag_compensation=bool(settings["lag_compensation"]),
                                      friction_compensation=bool(
                                          settings["friction_compensation"]),
                                      config=config, video=settings.get("video")),
                    seed=seed, robot=robot)
    return rig


AERIAL_PLOT = [("body position", "base_pos", None, "m"),
               ("attitude error (rotation vector)", "att_err_deg", None, "deg"),
               ("rotor thrust", "thrust", None, "N"),
               ("arm joints", "q", None, "rad"),
               ("arm torque", "tau", None, "N m")]


def add_derived(log) -> None:
    """Attitude error vs the commanded attitude (deg), for plots and metrics."""
    log.put("att_err_deg", np.degrees(rotation_vector_error(log["base_quat"], log["quat_des"])))


def hold(rig):
    """Hover point and the arm at its start pose (controller order)."""
    hover = rig.hover_pos.copy()
    q0 = rig.plant.q0.copy()[rig.to_ctrl]

    def command(t, inp):
        inp.position_ref[:] = hover
        inp.q_ref[:] = q0
    return command


def hold_errors(log, after) -> dict:
    """Position error [m] and attitude error [deg] of a hold (hover, wind) over the ticks where
    `after` is true: max and RMS."""
    pos_err = np.linalg.norm(log["base_pos"] - log["pos_ref"], axis=1)[after]
    att = np.linalg.norm(log["att_err_deg"], axis=1)[after]
    return {
        "max_position_error_m": float(pos_err.max()),
        "rms_position_error_m": float(np.sqrt(np.mean(pos_err ** 2))),
        "attitude_error_rms_deg": float(np.sqrt(np.mean(att ** 2))),
        "attitude_error_max_deg": float(att.max()),
    }
