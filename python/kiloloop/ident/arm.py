"""Identification of an arm from excitation logs, against its robot file as the nominal model.

Per tick k of a log (measured q, qd, commanded tau, 1 kHz), with the acceleration a_k = (qd_k+1 -
qd_k) / dt (a forward difference: the non-causal filter that is exact for a semi-implicit step,
where the damping acts on the step's end velocity qd_k+1; MuJoCo's implicitfast):

    applied_j(tau, delay, lag)_k - ID_nominal(q_k, qd_k, a_k)_j
        = armature_j a_kj + damping_j qd_k+1,j + coulomb_j sign(qd_k+1,j) + Y_j(q_k, qd_k, a_k) pi

ID_nominal: the rigid-body inverse dynamics of the nominal file's URDF (no joint damping,
friction or armature; MuJoCo's mj_inverse); Y pi: a payload rigidly on the chain's last link, its
ten inertial parameters (regressors.py). On a noisy log q, qd and the applied torque pass the
same zero-phase filter first (SMOOTHING, NOISE_FLOOR: the noise would otherwise swamp the
differentiated qd). Rows where a joint moves slowly (|qd| under SPEED_FRACTION of its peak speed
in that log, or under MIN_SPEED, at either end of the step) leave that joint's equation out: friction is not Coulomb's there, neither a real drive's (Stribeck, stiction) nor
MuJoCo's frictionloss, a soft constraint whose force grows with the speed up to the friction
(measured on the UR5's wrist, 3 N m of friction behind 0.025 kg m^2: 2.7 N m on average between
0.05 and 0.1 rad/s, 2.9 N m up to 0.2 rad/s, exactly 3 N m above).
The actuation delay (whole ticks) and lag minimise the residual (fit.py); then the bounded fit
gives the parameters (frictions, armatures and the payload mass >= 0); what the logs cannot tell
apart keeps the nominal file's value and is named.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..sil.arm_family import build_plant
from ..sil.log import SignalLog
from .fit import LinearModel
from .motor import applied
from .regressors import N_INERTIAL, PARAMETER_NAMES, BodyRegressor, split_parameters

DT = 0.001            # [s] the logs' tick (checked against their t)
MIN_SPEED = 0.05      # [rad/s] below it a joint's equation is left out (friction is set-valued)
SPEED_FRACTION = 0.3  # of a joint's peak speed in the log: slower rows are left out too
STRIDE = 4            # ticks between the rows used (consecutive ticks add little information)
SKIP = 0.2            # [s] left out at a log's start (the controller's first transient)
MAX_DELAY = 0.08      # [s] searched
MAX_LAG = 0.05        # [s] searched
# [s] half-widths of the zero-phase filter tried on a noisy log (arm.zero_phase). Measured on
# the UR5 (30 s, friction x2, armature x0.5, payload; encoder noise of 2e-3 rad/s and 1e-5
# rad): no filter gives armatures of 0 to 20 times the truth (21 ms of delay); 10 ms every
# parameter within 4 % at 21 ms, but at 33 ms (the loop rings) the elbow's Coulomb friction 6 %
# and wrist 3's armature 65 % off, 5 ms 1.4 % and 18 %: the equation holds between filtered
# signals only where q and the sign of qd hold across the window. On a noise-free log any
# filter costs (0.2 % at 15 ms, up to 93 % at 28-33 ms); whether a log is noisy is told by the
# fits themselves (a noise level estimated from qd's third difference mistook that ringing,
# 1.3e-4 rad/s, for noise), and the one that explains most of the torque is kept.
SMOOTHING = (0.0025, 0.005, 0.01)
# Residual RMS over the target's RMS under which the unfiltered fit is taken as it is (a
# noise-free log of a plant the model describes: 1e-13 and less).
EXACT_FIT = 1e-6
# A payload lighter than this share of the last link's mass, or not significant (under
# SIGNIFICANCE standard errors), is reported as none.
MIN_PAYLOAD_FRACTION = 0.01
SIGNIFICANCE = 3.0
_NAMES = ("armature", "damping", "frictionloss")


@dataclass
class ArmIdentification:
    joint_names: list
    armature: np.ndarray          # [kg m^2]
    damping: np.ndarray           # [N m s/rad]
    frictionloss: np.ndarray      # [N m]
    stderr: dict                  # name -> (nq,) or scalar standard errors
    payload_mass: float           # [kg] (0: none found)
    payload_com: np.ndarray       # [m] in the last link's frame
    payload_inertia: np.ndarray | None  # [kg m^2] about its CoM; None: not positive definite
    payload_link: str
    delay: float                  # [s]
    delay_ticks: int
    lag: float                    # [s]
    residual_rms: float           # [N m] of the fit
    relative_residual: float      # residual_rms over the target's RMS
    residual_by_delay: np.ndarray = field(repr=False, default=None)
    rows: int = 0                 # equations used
    trimmed: int = 0              # equations left out as outliers (fit.py)
    unidentified: list = field(default_factory=list)  # held at the nominal value (fit.py)
    smoothing: float = 0.0        # [s] the zero-phase filter's half-width used

    def as_dict(self) -> dict:
        def lst(x):  # JSON has no infinity: an unidentified parameter's error is null
            if x is None:
                return None
            a = np.asarray(x, float)
            if a.ndim == 0:
                return float(a) if np.isfinite(a) else None
            return [lst(v) for v in a]
        return {"joints": self.joint_names, "armature": lst(self.armature),
                "damping": lst(self.damping), "frictionloss": lst(self.frictionloss),
                "payload": {"link": self.payload_link, "mass": self.payload_mass,
                            "com": lst(self.payload_com), "inertia": lst(self.payload_inertia)},
                "delay": self.delay, "delay_ticks": self.delay_ticks, "lag": self.lag,
                "stderr": {k: lst(v) for k, v in self.stderr.items()},
                "residual_rms": self.residual_rms, "rows": self.rows,
                "trimmed": self.trimmed, "unidentified": self.unidentified,
                "smoothing": self.smoothing}


def zero_phase(x: np.ndarray, half_width: int) -> np.ndarray:
    """x (N, ...) through a centred moving average of 2 half_width + 1 ticks, twice (a
    triangular kernel: no phase, -40 dB per decade); the ends use what the window holds."""
    if half_width <= 0:
        return np.asarray(x, float)
    out = np.asarray(x, float)
    n = len(out)
    for _ in range(2):
        c = np.concatenate([np.zeros((1,) + out.shape[1:]), np.cumsum(out, axis=0)])
        lo = np.clip(np.arange(n) - half_width, 0, n)
        hi = np.clip(np.arange(n) + half_width + 1, 0, n)
        width = (hi - lo).reshape((-1,) + (1,) * (out.ndim - 1))
        out = (c[hi] - c[lo]) / width
    return out


def _rows(plant, regressor, log: SignalLog, smoothing: int = 0):
    """The regressor's per-tick pieces of one log: tick indices, accelerations, end velocities,
    nominal inverse dynamics, payload regressors."""
    for name in ("t", "q", "qd", "tau"):
        if name not in log:
            raise InputError(f"identify: the log has no {name!r} signal (an arm's log needs t, "
                             "q, qd, tau)")
    t, q, qd, tau = (np.asarray(log[n], float) for n in ("t", "q", "qd", "tau"))
    if q.shape[1] != plant.nq or tau.shape[1] != plant.nq:
        raise InputError(f"identify: the log has {q.shape[1]} joints, the robot {plant.nq}")
    steps = np.diff(t)
    if len(t) < 100 or np.max(np.abs(steps - DT)) > 1e-6:
        raise InputError(f"identify: the log must be sampled every {DT} s (at least 100 ticks)")
    # Smoothing (noisy encoders): the same zero-phase filter on the velocities and, in the
    # target, on the applied torque (linear: the equation holds between the filtered signals
    # where M(q) and the sign of qd hold across the window).
    raw = qd
    q, qd = zero_phase(q, smoothing), zero_phase(qd, smoothing)
    k = np.arange(int(round(SKIP / DT)), len(t) - 1, STRIDE)
    acc = (qd[k + 1] - qd[k]) / DT
    v_end = qd[k + 1]
    slowest = np.maximum(MIN_SPEED, SPEED_FRACTION * np.max(np.abs(qd), axis=0))
    moving = (np.abs(qd[k]) > slowest) & (np.abs(v_end) > slowest) & (
        np.sign(qd[k]) == np.sign(v_end))
    if smoothing:  # and over the filter's whole support (2 half-widths each side)
        reach = 2 * smoothing
        padded = np.pad(raw, ((reach, reach + 1), (0, 0)), mode="edge")
        window = np.lib.stride_tricks.sliding_window_view(padded, 2 * reach + 2, axis=0)[k]
        same_sign = np.all(np.sign(window) == np.sign(v_end)[:, :, None], axis=2)
        moving &= same_sign & (np.min(np.abs(window), axis=2) > 0.5 * slowest)
    inv = np.array([plant.inverse_dynamics(q[i], qd[i], a) for i, a in zip(k, acc)])
    Y = np.array([regressor(q[i], qd[i], a) for i, a in zip(k, acc)])
    return k, acc, v_end, moving, inv, Y, tau


def identify_arm(robot, logs: list[SignalLog], *, payload: bool = True,
                 smoothing: float | None = None) -> ArmIdentification:
    """Estimates from `logs` what `robot` (the nominal file) should say; see the module doc.
    smoothing [s]: the half-width of the zero-phase filter on q, qd and the torque (0: none;
    None: the fit without it, and where that leaves more than EXACT_FIT of the torque
    unexplained, those with each of SMOOTHING too: whichever explains most)."""
    for log in logs:
        if "qd" not in log:
            raise InputError("identify: the log has no 'qd' signal (an arm's log needs t, q, "
                             "qd, tau)")
    if smoothing is not None:
        return _identify_arm(robot, logs, payload, int(round(smoothing / DT)))
    best = _identify_arm(robot, logs, payload, 0)
    if best.relative_residual < EXACT_FIT:
        return best
    for width in SMOOTHING:
        fit = _identify_arm(robot, logs, payload, int(round(width / DT)))
        if fit.relative_residual < best.relative_residual:
            best = fit
    return best


def _identify_arm(robot, logs, payload: bool, half: int) -> ArmIdentification:
    """identify_arm with a zero-phase filter of half-width `half` ticks (0: none)."""
    # The nominal rigid body: the file's URDF, no joint damping, friction or armature.
    plant = build_plant(robot, damping=0.0, frictionloss=0.0, armature=0.0)
    m, nq = plant.model, plant.nq
    last = int(m.jnt_bodyid[m.joint(plant.joint_names[-1]).id])
    regressor = BodyRegressor(m, last, plant.qpos_addresses, plant.dof_addresses)
    pieces = [_rows(plant, regressor, log, half) for log in logs]
    effort = np.asarray(robot.model().effort_limit, float)  # the drives saturate there

    # Phi: one row per (tick, joint) where the joint moves; columns armature (nq), damping (nq),
    # Coulomb (nq), payload (10).
    n_theta = 3 * nq + (N_INERTIAL if payload else 0)
    blocks, selectors, groups = [], [], []
    for k, acc, v_end, moving, inv, Y, tau in pieces:
        rows = np.zeros((len(k), nq, n_theta))
        j = np.arange(nq)
        rows[:, j, j] = acc
        rows[:, j, nq + j] = v_end
        rows[:, j, 2 * nq + j] = np.sign(v_end)
        if payload:
            rows[:, :, 3 * nq:] = Y
        blocks.append(rows[moving])
        selectors.append(moving)
        groups.append(np.broadcast_to(j, moving.shape)[moving])
    phi = np.concatenate(blocks)
    if len(phi) < 10 * n_theta:
        raise InputError(f"identify: only {len(phi)} usable samples (joints moving faster "
                         f"than {MIN_SPEED} rad/s); excite longer or faster")

    def target(delay_ticks: int, lag: float) -> np.ndarray:
        out = []
        for (k, acc, v_end, moving, inv, Y, tau), sel in zip(pieces, selectors):
            u = zero_phase(applied(tau, delay_ticks, lag, DT, effort), half)[k]
            out.append((u - inv)[sel])
        return np.concatenate(out)

    lower = np.concatenate([np.zeros(3 * nq), [0.0] if payload else [],
                            np.full(N_INERTIAL - 1 if payload else 0, -np.inf)])
    # What the logs cannot tell apart stays at the nominal file's value (its [sim.joints]; no
    # payload).
    nominal = build_plant(robot).model
    dofs = plant.dof_addresses
    prior = np.concatenate([nominal.dof_armature[dofs], nominal.dof_damping[dofs],
                            nominal.dof_frictionloss[dofs], np.zeros(n_theta - 3 * nq)])
    model = LinearModel(phi, target, lower, np.concatenate(groups), prior)
    sol = model.identify(int(round(MAX_DELAY / DT)), MAX_LAG)
    d, lag, by_delay = sol.delay_ticks, sol.lag, sol.delay_residuals
    th, se = sol.theta, sol.stderr

    pm, com, inertia = 0.0, np.zeros(3), None
    link_mass = float(m.body_mass[last])
    if payload and model.identifiable[3 * nq]:
        pi = th[3 * nq:]
        if pi[0] > MIN_PAYLOAD_FRACTION * link_mass and pi[0] > SIGNIFICANCE * se[3 * nq]:
            pm, com, inertia = split_parameters(pi)
            # The inertia is reported only where it is one (positive definite about the CoM).
            if not np.all(np.linalg.eigvalsh(inertia) > 0):
                inertia = None
    stderr = {"armature": se[:nq], "damping": se[nq:2 * nq], "frictionloss": se[2 * nq:3 * nq]}
    if payload:
        stderr["payload_mass"] = float(se[3 * nq])
        stderr["payload_first_moment"] = se[3 * nq + 1:3 * nq + 4]
    return ArmIdentification(
        joint_names=list(plant.joint_names), armature=th[:nq], damping=th[nq:2 * nq],
        frictionloss=th[2 * nq:3 * nq], stderr=stderr, payload_mass=float(pm),
        payload_com=com, payload_inertia=inertia, payload_link=m.body(last).name,
        delay=d * DT, delay_ticks=d, lag=lag, residual_rms=sol.residual_rms,
        relative_residual=sol.residual_rms / max(sol.target_rms, 1e-300),
        residual_by_delay=by_delay, rows=len(phi) - sol.trimmed, trimmed=sol.trimmed,
        smoothing=half * DT,
        unidentified=[_NAMES[i // nq] + (f"[{i % nq}]" if i < 3 * nq else "")
                      if i < 3 * nq else f"payload {PARAMETER_NAMES[i - 3 * nq]}"
                      for i in np.nonzero(~model.identifiable)[0]])


def patch_data(robot, ident: ArmIdentification, out_path) -> dict:
    """The robot file's tables with the identification in them (patch.py); a payload goes into
    a copy of the URDF beside out_path (payload_urdf.py)."""
    from pathlib import Path

    from .patch import robot_data, set_delay, set_joints
    from .payload_urdf import write_with_payload

    out_path = Path(out_path)
    data = robot_data(robot, out_path)
    set_joints(data, ident.damping, ident.frictionloss, ident.armature)
    set_delay(data, "arm", ident.delay)
    if ident.payload_mass > 0:
        urdf = out_path.with_suffix(".urdf")
        write_with_payload(robot.urdf, urdf, ident.payload_link, ident.payload_mass,
                           ident.payload_com, ident.payload_inertia)
        data["urdf"] = urdf.name
    return data


def summary(ident: ArmIdentification) -> list[str]:
    """Lines for people (and the patch's header): each estimate with its standard error."""
    def row(name, values, errors, unit):
        return (f"{name:<13}" + " ".join(f"{v:9.4g}" for v in values) + f"  [{unit}]  +- "
                + " ".join(f"{e:.2g}" for e in errors))
    se = ident.stderr
    lines = ["joints       " + " ".join(f"{n[:9]:>9}" for n in ident.joint_names),
             row("damping", ident.damping, se["damping"], "N m s/rad"),
             row("frictionloss", ident.frictionloss, se["frictionloss"], "N m"),
             row("armature", ident.armature, se["armature"], "kg m^2")]
    if ident.payload_mass > 0:
        c = ident.payload_com
        lines.append(f"payload      {ident.payload_mass:.4g} kg +- {se['payload_mass']:.2g} on "
                     f"{ident.payload_link}, CoM [{c[0]:.4g}, {c[1]:.4g}, {c[2]:.4g}] m, inertia "
                     + ("positive definite" if ident.payload_inertia is not None
                        else "not positive definite: a point mass"))
    else:
        lines.append("payload      none found")
    lines.append(f"delay        {ident.delay * 1e3:.0f} ms ({ident.delay_ticks} ticks), lag "
                 f"{ident.lag * 1e3:.2f} ms (not written: an arm's file has no key for it)")
    if ident.unidentified:
        lines.append("not identifiable from these logs (the nominal value kept): "
                     + ", ".join(ident.unidentified))
    lines.append(f"residual     {ident.residual_rms:.3g} N m RMS over {ident.rows} equations "
                 f"({ident.trimmed} outliers left out; smoothing {ident.smoothing * 1e3:g} ms)")
    return lines
