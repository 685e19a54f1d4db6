"""quadruped-trot: trot forward at a commanded speed (0.5 m/s by default) for 20 s on estimated
state with all non-idealities on: no fall, small roll/pitch, velocity tracked."""
from __future__ import annotations

import numpy as np

from .quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from .quadruped_metrics import add_derived, fell_early, trot_command, trot_metrics
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-trot"
DESCRIPTION = "quadruped trots at 0.5 m/s for 20 s: no fall, roll/pitch RMS, velocity RMS error"
DURATION = 20.0
START = 0.5     # [s] standing before the trot command
SETTLED = 2.0   # [s] metrics from here on (the command ramps at 1 m/s^2)
MIN_DURATION = SETTLED + JUDGED_WINDOW  # [s] shorter runs have no metrics to judge
DEFAULTS = dict(COMMON_DEFAULTS, speed=0.5)
CRITERIA = {"fell": ("<", 0.5), "roll_pitch_rms_deg": ("<", 3.0), "velocity_rms_error": ("<", 0.1)}


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, robot=robot)
    log = rig.run(DURATION if duration is None else duration, trot_command(settings["speed"]),
                  stop=fell_early(rig))
    add_derived(log)
    metrics = trot_metrics(log, settings["speed"], SETTLED, rig.fall_height)
    metrics["speed"] = settings["speed"]
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def max_passing_speed(speeds=(0.5, 0.75, 1.0, 1.25, 1.5), seeds=(0, 7), settings=None) -> dict:
    """Runs the scenario at increasing speeds; the highest that passes every criterion with every
    seed (the pytest runs seeds 0 and 7); per-speed worst metrics in `runs`."""
    from . import parse_settings

    best, table = 0.0, {}
    for speed in speeds:
        s = parse_settings(DEFAULTS, dict(settings or {}, speed=speed))
        results = [run(s, seed=seed) for seed in seeds]
        passed = all(r.passed for r in results)
        table[speed] = {"passed": passed, "seeds": list(seeds),
                        **{k: max(r.metrics[k] for r in results) for k in CRITERIA}}
        if passed:
            best = max(best, speed)
    return {"max_passing_speed": best, "runs": table}


def plot_signals():
    return QUADRUPED_PLOT
