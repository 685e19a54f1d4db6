"""The UR5 MuJoCo plant against oracles computed here from the URDF text and the published DH table.

Proves that MuJoCo's URDF import kept the kinematics and the <inertial> blocks exactly, and that the
plant wires actuators, limits and sensors by joint name.
"""
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.sil.plant import MujocoPlant

ROOT = Path(__file__).resolve().parents[1]
URDF = ROOT / "models" / "ur5" / "ur5.urdf"
OVERLAY = kl.Robot.load("ur5").sim  # the robot file's [sim.*] sections
SEED = 5150
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
          "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
# Standard DH table (a, alpha, d) published by Universal Robots.
DH = [(0.0, np.pi / 2, 0.089159), (-0.425, 0.0, 0.0), (-0.39225, 0.0, 0.0),
      (0.0, np.pi / 2, 0.10915), (0.0, -np.pi / 2, 0.09465), (0.0, 0.0, 0.0823)]


@pytest.fixture(scope="module")
def plant():
    return MujocoPlant(URDF, OVERLAY)


def random_configurations(n, seed=SEED):
    print(f"seed={seed}")
    return np.random.default_rng(seed).uniform(-np.pi, np.pi, size=(n, 6))


# --- independent reference, from the URDF text only -------------------------------------------

def _rot(axis, angle):
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def _origin(element):
    """4x4 transform of an element's <origin> (URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll))."""
    T = np.eye(4)
    o = element.find("origin")
    if o is not None:
        r, p, y = (float(v) for v in o.get("rpy", "0 0 0").split())
        T[:3, :3] = _rot([0, 0, 1], y) @ _rot([0, 1, 0], p) @ _rot([1, 0, 0], r)
        T[:3, 3] = [float(v) for v in o.get("xyz", "0 0 0").split()]
    return T


def _urdf_chain():
    """(joint element, child link element) pairs from the root link down the serial chain."""
    root = ET.parse(URDF).getroot()
    links = {link.get("name"): link for link in root.findall("link")}
    by_parent = {j.find("parent").get("link"): j for j in root.findall("joint")}
    chain, link = [], "base_link"
    while link in by_parent:
        joint = by_parent[link]
        link = joint.find("child").get("link")
        chain.append((joint, links[link]))
    return chain


def _inertial(link):
    """(mass, CoM transform in the link frame, 3x3 inertia about the CoM) or None."""
    el = link.find("inertial")
    if el is None:
        return None
    m = float(el.find("mass").get("value"))
    i = {k: float(v) for k, v in el.find("inertia").attrib.items()}
    inertia = np.array([[i["ixx"], i["ixy"], i["ixz"]],
                        [i["ixy"], i["iyy"], i["iyz"]],
                        [i["ixz"], i["iyz"], i["izz"]]])
    return m, _origin(el), inertia


def reference_mass_matrix(q):
    """M = sum over links of m Jv' Jv + Jw' (R I R') Jw, with the Jacobians of each link's CoM."""
    n = len(q)
    M = np.zeros((n, n))
    T = np.eye(4)
    axes, points = [], []  # world joint axes and points on them, in joint order
    for joint, link in _urdf_chain():
        T = T @ _origin(joint)
        if joint.get("type") == "revolute":
            axis = np.array([float(v) for v in joint.find("axis").get("xyz").split()])
            axes.append(T[:3, :3] @ axis)
            points.append(T[:3, 3].copy())
            R = np.eye(4)
            R[:3, :3] = _rot(axis, q[len(axes) - 1])
            T = T @ R
        inertial = _inertial(link)
        if inertial is None:
            continue
        m, T_link_com, inertia = inertial
        T_com = T @ T_link_com
        Jv, Jw = np.zeros((3, n)), np.zeros((3, n))
        for k, (z, p) in enumerate(zip(axes, points)):
            Jv[:, k] = np.cross(z, T_com[:3, 3] - p)
            Jw[:, k] = z
        I_world = T_com[:3, :3] @ inertia @ T_com[:3, :3].T
        M += m * Jv.T @ Jv + Jw.T @ I_world @ Jw
    return M


def dh_forward_kinematics(q):
    T = np.eye(4)
    for qi, (a, alpha, d) in zip(q, DH):
        ct, st, ca, sa = np.cos(qi), np.sin(qi), np.cos(alpha), np.sin(alpha)
        T = T @ np.array([[ct, -st * ca, st * sa, a * ct],
                          [st, ct * ca, -ct * sa, a * st],
                          [0, sa, ca, d],
                          [0, 0, 0, 1]])
    return T


# --- tests --------------------------------------------------------------------------------------

def test_actuated_joints_and_effort_limits(plant):
    assert plant.joint_names == JOINTS
    assert plant.nq == 6 and plant.model.nu == 6
    effort = {j.get("name"): float(j.find("limit").get("effort"))
              for j, _ in _urdf_chain() if j.get("type") == "revolute"}
    m = plant.model
    for name in JOINTS:
        act = m.actuator(name)
        assert m.jnt_qposadr[act.trnid[0]] == m.joint(name).qposadr[0]
        np.testing.assert_array_equal(act.ctrlrange, [-effort[name], effort[name]])
        np.testing.assert_array_equal(act.forcerange, [-effort[name], effort[name]])
        np.testing.assert_allclose(m.joint(name).range, [-2 * np.pi, 2 * np.pi], rtol=0, atol=1e-15)


def test_masses_and_mass_matrix_match_urdf(plant):
    m = plant.model
    for _, link in _urdf_chain():
        inertial = _inertial(link)
        if inertial is not None:
            assert m.body(link.get("name")).mass[0] == pytest.approx(inertial[0], abs=1e-12)
    assert m.body("base_link").mass[0] == pytest.approx(4.0)
    d = mujoco.MjData(m)
    M = np.zeros((m.nv, m.nv))
    qadr = [m.joint(n).qposadr[0] for n in JOINTS]
    dof = [m.joint(n).dofadr[0] for n in JOINTS]
    for q in random_configurations(20):
        d.qpos[qadr] = q
        mujoco.mj_forward(m, d)
        mujoco.mj_fullM(m, d, M)
        np.testing.assert_allclose(M[np.ix_(dof, dof)], reference_mass_matrix(q), rtol=0, atol=1e-9,
                                   err_msg=f"seed={SEED}, q={q}")


def test_tool0_site_matches_dh_forward_kinematics(plant):
    for q in random_configurations(100):
        plant.reset(q)
        pos, rot = plant.ee_pose()
        T = dh_forward_kinematics(q)
        np.testing.assert_allclose(pos, T[:3, 3], rtol=0, atol=1e-9, err_msg=f"seed={SEED}, q={q}")
        np.testing.assert_allclose(rot, T[:3, :3], rtol=0, atol=1e-9, err_msg=f"seed={SEED}, q={q}")


def test_free_fall_from_rest_stays_finite():
    plant = MujocoPlant(URDF, OVERLAY)
    plant.reset()
    np.testing.assert_allclose(plant.q(), plant.q0, atol=0)
    plant.set_torque(np.zeros(6))
    plant.step(2000)
    assert plant.time() == pytest.approx(2.0)
    assert np.all(np.isfinite(plant.q())) and np.all(np.isfinite(plant.qd()))
    # The arm has fallen under gravity, and the sensors describe the state after the last step.
    assert np.linalg.norm(plant.q() - plant.q0) > 0.1
    qadr = [plant.model.joint(n).qposadr[0] for n in JOINTS]
    dof = [plant.model.joint(n).dofadr[0] for n in JOINTS]
    np.testing.assert_array_equal(plant.q(), plant.data.qpos[qadr])
    np.testing.assert_array_equal(plant.qd(), plant.data.qvel[dof])


def test_wrist_inertias_are_realistic(plant):
    # The URDF in wide circulation has wrist inertias near 0.1 kg m^2 (radius 0.6 instead of 0.06).
    for name in ("wrist_1_link", "wrist_2_link", "wrist_3_link"):
        inertia = plant.model.body(name).inertia
        assert np.all(inertia > 0) and np.max(inertia) < 0.01, name
