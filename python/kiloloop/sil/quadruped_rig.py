"""SIL rig for the quadruped: MuJoCo floating-base plant + non-idealities + the compiled
QuadrupedController, at 1 kHz. Scenarios (python/kiloloop/scenarios/quadruped_*.py) script the
commands and disturbances and judge the log; this file only moves data (no control logic).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

import kiloloop as kl

from .floating_plant import FloatingBasePlant
from .log import SignalLog
from .nonideal import MotorDelay, NonIdealities, SensorModel

CONTROL_DT = 0.001  # [s]


@dataclass
class RigSettings:
    slope_deg: float = 0.0
    physics_dt: float = 0.001
    nonideal: NonIdealities = field(default_factory=NonIdealities)
    ground_truth: bool = False     # controller runs on the simulator's state (debugging only)
    config: object = None          # kl.QuadrupedConfig; None = from the robot file
    video: str | None = None       # MP4 path: render the run
    # Ground other than a plane (sil/terrain.py), made from the resolved controller config so
    # that its sizes follow the robot (e.g. stone heights from the swing height).
    terrain: Callable[[object], object] | None = None


def quadruped_paths():
    return kl.model_files("quadruped")


def default_robot():
    return kl.Robot.load("quadruped")


# command(t) -> (gait 0/1, velocity command (3,)); events: (time [s], action(plant)) run once.
CommandFn = Callable[[float], tuple[int, np.ndarray]]


class QuadrupedRig:
    def __init__(self, settings: RigSettings, seed: int = 0, robot=None):
        from ..robot.quadruped import controller_config, plant_overlay

        self.robot = default_robot() if robot is None else robot
        self.settings = settings
        self.model = self.robot.model()
        delay = settings.nonideal.motor_delay if settings.nonideal.enabled else 0.0
        config = (settings.config if settings.config is not None
                  else controller_config(self.robot, actuation_delay=delay))
        config.dt = CONTROL_DT
        # The safe-stop tilt is measured from vertical; on a slope the trunk starts tilted by it
        # (15 deg would trip the default 15 deg at once; measured: with it raised by the slope
        # both robots stand on 15 deg).
        config.max_tilt = config.max_tilt + float(np.deg2rad(abs(settings.slope_deg)))
        self.controller = kl.QuadrupedController(self.model, config)
        self.config = self.controller.config  # everything derived filled in
        # Below this trunk height the robot has fallen (half its standing height).
        self.fall_height = 0.5 * self.config.body_height
        self.plant = FloatingBasePlant(self.robot.urdf, plant_overlay(self.robot, self.controller),
                                       timestep=settings.physics_dt, slope_deg=settings.slope_deg,
                                       package_dirs=self.robot.package_dirs,
                                       terrain=None if settings.terrain is None
                                       else settings.terrain(self.config))
        # Joint order: the controller's (leg-major) vs the plant's (URDF); mapped by name.
        plant_index = {name: i for i, name in enumerate(self.plant.joint_names)}
        self.to_ctrl = np.array([plant_index[n] for n in self.controller.joint_names])
        self.to_plant = np.argsort(self.to_ctrl)
        self.sensors = SensorModel(settings.nonideal, seed=seed)
        self.motors = MotorDelay(settings.nonideal, control_dt=CONTROL_DT, n=self.plant.nq)
        self.effort = np.asarray(self.controller.effort_limit)[self.to_plant]
        self.substeps = max(1, round(CONTROL_DT / self.plant.timestep))
        self.input, self.output = kl.QuadrupedInput(), kl.QuadrupedOutput()

    def run(self, duration: float, command: CommandFn, events=(), log: SignalLog | None = None,
            stop_when: Callable[[SignalLog], bool] | None = None) -> SignalLog:
        from .video import maybe_recorder

        log = SignalLog() if log is None else log
        pending = sorted(events, key=lambda e: e[0])
        inp, out, plant = self.input, self.output, self.plant
        recorder = maybe_recorder(self.settings.video, plant.model, body=plant.model.body(plant.base_body).id)
        try:
            self._loop(duration, command, pending, log, stop_when, recorder)
        finally:
            if recorder is not None:
                recorder.close()
        return log

    def _loop(self, duration, command, pending, log, stop_when, recorder):
        inp, out, plant = self.input, self.output, self.plant
        for k in range(int(round(duration / CONTROL_DT))):
            t = k * CONTROL_DT
            while pending and pending[0][0] <= t + 1e-12:
                pending.pop(0)[1](plant)
            imu, q, qd = self.sensors.apply(plant.imu(), plant.joint_q(), plant.joint_qd())
            inp.t = inp.stamp = t
            inp.q[:], inp.qd[:] = q[self.to_ctrl], qd[self.to_ctrl]
            inp.gyro[:], inp.accel[:], inp.quat[:] = imu["gyro"], imu["accel"], imu["quat"]
            gait, v_cmd = command(t)
            inp.gait, inp.velocity_command[:] = kl.Gait(int(gait)), v_cmd
            pos, quat = plant.base_pose()
            vel, omega = plant.base_velocity()
            if self.settings.ground_truth:
                inp.use_ground_truth = True
                inp.true_position[:], inp.true_velocity[:], inp.true_quat[:] = pos, vel, quat
            status = self.controller.step(inp, out)
            tau = self.motors.push(out.tau[self.to_plant])
            plant.set_torque(self.settings.nonideal.saturate(tau, self.effort))
            self._record(log, t, status, pos, quat, vel, omega, v_cmd)
            plant.step(self.substeps)
            if recorder is not None:
                recorder.capture(plant.data)
            if stop_when is not None and stop_when(log):
                break

    def _record(self, log, t, status, pos, quat, vel, omega, v_cmd):
        out = self.output
        log.record("t", t)
        log.record("status", int(status))
        log.record("base_pos", pos)
        log.record("base_quat", quat)
        log.record("base_vel", vel)
        log.record("base_omega", omega)
        log.record("est_pos", out.position)
        log.record("est_vel", out.velocity)
        log.record("tilt", out.tilt)
        log.record("safe_stop", float(out.safe_stop))
        log.record("contact", out.contact)
        log.record("scheduled", out.scheduled)
        log.record("foot_clearance", out.foot_clearance)
        log.record("tau", out.tau)
        log.record("foot_force_cmd", out.foot_force)
        log.record("foot_force", self.plant.foot_contact_forces())
        log.record("foot_pos", self.plant.foot_positions())
        log.record("v_cmd", v_cmd)
        log.record("qp_iterations", out.qp_iterations)


def roll_pitch(quat_wxyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Roll and pitch [rad] of a (N, 4) array of w, x, y, z quaternions (world <- body)."""
    w, x, y, z = quat_wxyz.T
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    return roll, pitch


# Settings every quadruped scenario accepts (`kiloloop run quadruped-... --set key=value`).
COMMON_DEFAULTS = {
    "nonideal": True,          # sensor noise, quantization, motor delay, saturation on
    "gyro_sigma": 0.02,        # [rad/s]
    "accel_sigma": 0.05,       # [m/s^2]
    "encoder_resolution_deg": 0.1,
    "motor_delay": 0.010,      # [s]
    "physics_dt": 0.001,       # [s]
    "ground_truth": False,     # controller on the simulator's state (debugging only)
}


def rig_from_settings(settings: dict, seed: int, slope_deg: float = 0.0, config=None,
                      robot=None, terrain=None) -> QuadrupedRig:
    nonideal = NonIdealities(enabled=settings["nonideal"], gyro_sigma=settings["gyro_sigma"],
                             accel_sigma=settings["accel_sigma"],
                             encoder_resolution=float(np.deg2rad(settings["encoder_resolution_deg"])),
                             motor_delay=settings["motor_delay"])
    nonideal.validate()
    return QuadrupedRig(RigSettings(slope_deg=slope_deg, physics_dt=settings["physics_dt"],
                                    nonideal=nonideal, ground_truth=settings["ground_truth"],
                                    config=config, video=settings.get("video"), terrain=terrain),
                        seed=seed, robot=robot)


def heading_velocity(log) -> np.ndarray:
    """Ground-truth trunk velocity in the heading frame (x forward, y left), (N, 2)."""
    w, x, y, z = log["base_quat"].T
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    v = log["base_vel"]
    c, s = np.cos(yaw), np.sin(yaw)
    return np.stack([c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1]], axis=1)


def fallen(log, min_height: float = 0.15, max_tilt_deg: float = 45.0) -> bool:
    """Trunk below min_height [m] (rigs: QuadrupedRig.fall_height) or tilted past max_tilt_deg."""
    roll, pitch = roll_pitch(log["base_quat"])
    tilt = np.degrees(np.arccos(np.clip(np.cos(roll) * np.cos(pitch), -1, 1)))
    return bool(np.any(log["base_pos"][:, 2] < min_height) or np.any(tilt > max_tilt_deg))


QUADRUPED_PLOT = [("trunk position", "base_pos", None, "m"),
                  ("trunk velocity (world)", "base_vel", None, "m/s"),
                  ("roll, pitch", "roll_pitch_deg", None, "deg"),
                  ("ground reaction, vertical", "foot_fz", None, "N"),
                  ("contact detected", "contact", None, "-")]


def add_derived(log) -> None:
    """Series the plots and metrics share: roll/pitch in degrees, vertical foot forces."""
    roll, pitch = roll_pitch(log["base_quat"])
    log.put("roll_pitch_deg", np.degrees(np.stack([roll, pitch], axis=1)))
    log.put("foot_fz", log["foot_force"][:, :, 2])


# Trotting helpers shared by the trotting scenarios (trot, push, turn, slope-trot).
def trot_command(speed: float, start: float = 0.5):
    """command(t): stand until `start` [s], then trot forward at `speed` [m/s] (heading frame)."""
    def command(t):
        return (1, np.array([speed, 0.0, 0.0])) if t >= start else (0, np.zeros(3))
    return command


def trot_metrics(log, speed: float, since: float, fall_height: float = 0.15) -> dict:
    """Fall, roll/pitch RMS and forward-velocity tracking of a trot from `since` [s] on."""
    t = log["t"]
    k = t >= since
    rp = log["roll_pitch_deg"][k]
    v = heading_velocity(log)[k]
    return {
        "fell": float(fallen(log, fall_height)),
        "roll_rms_deg": float(np.sqrt(np.mean(rp[:, 0] ** 2))),
        "pitch_rms_deg": float(np.sqrt(np.mean(rp[:, 1] ** 2))),
        "roll_pitch_rms_deg": float(np.sqrt(np.mean(rp ** 2, axis=0)).max()),
        # Forward velocity (heading frame) against the command, as the criterion asks.
        "velocity_rms_error": float(np.sqrt(np.mean((v[:, 0] - speed) ** 2))),
        "lateral_velocity_rms": float(np.sqrt(np.mean(v[:, 1] ** 2))),
        "mean_forward_velocity": float(np.mean(v[:, 0])),
        "distance_m": float(log["base_pos"][-1, 0] - log["base_pos"][0, 0]),
        "failed_ticks": int(np.sum(log["status"] < 0)),
    }


def fell_early(rig):
    """stop_when for trotting runs: the trunk near the ground ends the run."""
    # Cheap check every tick: the trunk near the ground ends the run (it is a fall either way).
    low = 0.8 * rig.fall_height
    return lambda log: log.last("base_pos")[2] < low
