"""quadruped-stand: the 12-DoF quadruped stands up from its initial pose and holds its height,
on estimated state, with sensor noise, encoder quantization and a 10 ms motor delay."""
from __future__ import annotations

import numpy as np

from ..sil.quadruped_rig import (COMMON_DEFAULTS, QUADRUPED_PLOT, add_derived, fallen,
                                 rig_from_settings)
from . import ScenarioResult, evaluate

NAME = "quadruped-stand"
DESCRIPTION = "quadruped stands at 0.30 m; height error after 1 s (noise, delay on)"
DURATION = 3.0
DEFAULTS = dict(COMMON_DEFAULTS, body_height=0.30)
CRITERIA = {"height_error_after_1s_m": ("<", 0.01), "fell": ("<", 0.5)}


def run(settings: dict, seed: int = 0, duration: float | None = None) -> ScenarioResult:
    import kiloloop as kl

    config = kl.QuadrupedConfig()
    config.body_height = settings["body_height"]
    rig = rig_from_settings(settings, seed, config=config)
    log = rig.run(DURATION if duration is None else duration, lambda t: (0, np.zeros(3)))
    add_derived(log)
    t, z = log["t"], log["base_pos"][:, 2]  # flat ground at z = 0
    after = t >= 1.0
    metrics = {
        "height_error_after_1s_m": float(np.max(np.abs(z[after] - settings["body_height"]))),
        "final_height_m": float(z[-1]),
        "fell": float(fallen(log)),
        "failed_ticks": int(np.sum(log["status"] < 0)),
    }
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
