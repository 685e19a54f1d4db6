"""Inverse-dynamics cross-check of the aerial manipulator against MuJoCo, moving base, friction off.

Our side: kl.FloatingBaseRne (KDL types, the arm's chain from the body) gives the arm torques and
the wrench the body applies to the arm. MuJoCo's side: mj_inverse on the plant built from the same
URDF gives the generalized forces of the free joint and the arm joints; subtracting the body's own
Newton-Euler terms (its CoM is its origin) from the free-joint part leaves the arm's share.
Used by tests/test_aerial_dynamics.py (asserts) and `kiloloop bench` (prints).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..robot import aerial as aerial_robot
from .aerial_plant import AerialPlant

_G = np.array([0.0, 0.0, -9.81])


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def inverse_dynamics_crosscheck(robot=None, n: int = 200, seed: int = 20261122) -> dict:
    """Largest |ours - MuJoCo| over n seeded random states (random attitude, body twist and
    acceleration, arm position within limits, velocity and acceleration): arm torques [N m] and
    the reaction wrench [N, N m]. robot: an aerial robot file with an arm whose body CoM is its
    origin (default: kiloloop's aerial manipulator)."""
    from .aerial_family import load_robot

    robot = load_robot(robot)
    plant = AerialPlant.from_robot(robot, damping=0.0, frictionloss=0.0, motor_lag=False)
    model = aerial_robot.model(robot)
    rne = kl.FloatingBaseRne(model)
    ctrl = kl.AerialController(model, aerial_robot.config(robot))
    m_b, J_b = ctrl.body_mass, np.asarray(ctrl.body_inertia)
    rng = np.random.default_rng(seed)
    worst_tau = worst_force = worst_torque = 0.0
    for _ in range(n):
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        q = rng.uniform(model.lower, model.upper)
        pos = rng.uniform(-1, 1, 3)
        v_w, omega = rng.normal(size=3), rng.normal(size=3) * 2.0
        a_w, alpha = rng.normal(size=3) * 5.0, rng.normal(size=3) * 10.0
        qd, qdd = rng.normal(size=model.nq) * 2.0, rng.normal(size=model.nq) * 10.0
        gen = plant.inverse_dynamics(pos, quat, q, v_w, omega, qd, a_w, alpha, qdd)
        R = quat_to_matrix(quat)
        status, tau, W = rne.compute(q, qd, qdd, R.T @ v_w, omega, R.T @ (a_w - _G), alpha)
        if status != kl.Status.OK:
            raise RuntimeError(f"FloatingBaseRne.compute: {status}")
        # The free joint's generalized force: world-frame force, body-frame torque about the origin.
        arm_force_world = gen[:3] - m_b * (a_w - _G)
        arm_torque_body = gen[3:6] - (J_b @ alpha + np.cross(omega, J_b @ omega))
        worst_tau = max(worst_tau, float(np.max(np.abs(tau - gen[6:]))))
        worst_force = max(worst_force, float(np.max(np.abs(R @ W[:3] - arm_force_world))))
        worst_torque = max(worst_torque, float(np.max(np.abs(W[3:] - arm_torque_body))))
    return {"states": n, "seed": seed, "max_tau_error_Nm": worst_tau,
            "max_force_error_N": worst_force, "max_torque_error_Nm": worst_torque,
            "total_mass_mujoco": plant.total_mass, "total_mass_kdl": ctrl.total_mass}
