"""quadruped-stones: trot at 0.5 m/s across stepping stones, 0.3 x 0.3 m, tops at random (seeded)
heights, blind (no terrain map: the controller finds each stone by touching it), on estimated
state with the non-idealities on: no fall, level trunk, velocity tracked, feet do not slide.
The height spread is a fraction of the swing height the controller derives (0.16 leg lengths):
a step between neighbours is at most half the swing apex."""
from __future__ import annotations

from .quadruped_settings import COMMON_DEFAULTS
from ..sil.terrain import Stones
from .terrain_trot import SETTLED, run_trot
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-stones"
DESCRIPTION = "trot 0.5 m/s over 0.3 m stepping stones at random heights: no fall, roll/pitch, velocity, slip"
DURATION = 10.0
MIN_DURATION = SETTLED + JUDGED_WINDOW  # [s] metrics from SETTLED on (scenarios/terrain_trot.py)
DEFAULTS = dict(COMMON_DEFAULTS, speed=0.5, stone_size=0.3, gap=0.0,
                spread_swing_heights=0.25)  # tops in +-0.25 swing heights
# The flat trot's bounds (quadruped-trot): the stones may shake the trunk and slow it, but not
# beyond what the trot is allowed on flat ground. Slip: see scenarios/terrain_trot.py (1 radius of
# travel = rolling twice as far as a stance sweeps; beyond 2 a foot has slid).
CRITERIA = {"fell": ("<", 0.5), "roll_pitch_rms_deg": ("<", 3.0), "velocity_rms_error": ("<", 0.1),
            "max_slip_radii": ("<", 2.0)}


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    def terrain(config):
        return Stones(spread=settings["spread_swing_heights"] * config.swing_height, seed=seed,
                      size=settings["stone_size"], gap=settings["gap"])

    rig, log, metrics = run_trot(settings, seed, DURATION if duration is None else duration,
                                 robot, terrain)
    metrics["stone_spread_m"] = rig.plant.terrain.spread
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
