"""quadruped-slope: standing on a 5 deg slope. The friction pyramids follow the estimated ground
normal; the feet must not creep, and the front/rear split of the normal forces must match the
static-equilibrium prediction from the robot's CoM and footholds."""
from __future__ import annotations

import numpy as np

from ..sil.quadruped_family import stand_command
from .quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from .quadruped_metrics import add_derived, fallen
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-slope"
DESCRIPTION = "quadruped stands on a 5 deg slope: foot drift, front/rear normal-force split"
DURATION = 5.5  # [s] 0.5 s to settle, then the 5 s over which drift is measured
SETTLE = 0.5
MIN_DURATION = SETTLE + JUDGED_WINDOW  # [s] the drift is measured from SETTLE on
DEFAULTS = dict(COMMON_DEFAULTS, slope_deg=5.0)
CRITERIA = {"foot_drift_m": ("<", 0.01), "split_error_rel": ("<", 0.05), "fell": ("<", 0.5)}


def static_front_share(plant, foot_radius: float = 0.02) -> float:
    """Front feet's share of the total normal force predicted by rigid static equilibrium.

    In the slope frame (s along the slope, n along its normal), moments about the rear contact
    line: N_front L = W (cos a x_c - sin a h_c), where x_c is the CoM's distance up the slope
    from the rear line, h_c its height above the surface, L the rear-to-front distance. Friction
    acts in the surface and has no moment about that line.
    """
    a = plant.slope
    s_dir, n_dir = np.array([np.cos(a), 0.0, np.sin(a)]), plant.ground_normal()
    com = plant.data.subtree_com[plant.model.body(plant.base_body).id]
    contact = plant.foot_positions() - foot_radius * n_dir  # foot sphere centre -> contact point
    rear = 0.5 * (contact[2] + contact[3])
    front = 0.5 * (contact[0] + contact[1])
    L = (front - rear) @ s_dir
    x_c, h_c = (com - rear) @ s_dir, (com - rear) @ n_dir
    # The CoM sits uphill of the rear line; gravity's along-slope component (W sin a, downhill)
    # at height h_c tips it back onto the rear feet.
    return float((np.cos(a) * x_c - np.sin(a) * h_c) / (L * np.cos(a)))


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, slope_deg=settings["slope_deg"], robot=robot)
    log = rig.run(DURATION if duration is None else duration, stand_command())
    add_derived(log)
    t = log["t"]
    start = np.searchsorted(t, SETTLE)
    feet = log["foot_pos"]
    drift = np.linalg.norm(feet[-1] - feet[start], axis=1)
    normal = rig.plant.ground_normal()
    fn = log["foot_force"][-200:] @ normal  # last 0.2 s, normal components (ticks, feet)
    measured = float(np.mean(fn[:, :2].sum(axis=1) / fn.sum(axis=1)))
    predicted = static_front_share(rig.plant, rig.config.foot_radius)
    metrics = {
        "foot_drift_m": float(drift.max()),
        "front_share_measured": measured,
        "front_share_predicted": predicted,
        "split_error_rel": float(abs(measured - predicted) / predicted),
        "fell": float(fallen(log, rig.fall_height)),
        "failed_ticks": int(np.sum(log["status"] < 0)),
    }
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
