"""The SIL's two time rules, once: seconds to whole ticks (or physics steps), and the physics
substeps of one control period.

A duration or delay given in seconds becomes the nearest whole number of periods, halves rounded
up (0.0105 s at 1 ms: 11 ticks); the 1e-9 absorbs the binary representation of decimal seconds
(0.0035 / 0.001 = 3.4999999999999996). The C++ loop rounds a push's physics steps the same way
(cpp/sil/native_loop.cpp). The physics timestep must divide the control period exactly: a
controller at 1 kHz over a 0.7 ms physics step would see the plant at uneven times.
"""
from __future__ import annotations

import math

from ..errors import InputError

CONTROL_DT = 0.001  # [s] the controllers' period (1 kHz)


def whole_periods(seconds: float, period: float = CONTROL_DT) -> int:
    """[periods] the nearest whole number of `period` [s] in `seconds` [s], halves up."""
    return int(math.floor(seconds / period + 0.5 + 1e-9))


def substeps(physics_dt: float, control_dt: float = CONTROL_DT) -> int:
    """Physics steps per control period; InputError naming physics_dt unless it divides it."""
    if not (isinstance(physics_dt, (int, float)) and math.isfinite(physics_dt) and physics_dt > 0):
        raise InputError(f"physics_dt: expected a timestep [s] > 0, got {physics_dt!r}")
    n = round(control_dt / physics_dt)
    if n < 1 or abs(n * physics_dt - control_dt) > 1e-12:
        raise InputError(f"physics_dt: {physics_dt:g} s does not divide the {control_dt:g} s "
                         f"control period (try {control_dt / max(n, 1):g} or "
                         f"{control_dt / (max(n, 1) + 1):g})")
    return int(n)
