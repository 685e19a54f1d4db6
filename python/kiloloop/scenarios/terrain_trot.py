"""A straight trot over a terrain (sil/terrain.py), judged on the ground truth: the run and the
metrics the terrain scenarios (quadruped-stones, -rough, -compliant) share."""
from __future__ import annotations

import numpy as np

from . import footholds
from .quadruped_settings import rig_from_settings
from .quadruped_metrics import add_derived, fell_early, trot_command, trot_metrics

START = 0.5     # [s] standing before the trot command
SETTLED = 2.0   # [s] metrics from here on (the command ramps at 1 m/s^2)


def run_trot(settings: dict, seed: int, duration: float, robot, terrain):
    """terrain: callable(resolved QuadrupedConfig) -> terrain spec. Returns (rig, log, metrics):
    trot_metrics plus the feet's slip and touch-down heights over whole stances after SETTLED."""
    rig = rig_from_settings(settings, seed, robot=robot, terrain=terrain)
    log = rig.run(duration, trot_command(settings["speed"], START), stop=fell_early(rig))
    add_derived(log)
    metrics = trot_metrics(log, settings["speed"], SETTLED, rig.fall_height)
    weight = rig.config.mass * 9.81
    intervals = footholds.stances(log, weight, SETTLED)
    slip = footholds.slip(log, intervals)
    heights = footholds.touchdown_heights(log, intervals, rig.plant.ground_height,
                                          rig.config.foot_radius)
    metrics.update({
        "stances": len(intervals),
        # No stance judged (a fall before SETTLED) is a failure, not a pass: NaN fails criteria.
        "max_slip_m": float(slip.max()) if slip.size else float("nan"),
        "mean_slip_m": float(slip.mean()) if slip.size else float("nan"),
        # Rolling alone moves a foot's centre by its radius x the leg's sweep over a stance
        # (about 0.5 rad: measured 0.55 radii on flat ground, both robots), so this ratio well
        # above 1 is the foot sliding.
        "max_slip_radii": float(slip.max() / rig.config.foot_radius) if slip.size else float("nan"),
        "touchdown_height_max_m": float(np.abs(heights).max()) if heights.size else float("nan"),
        # Landings on an edge (the sphere's centre over ground lower by more than half a radius):
        # blind footholds, reported, not judged.
        "edge_landings": float(np.mean(heights > 0.5 * rig.config.foot_radius))
        if heights.size else float("nan"),
        "foot_radius_m": rig.config.foot_radius,
    })
    return rig, log, metrics
