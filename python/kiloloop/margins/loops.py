"""Which signal each loop is: a direction in the rig's actuator forces where the loop is broken.

A loop is the pair (v, w) over the actuators u of the rig (sil/family.py actuators, their
MuJoCo actuator_force units: N m of a joint, N of a rotor), w . v = 1: the loop signal is
s = w . f (f: the actuators' forces); breaking the loop there and driving s with x is f ->
(I - v w^T) f + v x. The injection adds d along v as a generalized force (qfrc_applied = the
actuators' moment^T v d, what the actuators would apply), so the plant sees s = r + d with the
return r = w . f; the linearization closes the same loop (margins/linearization.py).

  arm        joint:<i>            the i-th chain joint's torque (v = w = e_i)
  quadruped  roll, pitch, height  the trunk's wrench about the robot's CoM that the joint torques
                                  exert through the stance feet (the static map tau -> f_feet ->
                                  trunk wrench from MuJoCo's foot Jacobians): body x, y torque
                                  [N m], vertical force [N]; v the least-norm torques of a pure one
  aerial     roll, pitch, yaw, z  the rotors' wrench about the vehicle's CoM: body x, y, z torque
                                  [N m], vertical force [N]; v the least-norm thrusts of a pure
                                  one (the arm's joints not used)
"""
from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from ..errors import InputError

# The wrench rows: [force (world) x, y, z; torque (body) x, y, z] about the CoM.
WRENCH_ROW = {"roll": 3, "pitch": 4, "yaw": 5, "z": 2, "height": 2}
FAMILY_LOOPS = {"arm": ("joint:<i>",), "quadruped": ("roll", "pitch", "height"),
                "aerial": ("roll", "pitch", "yaw", "z")}


@dataclass(frozen=True)
class Loop:
    name: str
    unit: str
    v: np.ndarray        # (nu) actuator forces of one unit of loop signal
    w: np.ndarray        # (nu) loop signal of the actuator forces
    qfrc: np.ndarray     # (nv) generalized force of one unit along v (the injection)
    authority: float     # [unit] the largest |s| along v within the actuators' limits


def moment(model, data) -> np.ndarray:
    """(nu, nv) dense actuator moment matrix (qfrc_actuator = moment^T actuator_force)."""
    dense = np.zeros((model.nu, model.nv))
    mujoco.mju_sparse2dense(dense, data.actuator_moment, data.moment_rownnz,
                            data.moment_rowadr, data.moment_colind)
    return dense


def _about_com(plant, data, G: np.ndarray) -> np.ndarray:
    """(6, k) [force (world); torque (body) about the base's subtree CoM] from free-joint
    generalized forces G (6, k): [world force; body torque about the body origin]."""
    b = int(plant._base_id)
    R = data.xmat[b].reshape(3, 3)
    arm = R.T @ (data.subtree_com[b] - data.xpos[b])   # body frame, origin -> CoM
    F_body = R.T @ G[:3]
    return np.vstack([G[:3], G[3:] - np.cross(arm, F_body.T).T])


def _limits(model, acts) -> np.ndarray:
    out = []
    for a in acts:
        lo, hi = model.actuator_forcerange[a] if model.actuator_forcelimited[a] else (
            model.actuator_ctrlrange[a] if model.actuator_ctrllimited[a] else (-np.inf, np.inf))
        out.append(min(abs(lo), abs(hi)))
    return np.array(out)


def _authority(v, headroom) -> float:
    ratio = np.abs(v) / np.where(headroom > 0, headroom, np.nan)
    worst = np.nanmax(ratio) if np.any(np.abs(v) > 0) else np.nan
    return float(1.0 / worst) if np.isfinite(worst) and worst > 0 else float("inf")


def _loop(name, unit, v, w, M, f0, headroom) -> Loop:
    return Loop(name, unit, v, w, M.T @ v, _authority(v, headroom - np.abs(f0)))


def arm_loop(op, data, name: str) -> Loop:
    m, acts = op.rig.plant.model, [int(a) for a in op.rig.plant._act]
    try:
        i = int(name.split(":", 1)[1])
    except (IndexError, ValueError):
        raise InputError(f"--loop {name}: an arm's loops are joint:<i>, i = 0..{len(acts) - 1}")
    if not (name.startswith("joint:") and 0 <= i < len(acts)):
        raise InputError(f"--loop {name}: an arm's loops are joint:<i>, i = 0..{len(acts) - 1}")
    e = np.zeros(len(acts))
    e[i] = 1.0
    M = moment(m, data)[acts]
    return _loop(name, "N m", e, e.copy(), M, data.actuator_force[acts], _limits(m, acts))


def _wrench_loop(name, W, M, f0, headroom, columns, nu) -> Loop:
    row = WRENCH_ROW[name]
    w = np.zeros(nu)
    v = np.zeros(nu)
    w[columns] = W[row]
    v[columns] = np.linalg.pinv(W)[:, row]
    if abs(w @ v - 1.0) > 1e-6:
        raise InputError(f"--loop {name}: the actuators cannot produce it alone")
    return _loop(name, "N" if row < 3 else "N m", v, w, M, f0, headroom)


def aerial_loop(op, data, name: str) -> Loop:
    rig = op.rig
    m, p = rig.plant.model, rig.plant
    acts = [int(a) for a in rig.family.actuators(rig.parts)]
    M = moment(m, data)[acts]
    rotors = list(range(rig.n_rotors))
    fd = int(p._free_d)
    W = _about_com(p, data, M[rotors][:, fd:fd + 6].T)
    thrust_max = np.array([m.actuator_ctrlrange[a][1] if m.actuator_ctrllimited[a] else np.inf
                           for a in acts])
    return _wrench_loop(name, W, M, data.actuator_force[acts], thrust_max, rotors, len(acts))


def quadruped_loop(op, data, name: str) -> Loop:
    rig = op.rig
    m, p = rig.plant.model, rig.plant
    acts = [int(a) for a in rig.family.actuators(rig.parts)]
    M = moment(m, data)[acts]                       # (12, nv)
    fd = int(p._free_d)
    base = list(range(fd, fd + 6))
    S = np.zeros((6, len(acts)))
    jac = np.zeros((3, m.nv))
    for site in p._foot_sites:
        mujoco.mj_jacSite(m, data, jac, None, int(site))
        legs = [j for j in range(m.nv) if j not in base and abs(jac[:, j]).max() > 1e-12]
        if len(legs) != 3:
            raise InputError(f"--loop {name}: a foot moved by {len(legs)} joints (expected 3)")
        # Static stance: the joint torques' generalized forces Q balance the foot force f:
        # Q_leg + J_leg^T f = 0; the trunk gets J_base^T f.
        f_of_tau = -np.linalg.solve(jac[:, legs].T, M[:, legs].T)   # (3, 12)
        S += jac[:, base].T @ f_of_tau
    W = _about_com(p, data, S)
    return _wrench_loop(name, W, M, data.actuator_force[acts], _limits(m, acts),
                        list(range(len(acts))), len(acts))


def loop_of(op, data, name: str) -> Loop:
    kind = op.rig.robot.kind
    if kind == "arm":
        return arm_loop(op, data, name)
    if name not in FAMILY_LOOPS[kind]:
        who = {"quadruped": "a quadruped", "aerial": "a multirotor"}[kind]
        raise InputError(f"--loop {name}: {who}'s loops are {', '.join(FAMILY_LOOPS[kind])}")
    return (aerial_loop if kind == "aerial" else quadruped_loop)(op, data, name)
