"""aerial-arm-sweep: hover while the arm's main joint sweeps through most of its range, the same
run with the reaction feed-forward on and off. Any arm (derive()): the swept joint is the one that
moves the arm's centre of mass the most sideways from the start pose (the aerial manipulator's
shoulder), the amplitude 1.5 rad or 90 % of the room its limits leave, whichever is smaller; the
next joint (if any) counter-swings by elbow_ratio. Reports the attitude error peak-to-peak
for both and the reduction the feed-forward brings (goal >= 60 %). The log is the feed-forward on
run's, with the off run's signals beside it under "_no_ff" (the plot shows both).

Both runs differ only in the reaction feed-forward: everything else, the position loop's target
included (hold_com: the vehicle's centre of mass, the default; or the body origin), is the same.

Attitude error: the body's attitude against the one the controller commands (the attitude loop's
error; the rotation vector, largest peak-to-peak over the three axes), averaged over 50 ms to
take out the IMU noise (whose own peak-to-peak, ~1.5 deg at hover, would otherwise dominate the
feed-forward case). The raw figure and its reduction, the body's tilt from level and the
excursion of the vehicle's centre of mass are reported beside it.
Measured (bench/RESULTS.md), period 4 s, reaction lead derived (30 ms): CoM held in both runs,
0.26 deg vs 3.41 deg (92 %); body origin held in both (`--set hold_com=false`), 1.75 deg vs
4.39 deg (60 %: the arm's lateral push moves the body and the position loop tilts it back).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil.aerial_signals import CONTROL_DT, REFERENCE_WIDTH, reference_row
from ..sil.timing import whole_periods
from .aerial_settings import COMMON_DEFAULTS, rig_from_settings
from .aerial_metrics import add_derived, diverged, rotation_vector_error
from ..errors import InputError, ScenarioRefused
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import AERIAL_ARM_SWEEP_PLOT

NAME = "aerial-arm-sweep"
DESCRIPTION = "hover while the arm sweeps; attitude error p-p with vs without reaction FF"
DURATION = 5.0
DEFAULTS = dict(COMMON_DEFAULTS, amplitude=1.5, elbow_ratio=0.0, period=4.0, start=0.5, cycles=1,
                sweep_joint=1)
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"period": (">", 0.0), "cycles": (">=", 1), "start": (">=", 0.0)}
MAX_AMPLITUDE = 1.5  # [rad]
LIMIT_SHARE = 0.9    # of the room between the start pose and the nearer limit


def min_duration(settings) -> float:
    """[s] the attitude error is judged from the sweep's start on."""
    return float(settings["start"]) + JUDGED_WINDOW


def derive(robot) -> dict:
    """The swept joint and its amplitude, from the arm's chain and limits (see the docstring)."""
    import kiloloop as kl

    from ..robot import aerial as aerial_robot

    model = aerial_robot.model(robot)
    if not robot.section("vehicle").get("ee") or model.nq == 0:
        raise ScenarioRefused(f"{robot.name}: {NAME} sweeps an arm; {robot.name} has none")
    # The plant's start pose, chain order ([sim.joints] q0, else zero).
    q0 = robot.sim.get("joints", {}).get("q0")
    q = np.zeros(model.nq) if q0 is None else np.asarray(q0, dtype=float)
    rne = kl.FloatingBaseRne(model)
    best, best_j = -1.0, 0
    for j in range(model.nq):
        dq = np.zeros(model.nq)
        dq[j] = 0.1
        moved = np.asarray(rne.first_moment(q + dq)[0]) - np.asarray(rne.first_moment(q)[0])
        if np.linalg.norm(moved[:2]) > best + 1e-12:
            best, best_j = float(np.linalg.norm(moved[:2])), j
    lo, up = np.asarray(model.lower, float)[best_j], np.asarray(model.upper, float)[best_j]
    room = min(q[best_j] - lo, up - q[best_j])
    return {"sweep_joint": best_j,
            "amplitude": float(min(MAX_AMPLITUDE, LIMIT_SHARE * room))}
CRITERIA = {"attitude_ptp_reduction": (">=", 0.60), "diverged_ff": ("<", 0.5),
            "diverged_no_ff": ("<", 0.5)}
SMOOTH = 0.05  # [s] moving average before the peak-to-peak
OFF_SUFFIX = "_no_ff"  # the feed-forward off run's signals in the returned log


def sweep_trajectory(settings, nq: int, q0=None) -> "kl.QuinticTrajectory":
    """Swept joint q0 +-amplitude, the next one -+elbow_ratio * amplitude, quintic between the
    extremes every half period, starting and ending at rest at q0."""
    a, half = settings["amplitude"], settings["period"] / 2
    j = int(settings["sweep_joint"])
    if not 0 <= j < nq:
        raise InputError(f"sweep_joint: expected 0..{nq - 1} (the arm has {nq} joints), got {j}")
    q0 = np.zeros(nq) if q0 is None else np.asarray(q0, float)
    n = 2 * int(settings["cycles"])
    points = [q0.copy()]
    for k in range(n):
        sign = 1.0 if k % 2 == 0 else -1.0
        p = q0.copy()
        p[j] += sign * a
        if j + 1 < nq:
            p[j + 1] -= sign * a * settings["elbow_ratio"]
        points.append(p)
    points.append(q0.copy())
    times = settings["start"] + half * np.concatenate([[0.0], 0.5 + np.arange(n), [n]])
    return kl.QuinticTrajectory(np.array(points), times)


def _one(settings, feedforward, seed, duration, robot):
    s = dict(settings, feedforward=feedforward)
    rig = rig_from_settings(s, seed, robot=robot)
    hover = rig.hover_pos.copy()
    if rig.controller.nq == 0:
        raise ScenarioRefused(f"{rig.robot.name}: {NAME} sweeps an arm; it has none")
    traj = sweep_trajectory(settings, rig.controller.nq, rig.plant.q0[rig.to_ctrl])

    def command(t, inp):
        inp.position_ref[:] = hover
        traj.sample_into(t, inp.q_ref, inp.qd_ref, inp.qdd_ref)

    def table(controller, ticks):
        """The same references as data: the hover row, the trajectory sampled into its arm columns."""
        inp = controller.make_input()
        command(0.0, inp)
        rows = np.tile(reference_row(inp, controller.nq), (ticks, 1))
        nq, arm = controller.nq, REFERENCE_WIDTH
        for k in range(ticks):
            row = rows[k]
            traj.sample_into(k * CONTROL_DT, row[arm:arm + nq], row[arm + nq:arm + 2 * nq],
                             row[arm + 2 * nq:])
        return rows

    command.table = table
    log = rig.run(duration, command)
    add_derived(log)
    level = np.tile([1.0, 0.0, 0.0, 0.0], (len(log["t"]), 1))
    tilt = np.degrees(rotation_vector_error(log["base_quat"], level))
    log.put("att_level_deg", tilt)
    after = log["t"] >= settings["start"]
    err = log["att_err_deg"][after]
    n = max(1, whole_periods(SMOOTH, CONTROL_DT))
    kernel = np.ones(n) / n
    smooth = np.stack([np.convolve(err[:, i], kernel, mode="valid") for i in range(3)], axis=1)
    pos_err = np.linalg.norm(log["base_pos"] - log["pos_ref"], axis=1)
    return {"ptp": float(np.max(np.ptp(smooth, axis=0))),
            "ptp_raw": float(np.max(np.ptp(err, axis=0))),
            "tilt_ptp": float(np.max(np.ptp(tilt[after], axis=0))),
            "pos": float(pos_err[after].max()),
            "com": float(np.linalg.norm(log["com"] - log["com"][0], axis=1).max()),
            "why": diverged(log)}, log


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    if duration is None:
        duration = max(DURATION, settings["start"] + settings["period"] * settings["cycles"] + 0.5)
    on, log = _one(settings, True, seed, duration, robot)
    off, log_off = _one(settings, False, seed, duration, robot)
    keep_both(log, log_off, OFF_SUFFIX)
    metrics = {
        "attitude_ptp_deg_ff": on["ptp"],
        "attitude_ptp_deg_no_ff": off["ptp"],
        "attitude_ptp_reduction": 1.0 - on["ptp"] / off["ptp"] if off["ptp"] > 0 else float("nan"),
        "attitude_ptp_raw_deg_ff": on["ptp_raw"],
        "attitude_ptp_raw_deg_no_ff": off["ptp_raw"],
        "attitude_ptp_raw_reduction": (1.0 - on["ptp_raw"] / off["ptp_raw"] if off["ptp_raw"] > 0
                                       else float("nan")),
        "tilt_ptp_deg_ff": on["tilt_ptp"],
        "tilt_ptp_deg_no_ff": off["tilt_ptp"],
        "max_position_error_m_ff": on["pos"],
        "max_position_error_m_no_ff": off["pos"],
        # The CoM's largest excursion from where it started: with hold_com (default) the body
        # gives way to the arm (its position error above) so that this stays small.
        "max_com_deviation_m_ff": on["com"],
        "max_com_deviation_m_no_ff": off["com"],
        "diverged_ff": float(bool(on["why"])),
        "diverged_no_ff": float(bool(off["why"])),
    }
    result = ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))
    result.settings["divergence"] = "; ".join(
        f"{tag}: {r['why']}" for tag, r in (("ff", on), ("no ff", off)) if r["why"])
    return result


def keep_both(log, other, suffix: str) -> None:
    """Adds the other run's per-tick signals to `log` under name + suffix, so that one log (and
    its plot) holds both runs; a run that stopped early is padded with NaN to log's length."""
    ticks = len(log["t"])
    for name in other.names():
        series = other[name]
        if name == "t" or len(series) != len(other["t"]):
            continue  # time is shared; event records (diverged) are not per tick
        padded = np.full((ticks,) + series.shape[1:], np.nan)
        n = min(ticks, len(series))
        padded[:n] = series[:n]
        log.put_array(name + suffix, padded)


def plot_signals():
    """Both runs, feed-forward on and off, on shared scales (scenarios/plots.py)."""
    return AERIAL_ARM_SWEEP_PLOT
