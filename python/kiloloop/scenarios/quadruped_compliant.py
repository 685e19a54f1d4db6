"""quadruped-compliant: trot at 0.5 m/s on soft ground, normal stiffness 1e3 N/m per contact
(sil/terrain.py Compliant: MuJoCo's soft contact calibrated so that force = stiffness x sinkage;
tests/test_terrain.py measures it), critically damped for the load of one foot (a quarter of the
robot's mass), on estimated state with the non-idealities on: no fall, level trunk, velocity
tracked, feet do not slide. A standing foot sinks m g / (4 k): 43 mm for the 17.6 kg model."""
from __future__ import annotations

from . import footholds
from .quadruped_settings import COMMON_DEFAULTS
from ..sil.terrain import Compliant
from .terrain_trot import SETTLED, run_trot
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import QUADRUPED_PLOT

NAME = "quadruped-compliant"
DESCRIPTION = "trot 0.5 m/s on soft ground (1e3 N/m): no fall, roll/pitch, velocity, slip"
DURATION = 10.0
MIN_DURATION = SETTLED + JUDGED_WINDOW  # [s] metrics from SETTLED on (scenarios/terrain_trot.py)
DEFAULTS = dict(COMMON_DEFAULTS, speed=0.5, stiffness=1e3, damping_ratio=1.0)
# The flat trot's bounds (quadruped-trot), and no sliding foot (scenarios/terrain_trot.py).
CRITERIA = {"fell": ("<", 0.5), "roll_pitch_rms_deg": ("<", 3.0), "velocity_rms_error": ("<", 0.1),
            "max_slip_radii": ("<", 2.0)}


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    def terrain(config):
        return Compliant(stiffness=settings["stiffness"], load_mass=config.mass / 4,
                         damping_ratio=settings["damping_ratio"])

    rig, log, metrics = run_trot(settings, seed, DURATION if duration is None else duration,
                                 robot, terrain)
    # Deepest sinkage of a loaded foot's sphere bottom below the surface (z = 0) [m].
    intervals = footholds.stances(log, rig.config.mass * 9.81, SETTLED)
    r = rig.config.foot_radius
    depth = [r - log["foot_pos"][s:e + 1, leg, 2].min() for leg, s, e in intervals]
    metrics["max_sinkage_m"] = float(max(depth)) if depth else float("nan")
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    return QUADRUPED_PLOT
