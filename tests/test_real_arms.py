"""Real arm descriptions from example-robot-data, as a user would bring them: the UR10 (ROS-Industrial
frames: zero pose pointing up, axes along y, rotated tool0) and the Panda with its hand (a mimic
finger off the chain). Dynamics equal Pinocchio's reduced model; the UR closed form is recognised
on the real UR5 and UR10 and every solution reaches the target."""
from pathlib import Path

import numpy as np
import pytest

import kiloloop as kl

from robot_files import erd_robots_dir as robots_dir

pin = pytest.importorskip("pinocchio")

SEED = 11


def urdf(rel: str) -> Path:
    path = robots_dir() / rel
    if not path.is_file():
        pytest.skip(f"{rel} not in this example-robot-data")
    return path


ARMS = {
    # name: (urdf, root, tip, locked)
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "base_link", "tool0", None),
    "panda_hand": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_hand",
                   {"panda_finger_joint1": 0.03, "panda_finger_joint2": 0.021}),
}


def set_q(model, q, jid, value):
    j = model.joints[jid]
    if j.nq == 2:
        q[j.idx_q:j.idx_q + 2] = [np.cos(value), np.sin(value)]
    else:
        q[j.idx_q] = value


@pytest.mark.parametrize("arm", sorted(ARMS))
def test_real_arm_dynamics_equal_pinocchio_reduced_model(arm):
    rel, root, tip, locked = ARMS[arm]
    path = urdf(rel)
    model = kl.RobotModel.from_urdf(str(path), root=root, tip=tip, locked=locked)
    names = list(model.joint_names)
    gravity = np.array([0.0, 0.0, -9.81])
    dyn = kl.Dynamics(model, gravity=tuple(gravity))
    full = pin.buildModelFromXML(path.read_text())
    q_ref = pin.neutral(full)
    lock = [j for j in range(1, full.njoints) if full.names[j] not in names]
    for j in lock:
        set_q(full, q_ref, j, (locked or {}).get(full.names[j], 0.0))
    red = pin.buildReducedModel(full, lock, q_ref)
    red.gravity.linear = gravity
    data = red.createData()
    idx = [red.joints[red.getJointId(n)].idx_v for n in names]
    fid = red.getFrameId(tip)
    # The chain root's pose in Pinocchio's world (fixed frames above it).
    pin.framesForwardKinematics(red, data, pin.neutral(red))
    T_world_root = data.oMf[red.getFrameId(root)].homogeneous.copy()
    assert np.allclose(T_world_root, np.eye(4)), "the test compares in the chain root frame"
    rng = np.random.default_rng(SEED)
    print(f"{arm}: seed {SEED}, folded {[(l, o, round(m, 3)) for l, o, m in model.folded_links]}")
    for k in range(20):
        q = rng.uniform(np.maximum(model.lower, -3), np.minimum(model.upper, 3))
        qd, qdd = rng.uniform(-1.5, 1.5, model.nq), rng.uniform(-2, 2, model.nq)
        pq = pin.neutral(red)
        pv, pa = np.zeros(red.nv), np.zeros(red.nv)
        for n, a, b, c in zip(names, q, qd, qdd):
            jid = red.getJointId(n)
            set_q(red, pq, jid, a)
            pv[red.joints[jid].idx_v], pa[red.joints[jid].idx_v] = b, c
        for ours, theirs, what in [
            (dyn.inverse_dynamics(q, qd, qdd), pin.rnea(red, data, pq, pv, pa)[idx], "inverse_dynamics"),
            (dyn.gravity(q), pin.computeGeneralizedGravity(red, data, pq)[idx], "gravity"),
            (dyn.mass_matrix(q), (lambda M: (np.triu(M) + np.triu(M, 1).T)[np.ix_(idx, idx)])(
                pin.crba(red, data, pq)), "mass_matrix"),
        ]:
            err, scale = np.max(np.abs(ours - theirs)), max(1.0, np.max(np.abs(theirs)))
            assert err <= 1e-8 * scale, f"{arm} {what}: {err:.3g}, seed {SEED} k {k}"
        pin.framesForwardKinematics(red, data, pq)
        assert np.max(np.abs(dyn.forward_kinematics(q) - data.oMf[fid].homogeneous)) <= 1e-10


def test_panda_hand_is_folded_and_the_mimic_finger_locked():
    rel, root, tip, locked = ARMS["panda_hand"]
    model = kl.RobotModel.from_urdf(str(urdf(rel)), root=root, tip=tip, locked=locked)
    assert model.nq == 7
    folded = {link: onto for link, onto, _ in model.folded_links}
    assert folded["panda_leftfinger"] == folded["panda_rightfinger"] == "panda_hand"
    with pytest.raises(ValueError, match="mimic joint 'panda_finger_joint2'"):
        kl.RobotModel.from_urdf(str(urdf(rel)), root=root, tip="panda_rightfinger")


@pytest.mark.parametrize("rel", ["ur_description/urdf/ur5_robot.urdf", "ur_description/urdf/ur10_robot.urdf"])
def test_ur_closed_form_is_used_on_the_real_ur_descriptions(rel):
    model = kl.RobotModel.from_urdf(str(urdf(rel)), root="base_link", tip="tool0")
    arm_ik = kl.ArmIk(model)
    assert arm_ik.solver() == "ur_analytic", arm_ik.analytic_reason()
    assert arm_ik.analytic_reason() == ""
    ik, dyn = kl.UrAnalyticIk(model), kl.Dynamics(model)
    assert ik.deviation < 1e-12
    rng = np.random.default_rng(SEED)
    for k in range(200):
        q_true = rng.uniform(-np.pi, np.pi, 6)
        seed = rng.uniform(-np.pi, np.pi, 6)
        target = dyn.forward_kinematics(q_true)
        sols, status = ik.solve(target, seed)
        assert status == kl.Status.OK and len(sols) >= 1, f"seed {SEED} k {k}"
        for q in sols:
            assert np.max(np.abs(dyn.forward_kinematics(q) - target)) < 1e-9, f"seed {SEED} k {k}"
        wrapped = np.abs(np.remainder(sols - q_true + np.pi, 2 * np.pi) - np.pi)
        assert wrapped.max(axis=1).min() < 1e-7, f"generating configuration missing, seed {SEED} k {k}"
        q, status = arm_ik.solve(target, seed)
        assert status == kl.Status.OK
        assert np.max(np.abs(dyn.forward_kinematics(q) - target)) < 1e-6


def test_panda_says_why_the_closed_form_is_not_used():
    model = kl.RobotModel.from_urdf(str(urdf("panda_description/urdf/panda.urdf")), root="panda_link0",
                                    tip="panda_hand")
    arm_ik = kl.ArmIk(model)
    assert arm_ik.solver() == "numeric"
    assert "6 joints" in arm_ik.analytic_reason()


def test_ur_closed_form_refuses_a_non_ur_chain_saying_why():
    xml = urdf("ur_description/urdf/ur10_robot.urdf").read_text()
    # Tilt the elbow axis: joints 2 and 3 are no longer parallel.
    tilted = xml.replace('<origin rpy="0.0 0.0 0.0" xyz="0.0 -0.1719 0.612"/>',
                         '<origin rpy="0.05 0.0 0.0" xyz="0.0 -0.1719 0.612"/>')
    assert tilted != xml
    model = kl.RobotModel.from_urdf(tilted, root="base_link", tip="tool0")
    with pytest.raises(ValueError, match=r"joint 3 \('elbow_joint'\) axis not parallel to joint 2"):
        kl.UrAnalyticIk(model)
    assert kl.UrAnalyticIk(model, tolerance=0.1).deviation > 1e-3  # loosely UR: a seed only
    arm_ik = kl.ArmIk(model)
    assert arm_ik.solver() == "numeric"
    assert "axis not parallel" in arm_ik.analytic_reason()
