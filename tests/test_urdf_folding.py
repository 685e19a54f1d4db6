"""Real-URDF loading: whatever hangs off the controlled chain (a gripper beyond the tip on fixed and
on locked movable joints, a mimic finger, a camera mast on link 2) is folded into the chain as
rigid mass, so kl.Dynamics equals Pinocchio's reduced model (every non-chain joint locked at the
same positions) to 1e-8 relative; continuous joints in the chain; the loader's errors name what is
wrong. Pinocchio is used from Python only (its wheel ships its own urdfdom)."""
import numpy as np
import pytest

import kiloloop as kl

pin = pytest.importorskip("pinocchio")

SEED = 20261123
GRAVITY = np.array([0.4, -0.3, -9.81])


def inertial(mass, xyz="0 0 0", rpy="0.1 -0.2 0.3"):
    return (f'<inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{mass}"/>'
            '<inertia ixx="0.021" iyy="0.032" izz="0.027" ixy="0.001" ixz="-0.002" iyz="0.0015"/></inertial>')


def link(name, mass=None, xyz="0 0 0"):
    return f'<link name="{name}">{inertial(mass, xyz) if mass else ""}</link>'


def joint(name, kind, parent, child, xyz="0 0 0", rpy="0 0 0", axis="0 0 1", extra=""):
    limit = ""
    if kind in ("revolute", "prismatic"):
        limit = '<limit lower="-2.5" upper="2.5" velocity="2" effort="100"/>'
    elif kind == "continuous":
        limit = '<limit velocity="3" effort="50"/>'
    ax = f'<axis xyz="{axis}"/>' if kind != "fixed" else ""
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/>{ax}{limit}{extra}</joint>')


def arm(extra_links="", extra_joints="", wrist="revolute", base_mass=4.0):
    """A 5-joint arm base -> tool0 (joint 4 `wrist` type, joint 5 continuous), plus EXTRA."""
    links = (link("base", base_mass, "0 0 0.05") + link("l1", 3.0, "0 0 0.1") + link("l2", 2.5, "0.15 0 0")
             + link("l3", 1.8, "0.12 0.01 0") + link("l4", 0.9, "0 0.02 0.05") + link("l5", 0.5, "0 0 0.03")
             + link("tool0"))
    joints = (joint("j1", "revolute", "base", "l1", "0 0 0.2")
              + joint("j2", "revolute", "l1", "l2", "0 0.05 0.2", "1.5707963 0 0")
              + joint("j3", "revolute", "l2", "l3", "0.35 0 0", "0 0.3 0", "0 0 1")
              + joint("j4", wrist, "l3", "l4", "0.3 0 0", "0 1.5707963 0.2", "0.6 0 0.8")
              + joint("j5", "continuous", "l4", "l5", "0 0 0.12", "-1.5707963 0 0", "0 0 1")
              + joint("flange", "fixed", "l5", "tool0", "0 0 0.08", "0 0 1.5707963"))
    return f'<robot name="folded">{links}{extra_links}{joints}{extra_joints}</robot>'


# A gripper beyond the tip: fixed palm, prismatic fingers (b mimics a), a revolute wrist camera.
GRIPPER_LINKS = (link("palm", 0.7, "0 0 0.03") + link("finger_a", 0.12, "0 0.01 0.04")
                 + link("finger_b", 0.11, "0 -0.01 0.04") + link("wrist_cam", 0.2, "0.02 0 0.01"))
GRIPPER_JOINTS = (joint("palm_joint", "fixed", "tool0", "palm", "0 0 0.02", "0 0 0.7")
                  + joint("finger_a_joint", "prismatic", "palm", "finger_a", "0 0 0.06", axis="0 1 0")
                  + joint("finger_b_joint", "prismatic", "palm", "finger_b", "0 0 0.06", axis="0 -1 0",
                          extra='<mimic joint="finger_a_joint" multiplier="1" offset="0"/>')
                  + joint("cam_tilt", "revolute", "palm", "wrist_cam", "0.05 0 0.02", "0.2 0 0", "1 0 0"))
# A camera mast branching off link 2, with a pan joint and a continuous spinning lidar on top.
MAST_LINKS = link("mast", 0.4, "0 0 0.1") + link("camera", 0.3, "0.02 0 0") + link("lidar", 0.25, "0 0 0.02")
MAST_JOINTS = (joint("mast_joint", "fixed", "l2", "mast", "0.1 0.08 0", "-1.5707963 0 0")
               + joint("pan", "revolute", "mast", "camera", "0 0 0.2")
               + joint("spin", "continuous", "camera", "lidar", "0 0 0.05", axis="0 0 1"))

CASES = {
    # name: (xml, root, tip, locked)
    "gripper_fixed_only": (arm(link("palm", 0.7, "0 0 0.03"), joint("palm_joint", "fixed", "tool0", "palm", "0 0 0.02")),
                           None, "tool0", None),
    "gripper_locked_nonzero": (arm(GRIPPER_LINKS, GRIPPER_JOINTS), "base", "tool0",
                               {"finger_a_joint": 0.031, "finger_b_joint": 0.017, "cam_tilt": -0.6}),
    "gripper_locked_default": (arm(GRIPPER_LINKS, GRIPPER_JOINTS), "base", "tool0", None),
    "mast_off_link2": (arm(MAST_LINKS, MAST_JOINTS), "base", "tool0", {"pan": 0.9, "spin": 2.2}),
    "everything_tip_inside": (arm(GRIPPER_LINKS + MAST_LINKS, GRIPPER_JOINTS + MAST_JOINTS), "base", "l4",
                              {"finger_a_joint": 0.02, "pan": -1.1, "spin": -0.4, "j5": 1.3}),
    "continuous_wrist": (arm(GRIPPER_LINKS, GRIPPER_JOINTS, wrist="continuous"), "base", "tool0",
                         {"cam_tilt": 0.5}),
}


def pin_reduced(xml, chain_joints, locked):
    """Pinocchio's model with every joint not in the chain locked at `locked` (default 0)."""
    full = pin.buildModelFromXML(xml)
    q_ref = pin.neutral(full)
    lock_ids = []
    for jid in range(1, full.njoints):
        name = full.names[jid]
        if name in chain_joints:
            continue
        lock_ids.append(jid)
        set_q(full, q_ref, jid, (locked or {}).get(name, 0.0))
    reduced = pin.buildReducedModel(full, lock_ids, q_ref)
    reduced.gravity.linear = GRAVITY
    return reduced


def set_q(model, q, jid, angle):
    """Writes a joint position into Pinocchio's q: a continuous joint is stored as (cos, sin)."""
    j = model.joints[jid]
    if j.nq == 2:
        q[j.idx_q:j.idx_q + 2] = [np.cos(angle), np.sin(angle)]
    else:
        q[j.idx_q] = angle


def to_pin(model, names, q):
    out = pin.neutral(model)
    for name, value in zip(names, q):
        set_q(model, out, model.getJointId(name), value)
    return out


def to_pin_v(model, names, v):
    out = np.zeros(model.nv)
    for name, value in zip(names, v):
        out[model.joints[model.getJointId(name)].idx_v] = value
    return out


def from_pin_v(model, names, v):
    return np.array([v[model.joints[model.getJointId(n)].idx_v] for n in names])


def close(a, b, what, k):
    err = np.max(np.abs(np.asarray(a) - np.asarray(b)))
    scale = max(1.0, np.max(np.abs(b)))
    assert err <= 1e-8 * scale, f"{what}: error {err:.3g} (scale {scale:.3g}), seed {SEED} sample {k}"


@pytest.mark.parametrize("case", sorted(CASES))
def test_dynamics_equal_pinocchio_reduced_model(case):
    xml, root, tip, locked = CASES[case]
    model = kl.RobotModel.from_urdf(xml, root=root, tip=tip, locked=locked)
    names = list(model.joint_names)
    dyn = kl.Dynamics(model, gravity=tuple(GRAVITY))
    red = pin_reduced(xml, set(names), locked)
    data = red.createData()
    assert red.nv == model.nq
    fid = red.getFrameId(tip)
    rng = np.random.default_rng(SEED)
    print(f"{case}: seed {SEED}")
    for k in range(25):
        q = rng.uniform(-2.0, 2.0, model.nq)
        qd = rng.uniform(-2.0, 2.0, model.nq)
        qdd = rng.uniform(-3.0, 3.0, model.nq)
        pq, pv, pa = to_pin(red, names, q), to_pin_v(red, names, qd), to_pin_v(red, names, qdd)
        tau = from_pin_v(red, names, pin.rnea(red, data, pq, pv, pa))
        close(dyn.inverse_dynamics(q, qd, qdd), tau, f"{case} inverse_dynamics", k)
        g = from_pin_v(red, names, pin.computeGeneralizedGravity(red, data, pq))
        close(dyn.gravity(q), g, f"{case} gravity", k)
        c = from_pin_v(red, names, pin.rnea(red, data, pq, pv, np.zeros(red.nv))) - g
        close(dyn.coriolis(q, qd), c, f"{case} coriolis", k)
        M = pin.crba(red, data, pq)
        M = np.triu(M) + np.triu(M, 1).T
        idx = [red.joints[red.getJointId(n)].idx_v for n in names]
        close(dyn.mass_matrix(q), M[np.ix_(idx, idx)], f"{case} mass_matrix", k)
        pin.framesForwardKinematics(red, data, pq)
        close(dyn.forward_kinematics(q), data.oMf[fid].homogeneous, f"{case} forward_kinematics", k)


def test_folded_links_say_what_went_where():
    xml, root, tip, locked = CASES["everything_tip_inside"]
    model = kl.RobotModel.from_urdf(xml, root=root, tip=tip, locked=locked)
    folded = {link: (onto, mass) for link, onto, mass in model.folded_links}
    assert folded["l5"] == ("l4", 0.5)  # beyond the tip: l5, tool0 and the gripper
    assert folded["finger_b"] == ("l4", pytest.approx(0.11))
    assert folded["mast"][0] == folded["lidar"][0] == "l2"
    assert "l3" not in folded and "base" not in folded
    assert model.locked == locked
    chain_mass = sum(m for _, _, m in model.folded_links)
    assert chain_mass == pytest.approx(0.5 + 0.7 + 0.12 + 0.11 + 0.2 + 0.4 + 0.3 + 0.25)
    # Without a tip beyond the root nothing is folded; kiloloop's own UR5 folds only tool0.
    ur5 = kl.RobotModel.from_urdf(str(kl.models_dir() / "ur5" / "ur5.urdf"))
    assert ur5.folded_links == []


def test_gripper_mass_changes_the_gravity_torques():
    """The mass beyond the tip is not dropped: it loads the shoulder."""
    xml, root, tip, locked = CASES["gripper_locked_nonzero"]
    with_gripper = kl.Dynamics(kl.RobotModel.from_urdf(xml, root=root, tip=tip, locked=locked))
    bare = kl.Dynamics(kl.RobotModel.from_urdf(arm(), root=root, tip=tip))
    q = np.array([0.1, 0.5, -0.4, 0.3, 0.2])
    assert abs(with_gripper.gravity(q)[1] - bare.gravity(q)[1]) > 1.0


def test_mimic_joint_in_the_chain_is_named():
    xml = arm(GRIPPER_LINKS, GRIPPER_JOINTS)
    with pytest.raises(ValueError, match=r"mimic joint 'finger_b_joint' is in the chain"):
        kl.RobotModel.from_urdf(xml, root="base", tip="finger_b")
    # Off the chain it is simply locked.
    assert kl.RobotModel.from_urdf(xml, root="base", tip="tool0").nq == 5


def test_chain_given_tip_to_root_is_refused():
    with pytest.raises(ValueError, match=r"tip->root: tip link 'l1' is an ancestor of root link 'l4'"):
        kl.RobotModel.from_urdf(arm(), root="l4", tip="l1")
    with pytest.raises(ValueError, match=r"different branches"):
        kl.RobotModel.from_urdf(arm(MAST_LINKS, MAST_JOINTS), root="camera", tip="tool0")


def test_unknown_link_and_locked_joint_are_named():
    with pytest.raises(ValueError, match=r"tip link 'tool9' is not in the model \(links: .*l1"):
        kl.RobotModel.from_urdf(arm(), tip="tool9")
    with pytest.raises(ValueError, match=r"root link 'bse' is not in the model"):
        kl.RobotModel.from_urdf(arm(), root="bse", tip="tool0")
    with pytest.raises(ValueError, match=r"locked joint 'pam' is not a joint"):
        kl.RobotModel.from_urdf(arm(MAST_LINKS, MAST_JOINTS), tip="tool0", locked={"pam": 0.1})
    with pytest.raises(ValueError, match=r"locked joint 'j2' is in the chain"):
        kl.RobotModel.from_urdf(arm(), tip="tool0", locked={"j2": 0.1})


def test_continuous_chain_joint_has_no_position_limit():
    model = kl.RobotModel.from_urdf(arm(wrist="continuous"), tip="tool0")
    assert np.isinf(model.lower[3]) and np.isinf(model.upper[3]) and np.isinf(model.upper[4])
    assert model.velocity_limit[4] == 3.0
