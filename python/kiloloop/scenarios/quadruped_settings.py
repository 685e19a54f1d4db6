"""The settings every quadruped scenario accepts (`kiloloop run quadruped-... --set key=value`)
and the rig they make: the signal chain (sil/signals.py) and the controller's design delay."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil.legged_sensors import LeggedSensorSettings
from ..sil.rig import Rig
from ..sil.signals import Signals
from .design_delay import design_delay

_SENSORS = LeggedSensorSettings()
COMMON_DEFAULTS = {
    "nonideal": True,          # master switch: sensor models, motor delay, saturation on
    # Sensors (sil/legged_sensors.py), realistic by default: MEMS IMU (Allan parameters below), no
    # orientation handed over, encoder-difference joint velocity; ideal_sensors=true (debugging):
    # the simulator's IMU, orientation and joint state with white noise (gyro_sigma, accel_sigma).
    "ideal_sensors": _SENSORS.ideal,
    "gyro_noise_density": _SENSORS.gyro_noise_density,          # [rad/s/sqrt(Hz)] BMI088
    "gyro_bias_random_walk": _SENSORS.gyro_bias_random_walk,    # [rad/s^2/sqrt(Hz)]
    "gyro_turn_on_bias": _SENSORS.gyro_turn_on_bias,            # [rad/s] 1 sigma
    "accel_noise_density": _SENSORS.accel_noise_density,        # [m/s^2/sqrt(Hz)] BMI088
    "accel_bias_random_walk": _SENSORS.accel_bias_random_walk,  # [m/s^3/sqrt(Hz)]
    "accel_turn_on_bias": _SENSORS.accel_turn_on_bias,          # [m/s^2] 1 sigma
    "velocity_resolution": _SENSORS.velocity_resolution,        # [rad] differentiated encoder
    "gyro_sigma": 0.02,        # [rad/s] ideal_sensors only
    "accel_sigma": 0.05,       # [m/s^2] ideal_sensors only
    "encoder_resolution_deg": 0.1,
    "motor_delay": 0.010,      # [s] the plant's command transport delay
    # [s] the delay the controller is designed for (its swing and stance timing); None: the
    # plant's motor_delay. Set apart to sweep the plant's delay with the design held.
    "design_delay": None,
    "physics_dt": 0.001,       # [s]
    "ground_truth": False,     # controller on the simulator's trunk state (debugging only)
}
LEGGED_SENSOR_KEYS = ("gyro_noise_density", "gyro_bias_random_walk", "gyro_turn_on_bias",
                      "accel_noise_density", "accel_bias_random_walk", "accel_turn_on_bias",
                      "velocity_resolution")


def default_robot():
    return kl.Robot.load("quadruped")


def signals_from_settings(settings: dict) -> Signals:
    sensors = LeggedSensorSettings(ideal=bool(settings["ideal_sensors"]),
                                   **{k: float(settings[k]) for k in LEGGED_SENSOR_KEYS})
    return Signals(enabled=bool(settings["nonideal"]), gyro_sigma=settings["gyro_sigma"],
                   accel_sigma=settings["accel_sigma"],
                   encoder_resolution=float(np.deg2rad(settings["encoder_resolution_deg"])),
                   motor_delay=settings["motor_delay"], legged_sensors=sensors)


def rig_from_settings(settings: dict, seed: int, slope_deg: float = 0.0, config=None,
                      robot=None, terrain=None) -> Rig:
    """The quadruped rig of these settings (robot: a kl.Robot, default kiloloop's quadruped)."""
    return Rig(default_robot() if robot is None else robot, signals_from_settings(settings),
               seed=seed, video=settings.get("video"), slope_deg=slope_deg,
               physics_dt=settings["physics_dt"], config=config, terrain=terrain,
               ground_truth=bool(settings["ground_truth"]),
               design_delay=design_delay(settings))
