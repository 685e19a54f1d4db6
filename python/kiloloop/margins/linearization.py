"""A loop's frequency response by linearization about the operating point, in discrete time at
the control period T:

  plant       x+ = A x + B u + B_d d            MuJoCo's mjd_transitionFD (A, B; x the tangent
                                                state [dq; qvel; act]); B_d the step differenced
                                                along the injection's generalized force
  measurement y = C_now x + z^-1 (C_acc x + D_acc u + D_d d)
                                                the native loop reads positions and velocities
                                                after the step, acceleration-stage sensors (an
                                                accelerometer) from the step before
  return      r = C_r x + D_r u                 w . actuator_force during the step
  controller  u = Q(z) y                        the compiled controller with everything between
                                                the plant's readings and its ctrl: sensor stages,
                                                measurement delay, adapter, motor delay and lag;
                                                Q is its impulse response, each measurement
                                                element perturbed by eps for one tick in the
                                                native loop (the physics frozen, the readings
                                                written) minus an unperturbed run
  closed      T(z) = r / d, and the loop at the break L = -T / (1 + T) (the injection's
                                                identity s = r + d, r = -L s; margins/loops.py)

The impulse responses are `memory` [s] long (margins/operating_point.py); beyond, each element
is continued geometrically from its last samples (a settled integrator's constant, a filter's
decay), so slow controller states (integrators, estimators) keep their low-frequency effect.
"""
from __future__ import annotations

import copy

import mujoco
import numpy as np

from ..errors import InputError
from ..sil.family import CONTROL_DT
from ..sil.timing import whole_periods

EPS = 1e-6        # perturbation of a measurement element (its unit) and of the plant's state


class _Frozen:
    """Writes the measurement's raw readings (sensordata, qpos, qvel addresses) of a data, with
    the plant held at one state: the controller chain run open loop in the native loop."""

    def __init__(self, data, addresses, sources):
        self.data = data
        self.state = (data.qpos.copy(), data.qvel.copy(), data.act.copy())
        arrays = {0: data.sensordata, 1: data.qpos, 2: data.qvel}
        self.targets = [(arrays[s], int(a)) for a, s in zip(addresses, sources)]
        self.y0 = np.array([arr[a] for arr, a in self.targets])

    def write(self, y):
        d = self.data
        d.qpos[:], d.qvel[:], d.act[:] = self.state
        for (arr, a), value in zip(self.targets, y):
            arr[a] = value


def controller_impulse(op, measurement, acts, memory: float, eps: float = EPS):
    """(N, nu, ny) the controller chain's response in ctrl[acts] to eps on each element of y
    for one tick, per unit (minus the unperturbed run); and y at the operating point."""
    n = whole_periods(memory, CONTROL_DT)
    ny = len(measurement.addresses)

    def run(j):
        r, data = op.rollout(n)
        r.advance(op.settle_ticks)
        frozen = _Frozen(data, measurement.addresses, measurement.sources)
        out = np.zeros((n, len(acts)))
        for k in range(n):
            y = frozen.y0.copy()
            if k == 0 and j is not None:
                y[j] += eps
            frozen.write(y)
            r.advance(1)
            out[k] = data.ctrl[acts]
        if not r.ok:
            raise RuntimeError(f"margins: controller experiment stopped: {r.error}")
        return out, frozen.y0

    base, y0 = run(None)
    H = np.zeros((n, len(acts), ny))
    for j in range(ny):
        H[:, :, j] = (run(j)[0] - base) / eps
    return H, y0


def fir_response(H: np.ndarray, z: np.ndarray) -> np.ndarray:
    """(nw, nu, ny) sum_k H[k] z^-k, continued geometrically past the last sample."""
    n = H.shape[0]
    powers = z[:, None] ** (-np.arange(n))[None, :]            # (nw, n)
    Q = np.einsum("wk,kij->wij", powers, H)
    lag = n // 4
    last, before = H[-1], H[-1 - lag]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where((last * before > 0) & (np.abs(before) > 0), last / before, 0.0)
    lam = np.clip(ratio, 0.0, 1.0) ** (1.0 / lag)
    zi = (1.0 / z)[:, None, None]
    tail = last[None] * zi ** (n - 1) * (lam[None] * zi) / (1.0 - lam[None] * zi)
    return Q + np.where(lam[None] > 0, tail, 0.0)


def _tangent(m, d_plus, d_minus, eps):
    dq = np.zeros(m.nv)
    mujoco.mj_differentiatePos(m, dq, 2 * eps, d_minus.qpos, d_plus.qpos)
    return np.concatenate([dq, (d_plus.qvel - d_minus.qvel) / (2 * eps),
                           (d_plus.act - d_minus.act) / (2 * eps)])


def _stepped(m, d, qfrc):
    dd = copy.copy(d)
    dd.qfrc_applied[:] = d.qfrc_applied + qfrc
    mujoco.mj_step(m, dd)
    return dd


def _forwarded(m, d, dx=None, du=None, acts=()):
    dd = copy.copy(d)
    if dx is not None:
        nv = m.nv
        mujoco.mj_integratePos(m, dd.qpos, dx[:nv], 1.0)
        dd.qvel[:] += dx[nv:2 * nv]
        dd.act[:] += dx[2 * nv:]
    if du is not None:
        dd.ctrl[acts] += du
    mujoco.mj_forward(m, dd)
    return dd


def plant(m, d, acts, qfrc, w, eps: float = EPS):
    """The plant's matrices at (d's state, d's ctrl): A, B (acts), B_d (qfrc), C, D (sensordata),
    D_d (sensordata to qfrc), C_r, D_r (w . actuator_force[acts])."""
    if abs(m.opt.timestep - CONTROL_DT) > 1e-12:
        raise InputError("the linearization takes physics_dt equal to the control "
                         f"period ({CONTROL_DT} s); --no-linearization measures by injection")
    nx, nu_all = 2 * m.nv + m.na, m.nu
    A, B = np.zeros((nx, nx)), np.zeros((nx, nu_all))
    C, D = np.zeros((m.nsensordata, nx)), np.zeros((m.nsensordata, nu_all))
    mujoco.mjd_transitionFD(m, d, eps, True, A, B, C, D)
    plus, minus = _stepped(m, d, eps * qfrc), _stepped(m, d, -eps * qfrc)
    B_d = _tangent(m, plus, minus, eps)
    D_d = (plus.sensordata - minus.sensordata) / (2 * eps)
    C_r = np.zeros(nx)
    for i in range(nx):
        e = np.zeros(nx)
        e[i] = eps
        f = _forwarded(m, d, e).actuator_force[acts] - _forwarded(m, d, -e).actuator_force[acts]
        C_r[i] = w @ f / (2 * eps)
    D_r = np.zeros(len(acts))
    for i in range(len(acts)):
        e = np.zeros(len(acts))
        e[i] = eps
        f = (_forwarded(m, d, du=e, acts=acts).actuator_force[acts]
             - _forwarded(m, d, du=-e, acts=acts).actuator_force[acts])
        D_r[i] = w @ f / (2 * eps)
    return dict(A=A, B=B[:, acts], B_d=B_d, C=C, D=D[:, acts], D_d=D_d, C_r=C_r, D_r=D_r)


def measurement_rows(m, addresses, sources):
    """Per y element: ("now" | "before", sensordata row) or ("state", tangent index)."""
    rows = []
    for a, s in zip(addresses, sources):
        a = int(a)
        if s == 0:
            sensor = int(np.searchsorted(m.sensor_adr, a, side="right") - 1)
            acc = m.sensor_needstage[sensor] == mujoco.mjtStage.mjSTAGE_ACC
            rows.append(("before" if acc else "now", a))
        elif s == 2:
            rows.append(("state", m.nv + a))
        else:
            j = int(np.searchsorted(m.jnt_qposadr, a, side="right") - 1)
            offset = a - int(m.jnt_qposadr[j])
            if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE and offset >= 3:
                raise InputError("the measurement reads a free joint's quaternion from qpos: "
                                 "not linearized")
            rows.append(("state", int(m.jnt_dofadr[j]) + offset))
    return rows


def loop_response(P: dict, rows, H: np.ndarray, w: np.ndarray):
    """L(e^{jwT}) at w [rad/s] of the plant matrices P, measurement rows and controller chain
    impulse response H."""
    nx = P["A"].shape[0]
    ny = len(rows)
    Cn, Ca = np.zeros((ny, nx)), np.zeros((ny, nx))
    Da, Dd = np.zeros((ny, P["B"].shape[1])), np.zeros(ny)
    for i, (kind, k) in enumerate(rows):
        if kind == "state":
            Cn[i, k] = 1.0
        elif kind == "now":
            Cn[i] = P["C"][k]
        else:
            Ca[i], Da[i], Dd[i] = P["C"][k], P["D"][k], P["D_d"][k]
    z = np.exp(1j * w * CONTROL_DT)
    Q = fir_response(H, z)
    out = np.zeros(len(w), complex)
    eye = np.eye(nx)
    for i, zi in enumerate(z):
        Phi_B = np.linalg.solve(zi * eye - P["A"], np.column_stack([P["B"], P["B_d"]]))
        XB, Xd = Phi_B[:, :-1], Phi_B[:, -1]
        Cy = Cn + Ca / zi
        Pu = Cy @ XB + Da / zi                 # u -> y
        Pd = Cy @ Xd + Dd / zi                 # d -> y
        Qi = Q[i]
        u = np.linalg.solve(np.eye(Qi.shape[0]) - Qi @ Pu, Qi @ Pd)
        out[i] = P["C_r"] @ (XB @ u + Xd) + P["D_r"] @ u
    return -out / (1.0 + out)
