"""quadruped-turn: a turning trot, 0.5 m/s forward with 0.5 rad/s of yaw, for 10 s on estimated
state with the non-idealities on. Reports the peak ground reaction per leg as a multiple of the
robot's weight (what the legs' structure and motors must carry when turning)."""
from __future__ import annotations

import numpy as np

from ..sil.quadruped_family import CommandSchedule
from .quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from .quadruped_metrics import add_derived, fell_early, trot_metrics
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-turn"
DESCRIPTION = "turning trot 0.5 m/s + 0.5 rad/s: no fall, yaw rate tracked, peak foot load per leg"
DURATION = 10.0
START = 0.5     # [s] standing before the command
SETTLED = 2.0   # [s] metrics from here on (the command ramps at 1 m/s^2, 1 rad/s^2)
MIN_DURATION = SETTLED + JUDGED_WINDOW  # [s] shorter runs have no metrics to judge
DEFAULTS = dict(COMMON_DEFAULTS, speed=0.5, yaw_rate=0.5)
CRITERIA = {"fell": ("<", 0.5), "roll_pitch_rms_deg": ("<", 3.0), "velocity_rms_error": ("<", 0.1),
            "yaw_rate_rms_error": ("<", 0.1)}
LEGS = ("FL", "FR", "RL", "RR")


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, robot=robot)
    v = np.array([settings["speed"], 0.0, settings["yaw_rate"]])

    command = CommandSchedule([(0.0, 0, np.zeros(3)), (START, 1, v)])

    log = rig.run(DURATION if duration is None else duration, command, stop=fell_early(rig))
    add_derived(log)
    metrics = trot_metrics(log, settings["speed"], SETTLED, rig.fall_height)
    k = log["t"] >= SETTLED
    yaw_rate = log["base_omega"][k, 2]  # world z: the heading's rate on flat ground
    metrics["yaw_rate_rms_error"] = float(np.sqrt(np.mean((yaw_rate - settings["yaw_rate"]) ** 2)))
    metrics["mean_yaw_rate"] = float(np.mean(yaw_rate))
    weight = rig.config.mass * 9.81
    force = np.linalg.norm(log["foot_force"][k], axis=2)  # (ticks, legs) [N]
    for i, leg in enumerate(LEGS):
        metrics[f"peak_load_{leg}_bw"] = float(force[:, i].max() / weight) if force.size else float("nan")
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
