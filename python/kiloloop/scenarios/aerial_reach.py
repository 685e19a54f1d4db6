"""aerial-reach: while hovering, the end effector follows a straight Cartesian line in the world
(quintic time scaling, orientation slerped between the start and end orientations) through the
controller's end-effector mode (damped IK on the measured body pose + computed torque). The 3-DoF
arm controls the end-effector position only: the orientation error against the slerp is reported,
not judged."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..errors import ScenarioRefused
from ..sil.aerial_signals import CONTROL_DT, reference_row
from .aerial_settings import COMMON_DEFAULTS, rig_from_settings
from .aerial_metrics import add_derived, diverged
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import AERIAL_PLOT

NAME = "aerial-reach"
DESCRIPTION = "end effector tracks a straight line (quintic, slerp orientation) while hovering"
DURATION = 4.5
# The arm starts bent forward (hanging straight down it is singular for position IK: stretched,
# and on the yaw axis). The body holds its own position (hold_com off): with the centre of mass
# held instead, the body gives way to the arm by up to 2.6 cm and the end-effector error grows
# from 1.1 to 8.3 mm (measured).
DEFAULTS = dict(COMMON_DEFAULTS, hold_com=False, q_start=[0.0, -0.8, 0.6],
                displacement=[-0.05, 0.12, 0.08], t_start=0.5, t_move=3.0)
CRITERIA = {"max_ee_error_m": ("<", 0.01), "diverged": ("<", 0.5)}
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"t_start": (">=", 0.0), "t_move": (">", 0.0)}
SIZES = {"q_start": "nq", "displacement": 3}  # [rad] per arm joint; [m] x, y, z


def derive(robot) -> dict:
    """Nothing to size; refuses an arm of fewer than 3 joints at start (the IK places the end
    effector's position: 3 coordinates)."""
    from ..robot import aerial as aerial_robot

    nq = aerial_robot.model(robot).nq if robot.section("vehicle").get("ee") else 0
    if nq < 3:
        raise ScenarioRefused(f"{robot.name}: {NAME} places the end effector's position (3 "
                              f"coordinates) with the arm's joints: it needs 3, the arm has {nq}")
    return {}


def min_duration(settings) -> float:
    """[s] the errors are judged from the reach's start on."""
    return float(settings["t_start"]) + JUDGED_WINDOW


def _quintic(s):
    """Rest-to-rest time scaling on [0, 1]: value, first and second derivative. Products and sums
    only (Horner), no powers: numpy's array power takes a SIMD path (AVX-512 here) that rounds
    differently from the scalar one, and the scenario samples this on the tick grid at once
    (command.table) where the generic sampler calls it one tick at a time: measured, s**3 on an
    array differed from the scalar in 11,043 of 200,001 points (1 ulp), and the two reference
    tables in 68 of 37,200 entries. Multiplication and addition round the same either way."""
    s = np.clip(s, 0.0, 1.0)
    s2 = s * s
    return (s2 * s * (10.0 + s * (-15.0 + 6.0 * s)), s2 * (30.0 + s * (-60.0 + 30.0 * s)),
            s * (60.0 + s * (-180.0 + 120.0 * s)))


def _slerp(q0, q1, u):
    dot = float(np.dot(q0, q1))
    if dot < 0:
        q1, dot = -q1, -dot
    if dot > 0.9995:
        q = q0 + u * (q1 - q0)
        return q / np.linalg.norm(q)
    theta = np.arccos(dot)
    return (np.sin((1 - u) * theta) * q0 + np.sin(u * theta) * q1) / np.sin(theta)


def _mat_to_quat(R):
    w = np.sqrt(max(1e-12, 1 + np.trace(R))) / 2
    return np.array([w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w),
                     (R[1, 0] - R[0, 1]) / (4 * w)])


class CartesianLine:
    """p(t) = p0 + s(t) (p1 - p0), orientation slerp(q0, q1, s(t)); s quintic over [t0, t0 + T]."""

    def __init__(self, p0, p1, q0, q1, t0, T):
        self.p0, self.p1 = np.asarray(p0, float), np.asarray(p1, float)
        self.q0, self.q1 = np.asarray(q0, float), np.asarray(q1, float)
        self.t0, self.T = float(t0), float(T)

    def sample(self, t):
        s, ds, _ = _quintic((t - self.t0) / self.T)
        d = self.p1 - self.p0
        return self.p0 + s * d, ds / self.T * d, _slerp(self.q0, self.q1, s)


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    rig = rig_from_settings(settings, seed, robot=robot)
    if rig.controller.nq < 3:  # derive() refuses such a robot before this when run by name
        raise ScenarioRefused(f"{rig.robot.name}: {NAME} places the end effector's position (3 "
                              f"coordinates) with the arm's joints; its arm has "
                              f"{rig.controller.nq}")
    rig.plant.reset(q=np.asarray(settings["q_start"], float)[np.argsort(rig.to_ctrl)])
    hover = rig.hover_pos.copy()
    p0, R0 = rig.plant.ee_pose()
    p1 = p0 + np.asarray(settings["displacement"], float)
    # Orientation: slerp from the start orientation to the one the arm ends with (a 3-DoF arm
    # sets its end-effector orientation with its position, so the goal is what it reaches; the
    # deviation from the slerp on the way is reported, not judged).
    line = CartesianLine(p0, p1, _mat_to_quat(R0), _mat_to_quat(R0), settings["t_start"],
                         settings["t_move"])

    def command(t, inp):
        inp.position_ref[:] = hover
        inp.arm_mode = kl.ArmMode.END_EFFECTOR
        p, v, _ = line.sample(t)
        inp.ee_position_ref[:] = p
        inp.ee_velocity_ref[:] = v

    def table(controller, ticks):
        """The same references as data: the line sampled on the tick grid at once."""
        inp = controller.make_input()
        command(0.0, inp)
        rows = np.tile(reference_row(inp, controller.nq), (ticks, 1))
        t = np.arange(ticks) * CONTROL_DT
        s, ds, _ = _quintic((t - line.t0) / line.T)
        d = line.p1 - line.p0
        rows[:, 16:19] = line.p0 + s[:, None] * d      # ee_position_ref (AerialAdapter::Ref)
        rows[:, 19:22] = (ds / line.T)[:, None] * d    # ee_velocity_ref
        return rows

    command.table = table
    log = rig.run(DURATION if duration is None else duration, command)
    add_derived(log)
    ref = np.array([line.sample(t)[0] for t in log["t"]])
    log.put("ee_ref", ref)
    err = np.linalg.norm(log["ee_pos"] - ref, axis=1)
    log.put("ee_err_mm", err * 1e3)
    start = log["t"] >= settings["t_start"]
    pos_err = np.linalg.norm(log["base_pos"] - log["pos_ref"], axis=1)
    q_ee = np.array([_mat_to_quat(R) for R in log["ee_rot"]])
    line.q1 = q_ee[-1]
    q_ref = np.array([line.sample(t)[2] for t in log["t"]])
    orient_err = 2 * np.arccos(np.clip(np.abs(np.sum(q_ref * q_ee, axis=1)), 0.0, 1.0))
    reason = diverged(log)
    metrics = {
        "max_ee_error_m": float(err[start].max()),
        "rms_ee_error_m": float(np.sqrt(np.mean(err[start] ** 2))),
        "max_body_position_error_m": float(pos_err[start].max()),
        # Not judged: a 3-DoF arm cannot hold an orientation independently of its position.
        "max_ee_orientation_dev_from_slerp_deg": float(np.degrees(orient_err[start].max())),
        "unreachable_ticks": int(np.sum(log["status"] == int(kl.Status.UNREACHABLE))),
        "diverged": float(bool(reason)),
    }
    result = ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))
    result.settings["divergence"] = reason
    return result


def plot_signals():
    return [("end effector (world)", "ee_pos", "ee_ref", "m"),
            ("end-effector error", "ee_err_mm", None, "mm")] + AERIAL_PLOT[:2]
