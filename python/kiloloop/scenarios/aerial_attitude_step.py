"""aerial-attitude-step: a 10 deg roll step in attitude mode (the collective thrust keeps the
altitude), for both attitude laws (quaternion PD and Lee's SO(3)) unless `--set law=...` picks
one. Roll is measured on the simulator's true attitude; noise on."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil.aerial_signals import CONTROL_DT, reference_row
from .aerial_settings import COMMON_DEFAULTS, LAWS, rig_from_settings
from .aerial_metrics import add_derived, diverged
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import AERIAL_PLOT

NAME = "aerial-attitude-step"
DESCRIPTION = "10 deg roll step, both attitude laws: overshoot and steady-state error"
DURATION = 2.5
DEFAULTS = dict(COMMON_DEFAULTS, law="both", step_deg=10.0, step_time=0.5)
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"step_time": (">=", 0.0)}
STEADY_WINDOW = 0.5  # [s] at the end, for the steady-state error


def min_duration(settings) -> float:
    """[s] the steady-state window must lie after the step."""
    return float(settings["step_time"]) + STEADY_WINDOW


def _criteria(laws):
    out = {}
    for law in laws:
        out[f"overshoot_{law}"] = ("<", 0.15)
        out[f"steady_state_error_rad_{law}"] = ("<", 0.01)
    return out


CRITERIA = _criteria(LAWS)


def roll_of(quat):
    w, x, y, z = quat.T
    return np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))


def _one(settings, law, seed, duration, robot):
    s = dict(settings, law=law)
    rig = rig_from_settings(s, seed, robot=robot)
    q0 = rig.plant.q0.copy()[rig.to_ctrl]
    hover = rig.hover_pos.copy()
    step = np.radians(settings["step_deg"])
    q_step = np.array([np.cos(step / 2), np.sin(step / 2), 0.0, 0.0])
    t_step = settings["step_time"]

    def command(t, inp):
        inp.position_ref[:] = hover
        inp.flight_mode = kl.FlightMode.ATTITUDE
        inp.quat_ref[:] = q_step if t >= t_step else (1.0, 0.0, 0.0, 0.0)
        inp.q_ref[:] = q0

    def table(controller, ticks):
        """The same references as data: the level row before the step, the stepped one after."""
        inp = controller.make_input()
        command(0.0, inp)
        before = reference_row(inp, controller.nq)
        command(t_step, inp)
        after = reference_row(inp, controller.nq)
        t = np.arange(ticks) * CONTROL_DT  # k * dt, as the loops count time
        return np.where((t >= t_step)[:, None], after, before)

    command.table = table
    log = rig.run(duration, command)
    add_derived(log)
    t, roll = log["t"], roll_of(log["base_quat"])
    after = t >= t_step
    end = t >= t[-1] - STEADY_WINDOW
    peak = float(np.max(roll[after])) if after.any() else float("nan")
    rise = t[after][np.argmax(roll[after] >= 0.9 * step)] - t_step if np.any(
        roll[after] >= 0.9 * step) else float("nan")
    metrics = {
        f"overshoot_{law}": max(0.0, (peak - step) / step),
        f"steady_state_error_rad_{law}": float(abs(np.mean(roll[end]) - step)),
        f"rise_time_s_{law}": float(rise),
        f"diverged_{law}": float(bool(diverged(log))),
    }
    metrics_reason = diverged(log)
    log.put("roll_deg", np.degrees(roll))
    return metrics, log, metrics_reason


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    duration = DURATION if duration is None else duration
    laws = list(LAWS) if settings["law"] == "both" else [settings["law"]]
    metrics, log, reasons = {}, None, []
    for law in laws:
        m, law_log, why = _one(settings, law, seed, duration, robot)
        metrics.update(m)
        log = law_log if log is None else log
        if why:
            reasons.append(f"{law}: {why}")
    result = ScenarioResult(NAME, metrics, evaluate(_criteria(laws), metrics), log, dict(settings))
    result.settings["divergence"] = "; ".join(reasons)
    return result


def plot_signals():
    return [("roll", "roll_deg", None, "deg")] + AERIAL_PLOT
