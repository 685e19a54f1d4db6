"""Linear-in-parameters regressors of rigid-body dynamics, on a MuJoCo model's scratch data.

The joint torques a body's own inertia takes are linear in its ten standard inertial parameters
pi = [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_xz, I_yy, I_yz, I_zz] (c: the CoM and I: the inertia
about the body frame's origin, both in the body frame):

    f = m a + alpha x (m c) + w x (w x (m c))           (force at the origin, body frame)
    n = I alpha + w x (I w) + (m c) x a                  (moment about the origin, body frame)
    tau = Jp^T R f + Jr^T R n

with w, alpha the body's angular velocity and acceleration, and a its origin's classical linear
acceleration minus gravity (MuJoCo's world acceleration carries -g). So a payload on a link adds
Y(q, qd, qdd) pi to the inverse dynamics: Khalil and Dombre, "Modeling, Identification and
Control of Robots" (2002), ch. 12.
"""
from __future__ import annotations

import mujoco
import numpy as np

N_INERTIAL = 10
PARAMETER_NAMES = ("m", "mcx", "mcy", "mcz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz")


def _skew(x) -> np.ndarray:
    return np.array([[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]])


def _inertia_map(x) -> np.ndarray:
    """L(x) with L(x) [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] = I x."""
    return np.array([[x[0], x[1], x[2], 0.0, 0.0, 0.0],
                     [0.0, x[0], 0.0, x[1], x[2], 0.0],
                     [0.0, 0.0, x[0], 0.0, x[1], x[2]]])


def wrench_regressor(w, alpha, a) -> np.ndarray:
    """(6, 10): [f; n] in the body frame = A pi (the Newton-Euler equations above)."""
    A = np.zeros((6, N_INERTIAL))
    W = _skew(w)
    A[:3, 0] = a
    A[:3, 1:4] = _skew(alpha) + W @ W
    A[3:, 1:4] = -_skew(a)
    A[3:, 4:] = _inertia_map(alpha) + W @ _inertia_map(w)
    return A


class BodyRegressor:
    """Y(q, qd, qdd) (ndof, 10) of one body of a MuJoCo model, for the dofs `dofs`."""

    def __init__(self, model, body: int, qpos_addresses, dof_addresses):
        self.m, self.body = model, int(body)
        self.d = mujoco.MjData(model)
        self.qadr, self.dadr = np.asarray(qpos_addresses), np.asarray(dof_addresses)
        self._jacp, self._jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
        self._v, self._a = np.zeros(6), np.zeros(6)

    def __call__(self, q, qd, qdd) -> np.ndarray:
        m, d = self.m, self.d
        d.qpos[self.qadr], d.qvel[self.dadr], d.qacc[self.dadr] = q, qd, qdd
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_comVel(m, d)
        mujoco.mj_rnePostConstraint(m, d)  # cacc: the bodies' accelerations (with -g)
        xbody = mujoco.mjtObj.mjOBJ_XBODY  # the body frame (mjOBJ_BODY: its inertial frame)
        mujoco.mj_objectVelocity(m, d, xbody, self.body, self._v, 1)
        mujoco.mj_objectAcceleration(m, d, xbody, self.body, self._a, 1)
        A = wrench_regressor(self._v[:3], self._a[:3], self._a[3:])
        mujoco.mj_jacBody(m, d, self._jacp, self._jacr, self.body)
        R = d.xmat[self.body].reshape(3, 3)
        Jp = (R.T @ self._jacp)[:, self.dadr]
        Jr = (R.T @ self._jacr)[:, self.dadr]
        return Jp.T @ A[:3] + Jr.T @ A[3:]


def inertial_parameters(mass: float, com, inertia_com) -> np.ndarray:
    """pi of a body from its mass [kg], CoM (3) [m] and inertia about the CoM (3, 3) [kg m^2],
    all in the body frame (the parallel-axis theorem moves the inertia to the origin)."""
    c = np.asarray(com, float)
    I = np.asarray(inertia_com, float) + mass * (c @ c * np.eye(3) - np.outer(c, c))
    return np.array([mass, *(mass * c), I[0, 0], I[0, 1], I[0, 2], I[1, 1], I[1, 2], I[2, 2]])


def split_parameters(pi) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, CoM (3), inertia about the CoM (3, 3)) of pi; CoM and inertia NaN without mass."""
    m = float(pi[0])
    if m <= 0:
        return m, np.full(3, np.nan), np.full((3, 3), np.nan)
    c = np.asarray(pi[1:4]) / m
    I = np.array([[pi[4], pi[5], pi[6]], [pi[5], pi[7], pi[8]], [pi[6], pi[8], pi[9]]])
    return m, c, I - m * (c @ c * np.eye(3) - np.outer(c, c))
