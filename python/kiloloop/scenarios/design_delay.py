"""The `design_delay` setting of the quadruped and aerial scenarios: the actuation delay [s] the
controller is designed for, apart from the plant's `motor_delay`, so that the plant's delay can be
swept with the design held (`kiloloop margins`' predictive check, docs/margins.md)."""
from __future__ import annotations

import math

from ..errors import InputError


def design_delay(settings: dict) -> float:
    """[s] the setting, or the plant's motor_delay when it is unset (0 on the ideal plant)."""
    design = settings.get("design_delay")
    if design not in (None, "", "none"):
        value = float(design)
        if not (math.isfinite(value) and value >= 0):
            raise InputError(f"design_delay: expected a delay [s] >= 0, got {design!r}")
        return value
    return float(settings["motor_delay"]) if settings["nonideal"] else 0.0
