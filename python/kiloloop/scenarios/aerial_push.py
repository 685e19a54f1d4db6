"""aerial-push: hovering, the body is pushed sideways: a force pulse of `push_duration` on the
vehicle's centre of mass whose impulse changes its velocity by `delta_v` (impulse = total mass x
delta_v, so every vehicle gets the same kick in velocity terms), unannounced to the controller.
Reports the peak deviation from the hover point and the recovery time: from the push until the
position error stays below `recovered_within` for good.
"""
from __future__ import annotations

import numpy as np

from ..sil.events import Push
from .aerial_settings import COMMON_DEFAULTS, rig_from_settings
from .aerial_metrics import add_derived, diverged, hold
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import AERIAL_PLOT
from ..sil.timing import whole_periods

NAME = "aerial-push"
DESCRIPTION = "0.5 m/s sideways push at t = 1 s: peak deviation and recovery time"
DURATION = 5.0
DEFAULTS = dict(COMMON_DEFAULTS, delta_v=0.5, push_heading_deg=60.0, push_time=1.0,
                push_duration=0.02, recovered_within=0.02)
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"push_duration": (">", 0.0), "push_time": (">=", 0.0), "recovered_within": (">", 0.0)}
CRITERIA = {"peak_deviation_m": ("<", 0.15), "recovery_time_s": ("<", 2.5),
            "diverged": ("<", 0.5)}


def min_duration(settings) -> float:
    """[s] the push must be over: deviation and recovery are judged after it."""
    return float(settings["push_time"]) + float(settings["push_duration"]) + JUDGED_WINDOW


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, robot=robot)
    h = np.radians(settings["push_heading_deg"])
    direction = np.array([np.cos(h), np.sin(h), 0.0])
    t0, dur = float(settings["push_time"]), float(settings["push_duration"])
    force = rig.plant.total_mass * float(settings["delta_v"]) / dur * direction  # [N]

    # An event: the force at the vehicle's CoM for whole physics steps .
    log = rig.run(DURATION if duration is None else duration, hold(rig),
                  events=[(t0, Push(force, dur))])
    add_derived(log)
    t = log["t"]
    steps = whole_periods(dur, rig.plant.timestep)
    on = (t >= t0) & (t < t0 + steps * rig.plant.timestep - 1e-12)
    log.put("push_force", np.where(on[:, None], force, 0.0))
    err = np.linalg.norm(log["base_pos"] - log["pos_ref"], axis=1)
    after = t >= t0
    outside = np.nonzero(after & (err >= settings["recovered_within"]))[0]
    recovery = float(t[outside[-1]] + 0.001 - t0) if outside.size else 0.0
    if outside.size and outside[-1] == len(t) - 1:
        recovery = float("inf")  # never back within the band
    reason = diverged(log)
    metrics = {
        "peak_deviation_m": float(err[after].max()) if after.any() else float("nan"),
        "recovery_time_s": recovery,
        "peak_tilt_deg": float(np.degrees(log["tilt"][after]).max()),
        "impulse_Ns": float(np.linalg.norm(force) * dur),
        "diverged": float(bool(reason)),
    }
    result = ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))
    result.settings["divergence"] = reason
    return result


def plot_signals():
    return AERIAL_PLOT[:3]
