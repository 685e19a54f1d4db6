"""Inverse-dynamics cross-check of the aerial manipulator against MuJoCo's mj_inverse, moving base,
friction off (the comparison itself lives in kiloloop.sil.aerial_crosscheck, which `kiloloop bench`
also prints), and the body inertia through URDF loading."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.sil.aerial_crosscheck import inverse_dynamics_crosscheck
from kiloloop.sil.aerial_plant import AerialPlant
from kiloloop.sil.aerial_family import aerial_paths, load_robot


@pytest.fixture(scope="module")
def setup():
    urdf, _ = aerial_paths()
    plant = AerialPlant.from_robot(load_robot(), damping=0.0, frictionloss=0.0, motor_lag=False)
    model = kl.RobotModel.from_urdf(str(urdf), tip="ee_link")
    return plant, model, kl.FloatingBaseRne(model)


def test_arm_torques_and_reaction_wrench_match_mj_inverse():
    r = inverse_dynamics_crosscheck(n=200)
    print(r)
    assert r["total_mass_mujoco"] == pytest.approx(r["total_mass_kdl"], abs=1e-12)
    assert r["max_tau_error_Nm"] < 1e-6
    assert r["max_force_error_N"] < 1e-6 and r["max_torque_error_Nm"] < 1e-6


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
