"""The quadruped's floating-base MuJoCo plant against oracles computed here from the URDF text:
wiring by joint name, masses and inertias, analytic leg kinematics, static equilibrium on flat and
sloped ground (contact forces = weight), push impulses and the IMU's specific-force convention.
"""
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.sil.floating_plant import FloatingBasePlant

MODEL_DIR = kl.models_dir() / "quadruped"
URDF = MODEL_DIR / "quadruped.urdf"
OVERLAY = kl.Robot.load("quadruped").sim  # the robot file's [sim.*] sections
SEED = 1207
LEGS = {"FL": (1, 1), "FR": (1, -1), "RL": (-1, 1), "RR": (-1, -1)}  # (sx, sy)
JOINTS = [f"{leg}_{j}" for leg in LEGS for j in ("hip_abd", "hip_pitch", "knee")]
FEET = [f"{leg}_foot" for leg in LEGS]
G = 9.81
TOTAL_MASS = 10.0 + 4 * (0.6 + 1.0 + 0.25 + 0.05)
FOOT_RADIUS = 0.02
STAND_DEPTH = 2 * 0.25 * np.cos(0.9)  # foot centre below the hip pitch axis at (0, 0.9, -1.8)


@pytest.fixture(scope="module")
def plant():
    return FloatingBasePlant(URDF, OVERLAY)


def urdf_root():
    return ET.parse(URDF).getroot()


def hold_pose(plant, seconds, kp=200.0, kd=4.0):
    """Joint PD on the standing pose, no gravity compensation."""
    for _ in range(int(round(seconds / plant.timestep))):
        plant.set_torque(kp * (plant.q0 - plant.joint_q()) - kd * plant.joint_qd())
        plant.step()


def quat_to_mat(quat):
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, np.asarray(quat, dtype=float))
    return R.reshape(3, 3)


def rot(axis, angle):
    c, s = np.cos(angle), np.sin(angle)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])  # y


def foot_in_trunk(leg, q_leg):
    """Analytic FK of one leg: hip_abd Rx(q1) at (sx 0.2, sy 0.08, 0), hip pitch Ry(q2) at
    (0, sy 0.07, 0), knee Ry(q3) 0.25 below, foot 0.25 below the knee."""
    sx, sy = LEGS[leg]
    q1, q2, q3 = q_leg
    a, b = q2, q2 + q3
    in_hip = np.array([-0.25 * (np.sin(a) + np.sin(b)), sy * 0.07,
                       -0.25 * (np.cos(a) + np.cos(b))])
    return np.array([sx * 0.2, sy * 0.08, 0.0]) + rot("x", q1) @ in_hip


# --- structure ----------------------------------------------------------------------------------

def test_joints_in_urdf_order_with_effort_ctrlrange(plant):
    assert plant.joint_names == JOINTS
    assert plant.nq == 12 and plant.model.nu == 12
    assert plant.model.nq == 19 and plant.model.nv == 18  # free joint + 12 hinges
    assert list(plant.feet) == FEET
    m = plant.model
    joints = {j.get("name"): j for j in urdf_root().findall("joint")}
    for name in JOINTS:
        limit = joints[name].find("limit")
        effort = float(limit.get("effort"))
        act = m.actuator(name)
        assert act.trnid[0] == m.joint(name).id
        np.testing.assert_array_equal(act.ctrlrange, [-effort, effort])
        np.testing.assert_array_equal(act.forcerange, [-effort, effort])
        np.testing.assert_array_equal(m.joint(name).range,
                                      [float(limit.get("lower")), float(limit.get("upper"))])
    np.testing.assert_array_equal(plant.q0, np.tile([0.0, 0.9, -1.8], 4))


def test_masses_and_inertias_match_urdf(plant):
    m = plant.model
    for link in urdf_root().findall("link"):
        inertial = link.find("inertial")
        body = m.body(link.get("name"))
        assert body.mass[0] == pytest.approx(float(inertial.find("mass").get("value")), abs=1e-12)
        com = [float(v) for v in inertial.find("origin").get("xyz").split()]
        np.testing.assert_allclose(body.ipos, com, rtol=0, atol=1e-12)
        i = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}
        expected = np.array([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]],
                             [i["ixz"], i["iyz"], i["izz"]]])
        # MuJoCo stores principal moments and the principal axes' orientation.
        R = quat_to_mat(body.iquat)
        np.testing.assert_allclose(R @ np.diag(body.inertia) @ R.T, expected, rtol=0, atol=1e-12,
                                   err_msg=link.get("name"))
    R = quat_to_mat(m.body("trunk").iquat)
    np.testing.assert_allclose(R @ np.diag(m.body("trunk").inertia) @ R.T,
                               np.diag([0.1, 0.2, 0.15]), rtol=0, atol=1e-12)
    assert plant.total_mass == pytest.approx(TOTAL_MASS, abs=1e-12)
    assert plant.total_mass == pytest.approx(mujoco.mj_getTotalmass(m), abs=0)


def test_kiloloop_model_loads_with_root_inertia():
    model = kl.RobotModel.from_urdf(str(URDF))
    plant = FloatingBasePlant(URDF, OVERLAY)
    assert model.root_inertia_restored
    assert model.root_name == "trunk"
    assert list(model.joint_names) == plant.joint_names
    assert model.total_mass == pytest.approx(plant.total_mass, rel=1e-12)
    np.testing.assert_array_equal(model.effort_limit, plant.effort)
    np.testing.assert_array_equal(model.lower, np.tile([-0.8, -1.2, -2.7], 4))
    np.testing.assert_array_equal(model.upper, np.tile([0.8, 3.0, -0.5], 4))


# --- kinematics ---------------------------------------------------------------------------------

def test_standing_pose_puts_feet_on_the_ground_below_the_hips(plant):
    plant.reset()
    pos, quat = plant.base_pose()
    np.testing.assert_allclose(pos, [0.0, 0.0, STAND_DEPTH + FOOT_RADIUS], rtol=0, atol=1e-6)
    np.testing.assert_array_equal(quat, [1.0, 0.0, 0.0, 0.0])
    expected = [[sx * 0.2, sy * 0.15, FOOT_RADIUS] for sx, sy in LEGS.values()]
    np.testing.assert_allclose(plant.foot_positions(), expected, rtol=0, atol=1e-6)
    assert STAND_DEPTH == pytest.approx(0.311, abs=5e-4)
    # without [base] pos0 the plant computes the same height from the feet's geometry
    overlay = kl.Robot.load("quadruped").sim
    del overlay["base"]
    auto = FloatingBasePlant(URDF, overlay)
    np.testing.assert_allclose(auto.base_pos0, plant.base_pos0, rtol=0, atol=1e-6)
    np.testing.assert_allclose(auto.foot_positions()[:, 2], FOOT_RADIUS, rtol=0, atol=1e-12)


def test_foot_positions_match_analytic_leg_kinematics(plant):
    print(f"seed={SEED}")
    rng = np.random.default_rng(SEED)
    lower, upper = np.tile([-0.8, -1.2, -2.7], 4), np.tile([0.8, 3.0, -0.5], 4)
    for _ in range(50):
        q = rng.uniform(lower, upper)
        base_pos = rng.uniform(-1, 1, 3)
        base_quat = rng.normal(size=4)
        base_quat /= np.linalg.norm(base_quat)
        plant.reset(q, base_pos, base_quat)
        R = quat_to_mat(base_quat)
        expected = [base_pos + R @ foot_in_trunk(leg, q[3 * k:3 * k + 3])
                    for k, leg in enumerate(LEGS)]
        np.testing.assert_allclose(plant.foot_positions(), expected, rtol=0, atol=1e-12,
                                   err_msg=f"seed={SEED} q={q}")
        np.testing.assert_allclose(plant.joint_q(), q, rtol=0, atol=1e-15)


def test_foot_positions_are_the_sphere_centres_at_the_feet_offset():
    # feet.offset (the controller's foot_offset: ANYmal's sphere sits up the shank): each foot's
    # reported position is its link origin + R_foot offset.
    offset = np.array([0.01, -0.005, 0.03])
    shifted = FloatingBasePlant(URDF, {**OVERLAY, "feet": {**OVERLAY["feet"], "offset": offset}})
    rng = np.random.default_rng(SEED)
    for _ in range(5):
        shifted.reset(rng.uniform(np.tile([-0.8, -1.2, -2.7], 4), np.tile([0.8, 3.0, -0.5], 4)))
        d, ids = shifted.data, shifted._foot_ids
        expected = d.xpos[ids] + np.einsum("fij,j->fi", d.xmat[ids].reshape(-1, 3, 3), offset)
        np.testing.assert_allclose(shifted.foot_positions(), expected, rtol=0, atol=1e-15)
        assert np.min(np.linalg.norm(shifted.foot_positions() - d.xpos[ids], axis=1)) > 0.03


# --- contact and statics ------------------------------------------------------------------------

def test_drop_then_stand_contact_forces_carry_the_weight():
    plant = FloatingBasePlant(URDF, OVERLAY)
    plant.reset(base_pos=plant.base_pos0 + [0.0, 0.0, 0.05])
    assert not np.any(plant.foot_contact_forces())  # in the air
    hold_pose(plant, 3.0)
    weight = plant.total_mass * G
    forces = plant.foot_contact_forces()
    print("foot forces [N]:", forces.round(3), "weight", weight)
    assert np.all(forces[:, 2] > 0.15 * weight)  # all four feet carry load
    assert forces[:, 2].sum() == pytest.approx(weight, rel=0.02)
    np.testing.assert_allclose(forces.sum(axis=0)[:2], 0.0, atol=0.01 * weight)
    # only the feet touch the floor, and the robot is at rest
    m, d = plant.model, plant.data
    feet_geoms = {m.geom(f"{f}_geom").id for f in FEET}
    assert d.ncon == 4
    assert all({d.contact[i].geom1, d.contact[i].geom2} - {m.geom("floor").id} <= feet_geoms
               for i in range(d.ncon))
    v, w = plant.base_velocity()
    assert np.linalg.norm(v) < 1e-3 and np.linalg.norm(w) < 1e-3
    # the PD sags a little under the load: the trunk stays within 2 cm of the standing height
    assert plant.base_pose()[0][2] == pytest.approx(STAND_DEPTH + FOOT_RADIUS, abs=0.02)


def test_standing_on_a_5_degree_slope():
    slope = np.deg2rad(5.0)
    plant = FloatingBasePlant(URDF, OVERLAY, slope_deg=5.0)
    normal = np.array([-np.sin(slope), 0.0, np.cos(slope)])
    np.testing.assert_allclose(plant.ground_normal(), normal, rtol=0, atol=1e-15)
    floor = plant.model.geom("floor").id
    np.testing.assert_allclose(plant.data.geom_xmat[floor].reshape(3, 3)[:, 2], normal, atol=1e-12)
    # reset: the standing pose rotated with the ground, so every foot sphere just touches it
    plant.reset()
    # (1e-6: sim.toml gives the standing height to 6 decimals)
    np.testing.assert_allclose(plant.foot_positions() @ normal, FOOT_RADIUS, rtol=0, atol=1e-6)
    _, quat = plant.base_pose()
    np.testing.assert_allclose(quat_to_mat(quat)[:, 2], normal, atol=1e-12)  # trunk aligned
    weight = plant.total_mass * G
    hold_pose(plant, 2.0)
    feet_before = plant.foot_positions()
    hold_pose(plant, 1.0)
    forces = plant.foot_contact_forces()
    print("foot forces [N]:", forces.round(3), "weight", weight)
    # the ground carries the weight along world z: no net horizontal force
    np.testing.assert_allclose(forces.sum(axis=0), [0.0, 0.0, weight], rtol=0, atol=0.02 * weight)
    normal_part = forces @ normal
    tangential = np.linalg.norm(forces - np.outer(normal_part, normal), axis=1)
    assert np.all(normal_part > 0.15 * weight)
    assert np.all(tangential <= 0.8 * normal_part * (1 + 1e-6))  # inside the friction cone
    assert np.all(tangential > 0)  # friction holds the robot on the incline
    # static friction holds: no foot slides more than 0.1 mm in the last second
    assert np.max(np.linalg.norm(plant.foot_positions() - feet_before, axis=1)) < 1e-4


def test_imu_reads_specific_force_and_current_state():
    plant = FloatingBasePlant(URDF, OVERLAY)
    hold_pose(plant, 4.0)  # the sag from the reset pose dies out in about 3 s
    imu = plant.imu()
    pos, quat = plant.base_pose()
    R = quat_to_mat(quat)
    # at rest the accelerometer reads the ground's support: +g along the body's up axis
    np.testing.assert_allclose(imu["accel"], R.T @ [0.0, 0.0, G], rtol=0, atol=2e-3)
    assert imu["accel"][2] == pytest.approx(G, abs=0.01)
    np.testing.assert_allclose(imu["gyro"], 0.0, atol=1e-3)
    np.testing.assert_allclose(imu["quat"], quat, rtol=0, atol=1e-12)
    # after step() the encoders, gyro and orientation describe the current state
    plant.set_torque(np.full(12, 5.0))
    plant.step(3)
    d = plant.data
    np.testing.assert_array_equal(plant.joint_q(), d.qpos[7:])
    np.testing.assert_array_equal(plant.joint_qd(), d.qvel[6:])
    np.testing.assert_allclose(plant.imu()["quat"], d.qpos[3:7], rtol=0, atol=1e-12)
    np.testing.assert_allclose(plant.imu()["gyro"], plant.base_velocity()[1], rtol=0, atol=1e-12)
    # free fall: specific force zero
    air = FloatingBasePlant(URDF, OVERLAY, floor=False)
    air.step(10)
    np.testing.assert_allclose(air.imu()["accel"], 0.0, atol=1e-9)
    assert air.base_velocity()[0][2] == pytest.approx(-G * air.time(), rel=1e-9)


def test_push_changes_momentum_by_the_impulse():
    plant = FloatingBasePlant(URDF, OVERLAY, floor=False)  # in the air: no friction to fight
    plant.reset()
    force, duration = np.array([60.0, -30.0, 0.0]), 0.05
    v0 = plant.base_velocity()[0]
    plant.apply_push(force, duration)
    hold_pose(plant, duration)
    d = plant.data
    assert np.any(d.xfrc_applied)  # the last push step has just been applied
    hold_pose(plant, 0.3)  # the legs catch up with the trunk
    np.testing.assert_array_equal(d.xfrc_applied, 0.0)
    impulse = force * duration
    dv_expected = impulse / plant.total_mass
    # whole-body momentum: the impulse (gravity acts along z only), up to the integrator's
    # O(dt^2) drift of the discrete momentum while the legs move (measured 1.4e-6 relative)
    mujoco.mj_subtreeVel(plant.model, d)
    com_v = d.subtree_linvel[plant.model.body("trunk").id]
    np.testing.assert_allclose(com_v[:2] * plant.total_mass, impulse[:2], rtol=1e-4)
    # the trunk moves with the body once the legs have caught up
    dv = plant.base_velocity()[0] - v0
    print("base dv", dv, "expected", dv_expected)
    np.testing.assert_allclose(dv[:2], dv_expected[:2], rtol=0.05)


# --- bad input ----------------------------------------------------------------------------------

def test_bad_inputs_raise(plant):
    with pytest.raises(ValueError, match="tau"):
        plant.set_torque(np.zeros(11))
    with pytest.raises(ValueError, match="base_quat"):
        plant.reset(base_quat=np.zeros(4))
    with pytest.raises(ValueError, match="force_world"):
        plant.apply_push([1.0, 2.0], 0.1)
    with pytest.raises(ValueError, match="duration"):
        plant.apply_push([1.0, 0.0, 0.0], -0.1)
    with pytest.raises(ValueError, match="unknown section"):
        FloatingBasePlant(URDF, {"nonsense": {}})
    with pytest.raises(ValueError, match="feet"):
        FloatingBasePlant(URDF, OVERLAY, feet=("FL_foot", "nose"))
    plant.reset()
