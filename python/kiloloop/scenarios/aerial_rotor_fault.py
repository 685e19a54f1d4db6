"""aerial-rotor-fault: hovering, one rotor (the robot file's first by default) drops to 70 % efficiency (thrust and drag
torque) at t = 1 s, unannounced to the controller; its integrators take up the imbalance. Judged
on the largest distance from the hover point over the whole run. Refused at start (refusal())
when the rotors left cannot hold the vehicle's weight level with no torque to spare, yaw
included: a fault no controller rides out."""
from __future__ import annotations

import numpy as np

from ..sil.events import RotorFault
from .aerial_settings import COMMON_DEFAULTS, rig_from_settings
from .aerial_metrics import add_derived, diverged, hold
from ..errors import InputError, ScenarioRefused
from ..robot import aerial as aerial_robot
from ..sil.aerial_family import load_robot
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import AERIAL_PLOT

NAME = "aerial-rotor-fault"
DESCRIPTION = "one rotor at 70 % efficiency from t = 1 s: stays airborne, within 10 cm"
DURATION = 6.0
DEFAULTS = dict(COMMON_DEFAULTS, rotor=0, efficiency=0.7, fault_time=1.0)
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"fault_time": (">=", 0.0), "efficiency": (">=", 0.0)}
CRITERIA = {"max_hover_deviation_m": ("<", 0.10), "airborne": (">", 0.5)}


def min_duration(settings) -> float:
    """[s] the fault must have happened."""
    return float(settings["fault_time"]) + JUDGED_WINDOW


def refusal(robot, settings) -> str:
    """'' when the rotors, rotor `rotor` at `efficiency`, can still hold the vehicle's weight
    level with zero torque (robot/aerial.py hover_weight_with), else why not, with the figures."""
    n = len(aerial_robot.rotors(robot))
    k, eff = int(settings["rotor"]), float(settings["efficiency"])
    if not 0 <= k < n:
        raise InputError(f"rotor: expected 0..{n - 1}, got {k}")
    efficiency = np.ones(n)
    efficiency[k] = eff
    held, weight = aerial_robot.hover_weight_with(robot, efficiency)
    if held >= weight:
        return ""
    full, _ = aerial_robot.hover_weight_with(robot, np.ones(n))
    return (f"{robot.name}: {NAME}: with rotor {k} at {eff:.0%} the rotors hold at most "
            f"{held:.2f} N level with zero torque (yaw included), the vehicle weighs "
            f"{weight:.2f} N (thrust/weight {full / weight:.2f} with every rotor)")


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    robot = load_robot(robot)
    why = refusal(robot, settings)
    if why:
        raise ScenarioRefused(why)
    rig = rig_from_settings(settings, seed, robot=robot)
    k, eff = int(settings["rotor"]), float(settings["efficiency"])
    events = [(settings["fault_time"], RotorFault(k, eff))]
    log = rig.run(DURATION if duration is None else duration, hold(rig), events=events)
    add_derived(log)
    dev = np.linalg.norm(log["base_pos"] - log["pos_ref"], axis=1)
    after = log["t"] >= settings["fault_time"]
    reason = diverged(log)
    z = log["base_pos"][:, 2]
    metrics = {
        "max_hover_deviation_m": float(dev.max()),
        "deviation_last_1s_m": float(dev[log["t"] >= log["t"][-1] - 1.0].max()),
        "min_altitude_m": float(z.min()),
        "airborne": float(not reason and z.min() > rig.hover_pos[2] - 0.5),
        "max_thrust_cmd_N": float(log["thrust_cmd"][after].max()) if after.any() else 0.0,
        "saturated_ticks": int(np.sum(log["rotors_saturated"] > 0)),
    }
    result = ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))
    result.settings["divergence"] = reason
    return result


def plot_signals():
    return AERIAL_PLOT
