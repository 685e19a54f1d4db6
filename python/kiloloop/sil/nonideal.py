"""Switchable, seeded sensor and actuator non-idealities for the SIL loop.

The plant (sil/floating_plant.py, sil/plant.py) is ideal; these sit between it and the controller:
  plant sensors -> SensorModel.apply -> controller -> saturate -> MotorDelay.push
                -> plant.set_torque
Everything random draws from one seeded numpy Generator, so a run is reproducible from its seed.
All quantities SI: rad, rad/s, m/s^2, s, N m.
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .timing import whole_periods


@dataclass
class NonIdealities:
    """One settings struct; `enabled=False` turns every effect off (the ideal plant)."""

    enabled: bool = True
    # [rad/s] white noise per axis, per sample (the default). A MEMS gyro such as the
    # BMI088 or ICM-42688 has a noise density of 0.003-0.014 deg/s/sqrt(Hz), i.e. 0.001-0.005 rad/s
    # over a few hundred Hz; 0.02 covers the legs' vibration on top and errs on the hard side.
    gyro_sigma: float = 0.02
    # [m/s^2] white noise per axis, per sample. MEMS accelerometers have 70-200 ug/sqrt(Hz)
    # (ICM-42688, BMI088); over a ~500 Hz bandwidth that is 0.015-0.045 m/s^2, rounded up to 0.05.
    accel_sigma: float = 0.05
    # [rad] small random rotation per axis on the reported orientation. 0: the attitude estimate is
    # left to the controller's estimator (the IMU's quaternion is then exact, a known optimism).
    quat_sigma: float = 0.0
    # [rad] quantization step of the joint encoders (0.1 deg, the value).
    encoder_resolution: float = float(np.deg2rad(0.1))
    # False: joint velocities pass through unchanged, standing in for a drive's velocity from its
    # motor-side encoder (finer by the gear ratio) or observer. True: (q_k - q_k-1) / dt from the
    # quantized positions, which at 1 kHz and 0.1 deg comes in steps of 1.75 rad/s and needs the
    # controller's own filtering; the first sample after reset reads 0.
    velocity_from_encoder_diff: bool = False
    # [s] command transport delay from the controller to the motors, whole control ticks
    # (rounded half up), 0-35 ms in the range.
    motor_delay: float = 0.010
    # Torques saturate at torque_limit_scale * effort (URDF effort); < 1 models weaker motors.
    torque_limit_scale: float = 1.0

    def validate(self) -> None:
        for name in ("gyro_sigma", "accel_sigma", "quat_sigma", "encoder_resolution",
                     "motor_delay"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0):
                raise InputError(f"{name}: expected a finite number >= 0, got {value!r}")
        if not (self.torque_limit_scale > 0):
            raise InputError(f"torque_limit_scale: expected > 0, got {self.torque_limit_scale!r}")

    def saturate(self, tau, effort) -> np.ndarray:
        """saturate() at torque_limit_scale when enabled; a copy of tau when not."""
        if not self.enabled:
            return _check(tau, "tau").copy()
        return saturate(tau, effort, self.torque_limit_scale)


def _check(x, name: str) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: non-finite value")
    return arr


def _small_rotation(quat: np.ndarray, dtheta: np.ndarray) -> np.ndarray:
    """quat (w, x, y, z) followed by a rotation vector dtheta in the body frame: q * exp(dtheta)."""
    angle = float(np.linalg.norm(dtheta))
    if angle < 1e-12:
        return quat.copy()
    axis = dtheta / angle
    w2, v2 = math.cos(angle / 2), math.sin(angle / 2) * axis
    w1, v1 = quat[0], quat[1:]
    out = np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])
    return out / np.linalg.norm(out)


class SensorModel:
    """Noisy IMU and quantized encoders: apply() maps ideal readings to measured ones."""

    def __init__(self, settings: NonIdealities | None = None, seed: int | None = 0,
                 control_dt: float = 0.001):
        self.settings = NonIdealities() if settings is None else settings
        self.settings.validate()
        if not (control_dt > 0):
            raise InputError(f"control_dt: expected > 0, got {control_dt!r}")
        self.control_dt = float(control_dt)
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self._q_prev: np.ndarray | None = None

    def reset(self, seed: int | None = None) -> None:
        """Forget the encoder history; with a seed, restart the random stream."""
        self._q_prev = None
        if seed is not None:
            self.seed = seed
            self.rng = np.random.default_rng(seed)

    def quantize(self, q) -> np.ndarray:
        step = self.settings.encoder_resolution
        q = _check(q, "q")
        return q.copy() if step == 0 else step * np.round(q / step)

    def apply(self, imu: dict, q, qd) -> tuple[dict, np.ndarray, np.ndarray]:
        """(imu, q, qd) -> measured copies; imu {"gyro": (3,), "accel": (3,), "quat": (4,)}."""
        s = self.settings
        gyro = _check(imu["gyro"], "gyro").copy()
        accel = _check(imu["accel"], "accel").copy()
        quat = _check(imu["quat"], "quat").copy()
        q = _check(q, "q").copy()
        qd = _check(qd, "qd").copy()
        if not s.enabled:
            return {"gyro": gyro, "accel": accel, "quat": quat}, q, qd
        # Fixed draw order (gyro, accel, quat) keeps a seed's stream independent of the sigmas.
        gyro += s.gyro_sigma * self.rng.standard_normal(3)
        accel += s.accel_sigma * self.rng.standard_normal(3)
        dtheta = s.quat_sigma * self.rng.standard_normal(3)
        if s.quat_sigma > 0:
            quat = _small_rotation(quat, dtheta)
        q_meas = self.quantize(q)
        if s.velocity_from_encoder_diff:
            qd_meas = (np.zeros_like(q_meas) if self._q_prev is None
                       else (q_meas - self._q_prev) / self.control_dt)
        else:
            qd_meas = qd
        self._q_prev = q_meas
        return {"gyro": gyro, "accel": accel, "quat": quat}, q_meas, qd_meas


class MotorDelay:
    """FIFO of torque commands: what a controller sends at tick k reaches the motors at k + ticks.

    delay: [s], or a NonIdealities (its motor_delay, or 0 when it is disabled). n: the number of
    joints, optional (checked against every command when given). Until the first command has
    travelled through, the motors get `initial`: "zeros" (a drive with no command outputs no
    torque, the default) or "first" (the first command: no start-up sag).
    """

    def __init__(self, delay: float | NonIdealities = 0.010, control_dt: float = 0.001,
                 n: int | None = None, initial: str = "zeros"):
        if isinstance(delay, NonIdealities):
            delay.validate()
            delay = delay.motor_delay if delay.enabled else 0.0
        delay, control_dt = float(delay), float(control_dt)
        if not (np.isfinite(delay) and delay >= 0):
            raise InputError(f"delay: expected a finite number >= 0, got {delay!r}")
        if not (np.isfinite(control_dt) and control_dt > 0):
            raise InputError(f"control_dt: expected > 0, got {control_dt!r}")
        if initial not in ("zeros", "first"):
            raise InputError(f"initial: expected 'zeros' or 'first', got {initial!r}")
        if n is not None and int(n) < 1:
            raise InputError(f"n: expected a positive joint count, got {n!r}")
        # Whole ticks, half rounded up (Python's round() would send 2.5 ticks to 2); the 1e-9
        # keeps quotients such as 0.0215 / 0.001 = 21.499999999999996 a tie.
        self.ticks = whole_periods(delay, control_dt)
        self.control_dt = control_dt
        self.n = None if n is None else int(n)
        self.initial = initial
        self._fifo: deque[np.ndarray] = deque()
        self._primed = False

    @classmethod
    def from_settings(cls, settings: NonIdealities, control_dt: float = 0.001,
                      n: int | None = None, initial: str = "zeros") -> MotorDelay:
        return cls(settings, control_dt, n, initial)

    @property
    def delay(self) -> float:
        """[s] the delay actually applied (whole ticks)."""
        return self.ticks * self.control_dt

    def reset(self) -> None:
        self._fifo.clear()
        self._primed = False

    def push(self, tau) -> np.ndarray:
        """Queue this tick's command; returns the command that reaches the motors now."""
        tau = _check(tau, "tau").copy()
        if self.n is not None and tau.shape != (self.n,):
            raise ValueError(f"tau: expected shape ({self.n},), got {tau.shape}")
        if not self._primed:
            fill = np.zeros_like(tau) if self.initial == "zeros" else tau
            self._fifo.extend(fill.copy() for _ in range(self.ticks))
            self._primed = True
        self._fifo.append(tau)
        return self._fifo.popleft()


def saturate(tau, effort, scale: float = 1.0) -> np.ndarray:
    """tau clipped to +-scale * effort (per joint; effort may be inf for no limit)."""
    if not (scale > 0):
        raise InputError(f"scale: expected > 0, got {scale!r}")
    limit = scale * np.asarray(effort, dtype=float)
    return np.clip(_check(tau, "tau"), -limit, limit)
