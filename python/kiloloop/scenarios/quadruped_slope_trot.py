"""quadruped-slope-trot: trot up a 10 deg slope at 0.5 m/s, then back down it (backwards, the
same speed), on estimated state with the non-idealities on: no fall, level trunk, velocity
tracked both ways. The slope is an infinite plane rising along +x (sil/floating_plant.py)."""
from __future__ import annotations

import numpy as np

from ..sil.quadruped_family import CommandSchedule
from .quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from .quadruped_metrics import add_derived, fallen, fell_early, heading_velocity
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-slope-trot"
DESCRIPTION = "trot up a 10 deg slope and back down at 0.5 m/s: no fall, roll/pitch, velocity"
DURATION = 12.0
START, REVERSE = 0.5, 6.0   # [s] trot uphill from START, downhill (backwards) from REVERSE
UP, DOWN = (2.0, 6.0), (8.0, 12.0)  # [s] windows the metrics use (after each ramp)
MIN_DURATION = DOWN[0] + JUDGED_WINDOW  # [s] the downhill window must have begun
DEFAULTS = dict(COMMON_DEFAULTS, slope_deg=10.0, speed=0.5)
CRITERIA = {"fell": ("<", 0.5), "roll_pitch_rms_deg": ("<", 3.0),
            "velocity_rms_error_up": ("<", 0.1), "velocity_rms_error_down": ("<", 0.1)}


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, slope_deg=settings["slope_deg"], robot=robot)
    speed = settings["speed"]

    command = CommandSchedule([(0.0, 0, np.zeros(3)), (START, 1, np.array([speed, 0.0, 0.0])),
                               (REVERSE, 1, np.array([-speed, 0.0, 0.0]))])

    log = rig.run(DURATION if duration is None else duration, command, stop=fell_early(rig))
    add_derived(log)
    t, v = log["t"], heading_velocity(log)[:, 0]
    up = (t >= UP[0]) & (t < UP[1])
    down = (t >= DOWN[0]) & (t < DOWN[1])
    rp = log["roll_pitch_deg"][t >= UP[0]]
    rms = lambda x: float(np.sqrt(np.mean(x ** 2))) if x.size else float("nan")  # noqa: E731
    metrics = {
        "fell": float(fallen(log, rig.fall_height)),
        "roll_pitch_rms_deg": float(max(rms(rp[:, 0]), rms(rp[:, 1]))) if rp.size else float("nan"),
        "velocity_rms_error_up": rms(v[up] - speed),
        "velocity_rms_error_down": rms(v[down] + speed),
        "climbed_m": float(log["base_pos"][:, 2].max() - log["base_pos"][0, 2]),
        "failed_ticks": int(np.sum(log["status"] < 0)),
    }
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
