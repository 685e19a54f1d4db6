"""Inverse-dynamics cross-check of the aerial manipulator against MuJoCo, moving base, friction off.

Our side: kl.FloatingBaseRne (KDL types, the arm's chain from the body) gives the arm torques and
the wrench the body applies to the arm. MuJoCo's side: mj_inverse on the plant built from the same
URDF gives the generalized forces of the free joint and the arm joints; subtracting the body's own
Newton-Euler terms (its CoM is its origin) from the free-joint part leaves the arm's share.
"""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.sil.aerial_plant import AerialPlant
from kiloloop.sil.aerial_rig import aerial_paths

G = np.array([0.0, 0.0, -9.81])


@pytest.fixture(scope="module")
def setup():
    urdf, overlay = aerial_paths()
    plant = AerialPlant(urdf, overlay, damping=0.0, frictionloss=0.0, motor_lag=False)
    model = kl.RobotModel.from_urdf(str(urdf), tip="ee_link")
    return plant, model, kl.FloatingBaseRne(model)


def quat_to_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def test_arm_torques_and_reaction_wrench_match_mj_inverse(setup, rng):
    plant, model, rne = setup
    ctrl = kl.AerialController(model)
    m_b, J_b = ctrl.body_mass, np.asarray(ctrl.body_inertia)
    assert plant.total_mass == pytest.approx(ctrl.total_mass, abs=1e-12)
    worst_tau = worst_wrench = 0.0
    for _ in range(200):
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        q = rng.uniform(model.lower, model.upper)
        pos = rng.uniform(-1, 1, 3)
        v_w, omega = rng.normal(size=3), rng.normal(size=3) * 2.0
        a_w, alpha = rng.normal(size=3) * 5.0, rng.normal(size=3) * 10.0
        qd, qdd = rng.normal(size=3) * 2.0, rng.normal(size=3) * 10.0
        gen = plant.inverse_dynamics(pos, quat, q, v_w, omega, qd, a_w, alpha, qdd)

        R = quat_to_matrix(quat)
        status, tau, W = rne.compute(q, qd, qdd, R.T @ v_w, omega, R.T @ (a_w - G), alpha)
        assert status == kl.Status.OK
        # The free joint's generalized force: world-frame force, body-frame torque about the origin.
        body_force = m_b * (a_w - G)
        body_torque = J_b @ alpha + np.cross(omega, J_b @ omega)
        arm_force_world = gen[:3] - body_force
        arm_torque_body = gen[3:6] - body_torque
        worst_tau = max(worst_tau, np.max(np.abs(tau - gen[6:])))
        worst_wrench = max(worst_wrench, np.max(np.abs(R @ W[:3] - arm_force_world)),
                           np.max(np.abs(W[3:] - arm_torque_body)))
    print(f"max |tau - mj| = {worst_tau:.3e} N m, max |wrench - mj| = {worst_wrench:.3e}")
    assert worst_tau < 1e-6
    assert worst_wrench < 1e-6


def test_body_inertia_survives_urdf_loading(setup):
    plant, model, _ = setup
    ctrl = kl.AerialController(model)
    body = plant.model.body(plant.base_body)
    assert ctrl.body_mass == pytest.approx(float(body.mass[0]), abs=1e-12) == 1.5
    # MuJoCo stores principal moments (sorted); the URDF tensor is diagonal.
    np.testing.assert_allclose(np.sort(np.diag(ctrl.body_inertia)), np.sort(body.inertia),
                               atol=1e-12)
    assert model.root_inertia_restored


def test_bad_sizes_raise_value_error(setup):
    _, _, rne = setup
    z3 = np.zeros(3)
    with pytest.raises(ValueError, match="q: expected shape"):
        rne.compute(np.zeros(2), z3, z3, z3, z3, z3, z3)
