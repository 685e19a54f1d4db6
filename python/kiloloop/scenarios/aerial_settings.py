"""The settings every aerial scenario accepts (`kiloloop run aerial-... --set key=value`) and
the rig they make: the signal chain (sil/signals.py) and the controller's configuration."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..errors import InputError
from ..robot import aerial as aerial_robot
from ..sil.aerial_family import load_robot
from ..sil.rig import Rig
from ..sil.signals import Signals
from .design_delay import design_delay

ENCODER_RESOLUTION = float(np.deg2rad(0.1))  # [rad] the arm's encoders

# Settings every aerial scenario accepts (`kiloloop run aerial-... --set key=value`).
COMMON_DEFAULTS = {
    "nonideal": True,          # IMU noise, encoder quantization, command delay on
    "gyro_sigma": 0.02,        # [rad/s]
    "accel_sigma": 0.05,       # [m/s^2]
    "quat_sigma": 0.002,       # [rad] attitude-estimate noise
    "position_sigma": 0.001,   # [m] motion capture
    "velocity_sigma": 0.005,   # [m/s]
    "motor_delay": 0.002,      # [s] command transport (ESC) delay, on top of the rotor lag
    # [s] the delay the controller is designed for; None: the plant's motor_delay. Set apart to
    # sweep the plant's delay with the design held. The gains come from the rotor lag alone
    # (robot/aerial.py); the derived reaction lead covers this delay on top of the lag.
    "design_delay": None,
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
        raise InputError(f"law: expected one of {sorted(LAWS)}, got {settings['law']!r}")
    config.attitude.law = getattr(kl.AttitudeLaw, LAWS[settings["law"]])
    config.reaction_feedforward = bool(settings["feedforward"])
    if settings["reaction_lead"] is not None:
        config.reaction_lead = float(settings["reaction_lead"])
    elif "reaction_lead" not in aerial_robot.controller_settings(load_robot(robot)):
        # The fed-forward reaction reaches the body after the command delay and the rotor lag:
        # led by both (measured, aerial-arm-sweep: 0.278 deg p-p at 30 ms, 0.278 at 32 ms).
        config.reaction_lead += design_delay(settings)
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


def signals_from_settings(settings: dict) -> Signals:
    return Signals(enabled=bool(settings["nonideal"]), gyro_sigma=settings["gyro_sigma"],
                   accel_sigma=settings["accel_sigma"], quat_sigma=settings["quat_sigma"],
                   position_sigma=settings["position_sigma"],
                   velocity_sigma=settings["velocity_sigma"],
                   encoder_resolution=ENCODER_RESOLUTION, motor_delay=settings["motor_delay"])


def rig_from_settings(settings: dict, seed: int, config=None, robot=None) -> Rig:
    """The multirotor rig of these settings (robot: a kl.Robot or a name, default kiloloop's
    aerial manipulator; config: a kl.AerialConfig instead of config_from_settings')."""
    robot = load_robot(robot)
    config = config_from_settings(settings, robot) if config is None else config
    return Rig(robot, signals_from_settings(settings), seed=seed, video=settings.get("video"),
               physics_dt=settings["physics_dt"], config=config,
               lag_compensation=bool(settings["lag_compensation"]),
               friction_compensation=bool(settings["friction_compensation"]))
