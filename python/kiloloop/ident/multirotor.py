"""Identification of a multirotor's rotors from excitation logs, against its robot file as the
nominal model: each rotor's thrust gain (the thrust per commanded newton: [sim.rotors]
efficiency), drag-torque coefficient and time constant, and the command delay.

Per tick k the vehicle's measured motion gives, through the nominal whole-body inverse dynamics
(MuJoCo's mj_inverse of the file's URDF with the arm at its encoders), the generalized force on
the floating base that the rotors must have made:

    ID_base(q_k, v_k, a_k) = sum_i f_ik (g_i Jf_ik + g_i c_i Jt_ik)

with Jf_ik, Jt_ik the base's generalized force of a unit thrust along rotor i's axis and of a
unit torque about it (times -spin: its drag), g_i the gain, c_i the drag-torque coefficient,
and f_ik the commanded thrust through the plant's rotor model: delayed by whole ticks, clipped to
the rotor's range, then the first-order lag d f / dt = (u - f) / T_i (MuJoCo's filter, Euler:
the force of tick k follows the command of tick k - 1). Linear in (g_i, g_i c_i) for a given
delay and lags, which are searched (the delay over whole ticks, the lags by golden sections).

The motion: orientation and angular velocity from the IMU (its site's pose on the base from the
file), angular acceleration a forward difference of the gyro, the linear acceleration the
accelerometer's specific force at the site plus gravity, moved to the base origin; position and
velocity from motion capture; the arm's joints from its encoders. A scenario's log (no IMU, the
base's state instead: `kiloloop run aerial-hover --log`) is read too.
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from ..errors import InputError
from ..sil.log import SignalLog
from .fit import bounded_lstsq, golden_section
from .motor import first_order

DT = 0.001
STRIDE = 4
SKIP = 0.3          # [s]
MAX_DELAY = 0.06    # [s]
MAX_TIME_CONSTANT = 0.2  # [s]


@dataclass
class MultirotorIdentification:
    gain: np.ndarray                 # [-] thrust per commanded thrust ([sim.rotors] efficiency)
    torque_coefficient: np.ndarray   # [m]
    time_constant: np.ndarray        # [s]
    stderr: dict
    delay: float                     # [s]
    delay_ticks: int
    residual_rms: float              # of the normalised base wrench rows
    rows: int

    def as_dict(self) -> dict:
        return {"gain": self.gain.tolist(), "torque_coefficient": self.torque_coefficient.tolist(),
                "time_constant": self.time_constant.tolist(),
                "stderr": {k: [e if np.isfinite(e) else None for e in np.asarray(v).tolist()]
                           for k, v in self.stderr.items()},
                "delay": self.delay, "delay_ticks": self.delay_ticks,
                "residual_rms": self.residual_rms, "rows": self.rows}


def _quat_mat(q) -> np.ndarray:
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, np.asarray(q, float))
    return R.reshape(3, 3)


def _imu_motion(plant, log: SignalLog):
    """(N, 4) base orientation (w, x, y, z), (N, 3) base angular velocity (base frame) and
    (N, 3) the base origin's linear acceleration of each tick (world) [m/s^2], from the IMU: the
    accelerometer's sample of tick k + 1 is the step that ended there (tick k's acceleration),
    its specific force at the site plus gravity, moved to the base origin."""
    m = plant.model
    site = m.site(plant.imu_site).id
    R_bs = _quat_mat(m.site_quat[site])          # base <- IMU site
    r_b = m.site_pos[site].copy()                # the IMU in the base frame [m]
    gyro, accel, quat = (np.asarray(log[n], float) for n in ("gyro", "accel", "imu_quat"))
    w_b = gyro @ R_bs.T
    alpha = np.zeros_like(w_b)
    alpha[:-1] = (w_b[1:] - w_b[:-1]) / DT
    quats, acc = np.zeros((len(w_b), 4)), np.zeros((len(w_b), 3))
    g = m.opt.gravity
    for i in range(len(w_b) - 1):
        R_ws = _quat_mat(quat[i])
        R_wb = R_ws @ R_bs.T
        mujoco.mju_mat2Quat(quats[i], R_wb.ravel())
        w, al = w_b[i], alpha[i]
        a_site = R_ws @ accel[i + 1] + g
        acc[i] = a_site - R_wb @ (np.cross(al, r_b) + np.cross(w, np.cross(w, r_b)))
    quats[-1] = quats[-2]
    return quats, w_b, acc


def _state_motion(log: SignalLog):
    """The same from a scenario's log without an IMU: its base_quat, base_omega (base frame)
    and the forward difference of base_vel (the ground truth an aerial scenario logs)."""
    vel = np.asarray(log["base_vel"], float)
    acc = np.zeros_like(vel)
    acc[:-1] = (vel[1:] - vel[:-1]) / DT
    return np.asarray(log["base_quat"], float), np.asarray(log["base_omega"], float), acc


IMU_SIGNALS = ("gyro", "accel", "imu_quat")
STATE_SIGNALS = ("base_quat", "base_omega")


def _base_motion(plant, log: SignalLog, k: np.ndarray, arm_index: np.ndarray):
    """(qpos, qvel, qacc) rows of the nominal plant at ticks k from the logged sensors (the IMU
    when the log has one, else the base's logged state)."""
    quat, w_b, acc = (_imu_motion(plant, log) if all(n in log for n in IMU_SIGNALS)
                      else _state_motion(log))
    pos, vel = np.asarray(log["base_pos"], float), np.asarray(log["base_vel"], float)
    alpha = (w_b[k + 1] - w_b[k]) / DT
    nq = plant.nq
    q = np.asarray(log["q"], float) if nq else np.zeros((len(pos), 0))
    qd = np.asarray(log["qd"], float) if nq and "qd" in log else None
    if nq and qd is None:  # a scenario's log: the encoders' positions only
        qd = np.zeros_like(q)
        qd[:-1] = (q[1:] - q[:-1]) / DT
    qdd = (qd[k + 1] - qd[k]) / DT if nq else np.zeros((len(k), 0))
    out = []
    for row, i in enumerate(k):
        qpos = np.concatenate([pos[i], quat[i], q[i][arm_index]])
        qvel = np.concatenate([vel[i], w_b[i], qd[i][arm_index]])
        qacc = np.concatenate([acc[i], alpha[row], qdd[row][arm_index]])
        out.append((qpos, qvel, qacc))
    return out


def _columns(plant, motion):
    """Per tick: the base's required generalized force (6) and the rotors' unit thrust and unit
    drag columns (6, n) each."""
    m = plant.model
    d = mujoco.MjData(m)
    fq, fd = plant._free_q, plant._free_d
    arm_q, arm_d = plant._qadr, plant._dadr
    sites = [m.site(n).id for n in plant.rotor_names]
    spins = np.array([r["spin"] for r in plant.rotors], float)
    jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    free = slice(fd, fd + 6)
    target, F, T = [], [], []
    for qpos, qvel, qacc in motion:
        d.qpos[fq:fq + 7], d.qvel[fd:fd + 6], d.qacc[fd:fd + 6] = qpos[:7], qvel[:6], qacc[:6]
        if len(arm_q):
            d.qpos[arm_q], d.qvel[arm_d], d.qacc[arm_d] = qpos[7:], qvel[6:], qacc[6:]
        mujoco.mj_inverse(m, d)
        target.append(d.qfrc_inverse[free].copy())
        Fk, Tk = [], []
        for s, spin in zip(sites, spins):
            mujoco.mj_jacSite(m, d, jacp, jacr, s)
            axis = d.site_xmat[s].reshape(3, 3)[:, 2]
            Fk.append(jacp[:, free].T @ axis)
            Tk.append(jacr[:, free].T @ (-spin * axis))
        F.append(np.array(Fk).T)
        T.append(np.array(Tk).T)
    return np.array(target), np.array(F), np.array(T)


def thrusts(u: np.ndarray, delay_ticks: int, time_constants, lo, hi) -> np.ndarray:
    """(N, n) the rotors' thrusts per unit gain from commands u (N, n): the ESC holds the first
    command until the delay has passed, MuJoCo clips to the range and filters (Euler, a tick
    late: see the module doc); the filter starts at the first command (a hover's start)."""
    x = np.empty_like(u)
    d = int(delay_ticks) + 1
    x[:d] = u[0]
    x[d:] = u[:len(u) - d]
    x = np.clip(x, lo, hi)
    out = np.empty_like(x)
    for i, T in enumerate(time_constants):
        alpha = min(1.0, DT / T) if T > 0 else 1.0
        out[:, i] = first_order(x[:, i:i + 1] - x[0, i], alpha)[:, 0] + x[0, i]
    if all(T <= 0 for T in time_constants):
        out[1:] = x[:-1]  # no filter: the command of the tick before (the same late tick)
        out[0] = x[0]
    return out


def identify_multirotor(robot, logs: list[SignalLog]) -> MultirotorIdentification:
    from ..robot import aerial as aerial_robot
    from ..sil.aerial_plant import AerialPlant

    plant = AerialPlant.from_robot(robot)
    n = plant.n_rotors
    lo = np.array([r["thrust_min"] for r in plant.rotors])
    hi = np.array([r["thrust_max"] for r in plant.rotors])
    names = list(aerial_robot.model(robot).joint_names) if plant.nq else []
    arm_index = np.array([names.index(j) for j in plant.joint_names], int) if plant.nq else \
        np.zeros(0, int)
    pieces = []
    for log in logs:
        needed = ("t", "thrust_cmd", "base_pos", "base_vel") + (
            IMU_SIGNALS if not all(n in log for n in STATE_SIGNALS) else ())
        for name in needed + (("q",) if plant.nq else ()):
            if name not in log:
                raise InputError(f"identify: the log has no {name!r} signal (a multirotor's log "
                                 "needs t, thrust_cmd, base_pos, base_vel, an IMU (gyro, accel, "
                                 "imu_quat) or the base's state (base_quat, base_omega), and "
                                 "the arm's q)")
        u = np.asarray(log["thrust_cmd"], float)
        if u.shape[1] != n:
            raise InputError(f"identify: the log has {u.shape[1]} rotors, the robot {n}")
        k = np.arange(int(round(SKIP / DT)), len(u) - 2, STRIDE)
        target, F, T = _columns(plant, _base_motion(plant, log, k, arm_index))
        pieces.append((k, u, target, F, T))
    target = np.concatenate([p[2] for p in pieces])
    # Each of the six rows in its own scale (forces [N], moments [N m]).
    weight = 1.0 / np.maximum(np.sqrt(np.mean(target ** 2, axis=0)), 1e-9)
    y = (target * weight).ravel()

    def phi(delay_ticks, taus):
        cols = []
        for k, u, _, F, T in pieces:
            f = thrusts(u, delay_ticks, taus, lo, hi)[k]            # (K, n)
            cols.append(np.concatenate([F * f[:, None, :], T * f[:, None, :]], axis=2)
                        * weight[None, :, None])
        return np.concatenate(cols).reshape(-1, 2 * n)

    def rms(delay_ticks, taus):
        P = phi(delay_ticks, taus)
        theta = np.linalg.lstsq(P, y, rcond=None)[0]
        return float(np.sqrt(np.mean((y - P @ theta) ** 2)))

    nominal_taus = np.array([r["time_constant"] for r in plant.rotors], float)
    max_d = int(round(MAX_DELAY / DT))
    by_delay = [rms(dd, nominal_taus) for dd in range(max_d + 1)]
    delay = int(np.argmin(by_delay))
    taus = nominal_taus.copy()
    for _ in range(2):
        common, _ = golden_section(lambda T: rms(delay, np.full(n, T)), 1e-4, MAX_TIME_CONSTANT,
                                   1e-5)
        taus = np.full(n, common)
        for i in range(n):
            def one(T, i=i):
                t = taus.copy()
                t[i] = T
                return rms(delay, t)
            taus[i] = golden_section(one, 1e-4, MAX_TIME_CONSTANT, 1e-5)[0]
        near = range(max(0, delay - 5), min(max_d, delay + 5) + 1)
        best = min(near, key=lambda dd: rms(dd, taus))
        if best == delay:
            break
        delay = best
    P = phi(delay, taus)
    theta = bounded_lstsq(P, y, np.zeros(2 * n))
    e = y - P @ theta
    free = np.linalg.lstsq(P, y, rcond=None)[0]
    s2 = float(np.sum((y - P @ free) ** 2)) / max(1, len(y) - len(free))
    cov = s2 * np.linalg.pinv(P.T @ P)
    se = np.sqrt(np.diag(cov))
    gain, moment = theta[:n], theta[n:]
    c = np.where(gain > 0, moment / np.maximum(gain, 1e-12), 0.0)
    se_c = np.where(gain > 0, se[n:] / np.maximum(gain, 1e-12), np.inf)
    return MultirotorIdentification(
        gain=gain, torque_coefficient=c, time_constant=taus,
        stderr={"gain": se[:n], "torque_coefficient": se_c}, delay=delay * DT,
        delay_ticks=delay, residual_rms=float(np.sqrt(np.mean(e ** 2))), rows=len(y))


def patch_data(robot, ident: MultirotorIdentification, out_path) -> dict:
    from pathlib import Path

    from .patch import robot_data, set_delay

    data = robot_data(robot, Path(out_path))
    for i, rotor in enumerate(data["rotors"]):
        rotor["torque_coefficient"] = float(f"{ident.torque_coefficient[i]:.6g}")
        rotor["time_constant"] = float(f"{ident.time_constant[i]:.6g}")
    data.setdefault("sim", {}).setdefault("rotors", {})["efficiency"] = [
        float(f"{g:.6g}") for g in ident.gain]
    set_delay(data, "aerial", ident.delay)
    return data


def summary(ident: MultirotorIdentification) -> list[str]:
    se = ident.stderr
    n = len(ident.gain)
    lines = ["rotors        " + " ".join(f"{i:>9}" for i in range(n)),
             "gain          " + " ".join(f"{v:9.4g}" for v in ident.gain) + "  [-]  +- "
             + " ".join(f"{e:.2g}" for e in se["gain"]),
             "torque coeff  " + " ".join(f"{v:9.4g}" for v in ident.torque_coefficient)
             + "  [m]  +- " + " ".join(f"{e:.2g}" for e in se["torque_coefficient"]),
             "time constant " + " ".join(f"{v:9.4g}" for v in ident.time_constant) + "  [s]",
             f"delay         {ident.delay * 1e3:.0f} ms ({ident.delay_ticks} ticks)",
             f"residual      {ident.residual_rms:.3g} (base wrench rows, each in its own RMS) "
             f"over {ident.rows} equations"]
    return lines
