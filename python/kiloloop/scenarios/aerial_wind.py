"""aerial-wind: hovering in a steady wind with seeded gusts. The air pushes the body through a
quadratic drag model, F = 1/2 rho CdA |w - v| (w - v), applied at the vehicle's centre of mass; the
wind w is the steady part (ramped in over `ramp` seconds) plus gusts, a first-order (Dryden-like)
low-pass of white noise per axis with standard deviation gust_sigma and correlation time gust_tau,
seeded. The controller is not told about the wind: its integrators take up the steady part.
Judged after the ramp plus a settling second: position error and attitude error (against the
commanded attitude, which the position loop moves with every gust: 2 deg RMS allows for that
tracking on top of the ~0.3-0.5 deg the IMU noise alone gives at hover).

Sizes derived from the robot (derive()): CdA = DRAG_SHAPE (2 r)^2, r the largest rotor distance
from the base origin (the vehicle's span), so the same wind loads a bigger vehicle more.
"""
from __future__ import annotations

import numpy as np

from ..sil import aerial_signals
from .aerial_settings import COMMON_DEFAULTS, rig_from_settings
from .aerial_metrics import add_derived, diverged, hold, hold_errors
from . import ScenarioResult, evaluate
from .plots import AERIAL_PLOT

NAME = "aerial-wind"
DESCRIPTION = "hover in 5 m/s wind with seeded gusts (drag model): position and attitude error"
DURATION = 8.0
AIR_DENSITY = 1.225  # [kg/m^3] sea level
# CdA per squared span: a frame, battery and props seen from the side fill about a fifth of the
# span's square with a drag coefficient near 1 (0.05 m^2 for a 0.5 m quadrotor).
DRAG_SHAPE = 0.2
DEFAULTS = dict(COMMON_DEFAULTS, wind_speed=5.0, wind_heading_deg=30.0, gust_sigma=1.5,
                gust_tau=0.5, ramp=1.0, drag_area=0.05)
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"gust_tau": (">", 0.0), "gust_sigma": (">=", 0.0), "ramp": (">=", 0.0),
          "drag_area": (">=", 0.0)}
CRITERIA = {"max_position_error_m": ("<", 0.15), "attitude_error_rms_deg": ("<", 2.0),
            "diverged": ("<", 0.5)}


def derive(robot) -> dict:
    from ..robot import aerial as aerial_robot

    span = 2.0 * max(float(np.linalg.norm(r["position"][:2])) for r in aerial_robot.rotors(robot))
    return {"drag_area": DRAG_SHAPE * span * span}


def Wind(settings, seed) -> aerial_signals.Wind:
    """Steady wind plus seeded first-order gusts and the drag it puts on the vehicle, as data: the
    model itself is C++ (cpp/sil/wind_drag.hpp: exact discretization of d/dt g = -g / tau +
    sigma sqrt(2 / tau) white noise per axis, vertical gusts halved, drag at the vehicle's CoM)."""
    h = np.radians(settings["wind_heading_deg"])
    return aerial_signals.Wind(steady=settings["wind_speed"] * np.array([np.cos(h), np.sin(h), 0.0]),
                           ramp=max(float(settings["ramp"]), 1e-9),
                           gust_sigma=float(settings["gust_sigma"]),
                           gust_tau=float(settings["gust_tau"]),
                           drag_area=float(settings["drag_area"]),
                           seed=(0 if seed is None else int(seed)) + 7_000_001,
                           vertical_scale=0.5, air_density=AIR_DENSITY)


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, robot=robot)
    log = rig.run(DURATION if duration is None else duration, hold(rig),
                  disturbances=[Wind(settings, seed)])
    add_derived(log)
    t = log["t"]
    after = t >= min(settings["ramp"] + 1.0, 0.5 * t[-1])
    reason = diverged(log)
    metrics = {
        **hold_errors(log, after),
        "max_tilt_deg": float(np.degrees(log["tilt"][after]).max()),
        "max_wind_force_N": float(np.linalg.norm(log["wind_force"], axis=1).max()),
        "drag_area_m2": float(settings["drag_area"]),
        "saturated_ticks": int(np.sum(log["rotors_saturated"] > 0)),
        "diverged": float(bool(reason)),
    }
    result = ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))
    result.settings["divergence"] = reason
    return result


def plot_signals():
    return [("wind", "wind", None, "m/s")] + AERIAL_PLOT[:3]
