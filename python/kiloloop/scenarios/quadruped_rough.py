"""quadruped-rough: trot at 0.5 m/s over a rough heightfield of smooth random bumps (seeded),
blind, on estimated state with the non-idealities on: no fall, level trunk, velocity tracked,
feet do not slide. Sized from the robot: peak |height| a fraction of the swing height the
controller derives, bumps about one standing height long (body_height)."""
from __future__ import annotations

from .quadruped_settings import COMMON_DEFAULTS
from ..sil.terrain import Rough
from .terrain_trot import SETTLED, run_trot
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-rough"
DESCRIPTION = "trot 0.5 m/s over a random heightfield: no fall, roll/pitch, velocity, slip"
DURATION = 10.0
MIN_DURATION = SETTLED + JUDGED_WINDOW  # [s] metrics from SETTLED on (scenarios/terrain_trot.py)
DEFAULTS = dict(COMMON_DEFAULTS, speed=0.5, amplitude_swing_heights=0.25,
                bump_body_heights=1.0)
# The flat trot's bounds (quadruped-trot), and no sliding foot (scenarios/terrain_trot.py).
CRITERIA = {"fell": ("<", 0.5), "roll_pitch_rms_deg": ("<", 3.0), "velocity_rms_error": ("<", 0.1),
            "max_slip_radii": ("<", 2.0)}


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    def terrain(config):
        return Rough(amplitude=settings["amplitude_swing_heights"] * config.swing_height,
                     bump_length=settings["bump_body_heights"] * config.body_height, seed=seed)

    rig, log, metrics = run_trot(settings, seed, DURATION if duration is None else duration,
                                 robot, terrain)
    metrics["amplitude_m"] = rig.plant.terrain.amplitude
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
