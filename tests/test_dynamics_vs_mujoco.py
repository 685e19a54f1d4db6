"""kiloloop.Dynamics (KDL, from the URDF) against MuJoCo's mj_inverse and mj_fullM on the UR5.

Both sides read the same models/ur5/ur5.urdf. The MuJoCo plant is built without damping, friction
loss, armature or floor, with gravity (0, 0, -9.81), and its inverse dynamics ignores constraints,
so both compute the same rigid-body quantities and agree to rounding.
"""
from pathlib import Path

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.sil.plant import MujocoPlant

ROOT = Path(__file__).resolve().parents[1]
URDF = ROOT / "models" / "ur5" / "ur5.urdf"
SEED = 20240917
N_SAMPLES = 1000
GRAVITY = (0.0, 0.0, -9.81)


@pytest.fixture(scope="module")
def plant():
    plant = MujocoPlant(URDF, {"physics": {"gravity": list(GRAVITY)}}, damping=0.0,
                        frictionloss=0.0, armature=0.0, floor=False)
    m = plant.model
    assert np.all(m.dof_damping == 0) and np.all(m.dof_frictionloss == 0)
    assert np.all(m.dof_armature == 0)
    np.testing.assert_array_equal(m.opt.gravity, GRAVITY)
    return plant


@pytest.fixture(scope="module")
def dyn():
    model = kl.RobotModel.from_urdf(str(URDF))
    return model, kl.Dynamics(model, gravity=GRAVITY)


@pytest.fixture(scope="module")
def samples():
    """(q, qd, qdd) rows in kiloloop's joint order: q in +-pi, qd within the UR5 speed limits."""
    print(f"seed={SEED}")
    rng = np.random.default_rng(SEED)
    q = rng.uniform(-np.pi, np.pi, size=(N_SAMPLES, 6))
    qd = rng.uniform(-3.15, 3.15, size=(N_SAMPLES, 6))
    qdd = rng.uniform(-10.0, 10.0, size=(N_SAMPLES, 6))
    return q, qd, qdd


def _plant_order(plant, model):
    """Index array p with x_plant = x_kl[p], matching joints by name, not by position."""
    assert sorted(model.joint_names) == sorted(plant.joint_names)
    return np.array([list(model.joint_names).index(n) for n in plant.joint_names])


def test_inverse_dynamics_matches_mj_inverse(plant, dyn, samples):
    model, d = dyn
    p = _plant_order(plant, model)
    worst = 0.0
    for q, qd, qdd in zip(*samples):
        tau_kl = np.asarray(d.inverse_dynamics(q, qd, qdd))
        tau_mj = plant.inverse_dynamics(q[p], qd[p], qdd[p])
        worst = max(worst, np.max(np.abs(tau_kl[p] - tau_mj)))
    print(f"inverse dynamics vs mj_inverse, {N_SAMPLES} samples: max error {worst:.3e} N m")
    assert worst < 1e-6, f"seed={SEED}: max |tau_kl - tau_mj| = {worst:.3e} N m"


def test_mass_matrix_matches_mj_fullM(plant, dyn, samples):
    model, d = dyn
    m = plant.model
    data = mujoco.MjData(m)
    # MuJoCo addresses of each kiloloop joint, by name.
    qadr = [m.joint(n).qposadr[0] for n in model.joint_names]
    dof = [m.joint(n).dofadr[0] for n in model.joint_names]
    M_mj = np.zeros((m.nv, m.nv))
    worst = 0.0
    for q in samples[0]:
        data.qpos[qadr] = q
        mujoco.mj_forward(m, data)
        mujoco.mj_fullM(m, data, M_mj)
        M_kl = np.asarray(d.mass_matrix(q))
        worst = max(worst, np.max(np.abs(M_kl - M_mj[np.ix_(dof, dof)])))
    print(f"mass matrix vs mj_fullM, {N_SAMPLES} samples: max error {worst:.3e}")
    assert worst < 1e-9, f"seed={SEED}: max |M_kl - M_mj| = {worst:.3e}"


def test_inverse_dynamics_equals_m_qdd_plus_c_plus_g(dyn, samples):
    _, d = dyn
    worst = 0.0
    for q, qd, qdd in zip(*samples):
        tau = np.asarray(d.inverse_dynamics(q, qd, qdd))
        split = (np.asarray(d.mass_matrix(q)) @ qdd + np.asarray(d.coriolis(q, qd))
                 + np.asarray(d.gravity(q)))
        worst = max(worst, np.max(np.abs(tau - split)))
    assert worst < 1e-9, f"seed={SEED}: max |tau - (M qdd + C qd + g)| = {worst:.3e} N m"
