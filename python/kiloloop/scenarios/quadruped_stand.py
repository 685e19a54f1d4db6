"""quadruped-stand: the 12-DoF quadruped stands up from its initial pose and holds its height,
on estimated state, with sensor noise, encoder quantization and a 10 ms motor delay. Any
quadruped robot file: the height is the robot's derived (or configured) standing height."""
from __future__ import annotations

import numpy as np

from ..sil.quadruped_family import stand_command
from .quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from .quadruped_metrics import add_derived, fallen
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-stand"
DESCRIPTION = "quadruped stands at its standing height; height error after 1 s (noise, delay on)"
DURATION = 3.0
JUDGED_FROM = 1.0  # [s] the height error is judged from here on (standing up takes less)
MIN_DURATION = JUDGED_FROM + JUDGED_WINDOW
DEFAULTS = dict(COMMON_DEFAULTS, body_height=0.0)  # [m] 0: the robot's standing height
CRITERIA = {"height_error_after_1s_m": ("<", 0.01), "fell": ("<", 0.5)}


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    from ..robot.quadruped import controller_config
    from .quadruped_settings import default_robot, design_delay

    robot = robot or default_robot()
    config = controller_config(robot, actuation_delay=design_delay(settings))
    if settings["body_height"] > 0:
        config.body_height = settings["body_height"]
    rig = rig_from_settings(settings, seed, config=config, robot=robot)
    height = rig.config.body_height
    log = rig.run(DURATION if duration is None else duration, stand_command())
    add_derived(log)
    t, z = log["t"], log["base_pos"][:, 2]  # flat ground at z = 0
    after = t >= min(JUDGED_FROM, t[-1])
    metrics = {
        "height_error_after_1s_m": float(np.max(np.abs(z[after] - height))),
        "body_height_m": float(height),
        "final_height_m": float(z[-1]),
        "fell": float(fallen(log, rig.fall_height)),
        "failed_ticks": int(np.sum(log["status"] < 0)),
    }
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
