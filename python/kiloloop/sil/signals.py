"""What lies between the plant and the controller, for every family: one settings struct.

The plant (MuJoCo) is ideal; a run's measurement y and command u pass through C++ models in the
native loop (cpp/sil/signal_models.hpp, sensor_stage.hpp):

    plant signals -> white noise, quantization (SensorModel) -> sensor stages (a realistic IMU,
    encoder differencing, attitude-estimate noise, dropouts) -> measurement delay -> adapter
    (controller) -> motor model (transport delay, first-order lag, saturation) -> MuJoCo ctrl

Every field is SI and every delay is in seconds; whole control ticks are taken by one rule
(sil/timing.py whole_periods: half up). Which fields a family reads is the family's business
(sil/*_family.py): an arm's y has joints only, a quadruped's an IMU too, a multirotor's a
motion-capture position as well. A field a family's measurement lacks is ignored there.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..errors import InputError
from .legged_sensors import LeggedSensorSettings
from .timing import whole_periods


@dataclass
class Signals:
    """Sensor and actuator non-idealities of one run; the defaults are the ideal plant."""

    # Master switch: False turns every effect below off (debugging, ideal-plant references).
    enabled: bool = True
    # Joint encoders: white noise per sample [rad], [rad/s]; quantization step of q [rad].
    q_sigma: float = 0.0
    qd_sigma: float = 0.0
    encoder_resolution: float = 0.0
    # IMU white noise per axis and sample: gyro [rad/s], accelerometer [m/s^2]; a small random
    # rotation [rad] per axis on the reported orientation (an attitude estimator's error).
    gyro_sigma: float = 0.0
    accel_sigma: float = 0.0
    quat_sigma: float = 0.0
    # Motion capture (a multirotor's position and velocity source): white noise [m], [m/s].
    position_sigma: float = 0.0
    velocity_sigma: float = 0.0
    # A realistic legged sensor set instead of the white IMU noise: a MEMS IMU with bias random
    # walk and turn-on bias, encoder-difference joint velocity (sil/legged_sensors.py); the
    # controller then estimates its attitude itself. None: the white-noise models above.
    legged_sensors: LeggedSensorSettings | None = None
    # [s] age of the measurement the controller gets (a transport delay on y).
    measurement_delay: float = 0.0
    # [s] command transport delay to the motors (an ESC, a bus).
    motor_delay: float = 0.0
    # [s] first-order lag of the produced torque (0: none).
    motor_time_constant: float = 0.0
    # Legged motors saturate at this times the URDF effort (< 1: weaker motors).
    torque_limit_scale: float = 1.0

    def validate(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("enabled", "legged_sensors"):
                continue
            if not (np.isfinite(value) and value >= 0):
                raise InputError(f"{f.name}: expected a finite number >= 0, got {value!r}")
        if not self.torque_limit_scale > 0:
            raise InputError(f"torque_limit_scale: expected > 0, got {self.torque_limit_scale!r}")

    def on(self, name: str) -> float:
        """The field's value when enabled, else 0."""
        return float(getattr(self, name)) if self.enabled else 0.0

    def ticks(self, name: str, control_dt: float) -> int:
        """A delay field in whole control ticks (0 when disabled)."""
        return whole_periods(self.on(name), control_dt)

    @property
    def realistic_legged(self) -> bool:
        """Whether the realistic legged sensor stages replace the white-noise IMU model."""
        return (self.enabled and self.legged_sensors is not None
                and not self.legged_sensors.ideal)


IDEAL = Signals(enabled=False)
