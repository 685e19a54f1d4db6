"""aerial-hover: a multirotor (the aerial manipulator by default; any aerial robot file) holds a
hover point 1 m up with its arm (if any) at its start pose, IMU noise,
attitude-estimate noise, motion-capture noise, encoder quantization and a 2 ms command delay on.
Judged after a 1 s settling window."""
from __future__ import annotations

import numpy as np

from .aerial_settings import COMMON_DEFAULTS, rig_from_settings
from .aerial_metrics import add_derived, diverged, hold, hold_errors
from . import ScenarioResult, evaluate
from .plots import AERIAL_PLOT

NAME = "aerial-hover"
DESCRIPTION = "multirotor (+ arm) hovers at 1 m; position and attitude error (noise on)"
DURATION = 5.0
SETTLE = 1.0  # [s] excluded from the metrics
DEFAULTS = dict(COMMON_DEFAULTS)
CRITERIA = {"max_position_error_m": ("<", 0.02), "attitude_error_rms_deg": ("<", 0.5),
            "diverged": ("<", 0.5)}


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, robot=robot)
    log = rig.run(DURATION if duration is None else duration, hold(rig))
    add_derived(log)
    t = log["t"]
    after = t >= min(SETTLE, 0.5 * t[-1])
    reason = diverged(log)
    metrics = {
        **hold_errors(log, after),
        "mean_thrust_N": float(np.mean(np.sum(log["thrust"][after], axis=1))),
        "diverged": float(bool(reason)),
        "failed_ticks": int(np.sum(log["status"] < 0)),
    }
    result = ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))
    result.settings["divergence"] = reason
    return result


def plot_signals():
    return AERIAL_PLOT
