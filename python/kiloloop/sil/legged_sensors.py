"""Realistic sensors of the quadruped SIL rig: settings, and the C++ measurement stages the native
loop runs (cpp/sil/legged_sensor_stages.hpp, Rollout(stages=...); a test may call one through
stage.apply(t, y)).

  IMU     gyro and accelerometer: white noise, bias random walk and a seeded turn-on bias, from
          Allan-variance parameters (defaults: Bosch BMI088, cpp/sil/imu_model.hpp). The
          orientation is not handed over: the controller estimates it (its attitude filter,
          estimator.external_attitude false), the quaternion in y is not read.
  q       the joint encoders, quantized (encoder_resolution, 0.1 deg).
  qd      from encoder differences, (Q(q_k) - Q(q_k-1)) / dt, Q at the resolution of the encoder
          the drive differentiates: a 14-bit motor encoder behind a 4-10:1 gear is 4e-5 to 1e-4
          rad at the joint; 1e-4 (the coarse end) gives qd in steps of 0.1 rad/s at 1 kHz.

These are the default. `ideal=True` (the debug switch, `--set ideal_sensors=true`): the
simulator's IMU readings, its orientation as an exact external AHRS (estimator.external_attitude)
and the joint state, with only the white noise and quantization of the sensor model (gyro_sigma,
accel_sigma, encoder_resolution).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _core

_native = _core.native
# (noise density, bias random walk, turn-on bias sigma) of the C++ model's defaults.
_IMU = _native.imu_defaults if _native.available else {"gyro": (0.0, 0.0, 0.0), "accel": (0.0, 0.0, 0.0)}
# The IMU stage's random stream is the rig seed's plus this (apart from the sensor model's).
IMU_STREAM = 0x1A11


@dataclass
class LeggedSensorSettings:
    # Realistic by default: with the attitude filter's Kalman bias learning every 10 ms row of
    # bench/quadruped_matrix.md that passes with ideal sensors also passes with these
    # (bench/quadruped_matrix_realistic.md). ideal=True is the debug switch.
    ideal: bool = False
    gyro_noise_density: float = _IMU["gyro"][0]      # [rad/s/sqrt(Hz)]
    gyro_bias_random_walk: float = _IMU["gyro"][1]   # [rad/s^2/sqrt(Hz)]
    gyro_turn_on_bias: float = _IMU["gyro"][2]       # [rad/s] 1 sigma
    accel_noise_density: float = _IMU["accel"][0]    # [m/s^2/sqrt(Hz)]
    accel_bias_random_walk: float = _IMU["accel"][1] # [m/s^3/sqrt(Hz)]
    accel_turn_on_bias: float = _IMU["accel"][2]     # [m/s^2] 1 sigma
    velocity_resolution: float = 1e-4                # [rad] quantum of the differentiated encoder


def stages(settings: LeggedSensorSettings, *, joints: int, imu_offset: int, encoder_resolution: float,
           seed: int, control_dt: float = 0.001) -> list:
    """Fresh C++ stages for one run over y = [q (joints); qd (joints); gyro; accel; ...]:
    [JointEncoderStage, ImuStage]; [] when ideal."""
    if settings.ideal:
        return []
    if not _native.available:
        raise RuntimeError("realistic sensors need the native SIL models (kiloloop was built without "
                           "mujoco headers); use ideal_sensors=true")
    s = settings
    return [_native.JointEncoderStage(joints, 0, joints, float(encoder_resolution),
                                      float(s.velocity_resolution), control_dt),
            _native.ImuStage(imu_offset,
                             (s.gyro_noise_density, s.gyro_bias_random_walk, s.gyro_turn_on_bias),
                             (s.accel_noise_density, s.accel_bias_random_walk, s.accel_turn_on_bias),
                             control_dt, int(seed) + IMU_STREAM)]
