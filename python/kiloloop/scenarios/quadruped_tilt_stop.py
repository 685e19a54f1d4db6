"""quadruped-tilt-stop: a lateral shove large enough to tip the standing robot over. The safe
stop (damped joints, crouch) must engage within one tick of the trunk crossing 15 deg of tilt."""
from __future__ import annotations

import numpy as np

from ..sil.events import Push
from ..sil.quadruped_family import stand_command
from .quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from .quadruped_metrics import add_derived
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-tilt-stop"
DESCRIPTION = "a shove tips the robot: safe stop within one tick of 15 deg tilt"
DURATION = 2.0
PUSH_TIME = 0.5
# impulse [N s]: 0 = impulse_per_kg times the robot's mass (40 N s on the 17.6 kg model).
DEFAULTS = dict(COMMON_DEFAULTS, impulse=0.0, impulse_per_kg=2.3, push_duration=0.1, push_height=0.0)
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"push_duration": (">", 0.0)}
CRITERIA = {"ticks_late": ("<=", 1.0), "tilted": (">", 0.5)}


def min_duration(settings) -> float:
    """[s] the shove must be over before the tilt can be judged."""
    return PUSH_TIME + float(settings["push_duration"]) + JUDGED_WINDOW


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, robot=robot)
    impulse = settings["impulse"] or settings["impulse_per_kg"] * rig.config.mass
    force = np.array([0.0, impulse / settings["push_duration"], 0.0])
    events = [(PUSH_TIME, Push(force, settings["push_duration"]))]
    log = rig.run(DURATION if duration is None else duration, stand_command(),
                  events=events)
    add_derived(log)
    rp = np.radians(log["roll_pitch_deg"])
    tilt = np.degrees(np.arccos(np.clip(np.cos(rp[:, 0]) * np.cos(rp[:, 1]), -1, 1)))
    crossed = np.flatnonzero(tilt > 15.0)
    stopped = np.flatnonzero(log["safe_stop"] > 0.5)
    # The tick whose sensor reading first shows > 15 deg must already carry the safe output:
    # ticks_late = stop tick - crossing tick (<= 0 when the estimate leads, 1 allowed).
    first_cross = int(crossed[0]) if crossed.size else -1
    first_stop = int(stopped[0]) if stopped.size else -1
    metrics = {
        "tilted": float(crossed.size > 0),
        "crossing_tick": first_cross,
        "safe_stop_tick": first_stop,
        "ticks_late": float(first_stop - first_cross) if crossed.size and stopped.size else float("inf"),
        "safe_stop_latched": float(stopped.size > 0 and bool(np.all(log["safe_stop"][first_stop:] > 0.5))),
        "max_tilt_deg": float(tilt.max()),
    }
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
