"""Any 12-DoF quadruped from a minimal robot file (name, kind, urdf, package_dirs, [legs]):
derivation checked against Pinocchio, a clear error for swapped feet, MuJoCo accepts Go1's dummy
root link, and a generated light quadruped (knee offsets along the hip axis, forward knees)
stands and trots in SIL, and stand poses derived within the joint limits on both knee bends."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.robot.quadruped import controller_config, plant_overlay
from kiloloop.sil.floating_plant import FloatingBasePlant

from quadruped_robots import (forward_knee_quadruped_urdf, go1_robot_file, light_quadruped_urdf,
                              minimal_robot_file, pinocchio_com_and_inertia)


def controller_for(robot):
    return kl.QuadrupedController(robot.model(), controller_config(robot))


def assert_criteria(result):
    for name, c in result.criteria.items():
        assert c["passed"], f"{result.scenario}: {name} = {c['value']} (needs {c['op']} {c['threshold']})"


@pytest.fixture(scope="module")
def go1(tmp_path_factory):
    path = go1_robot_file(tmp_path_factory.mktemp("go1"))
    if path is None:
        pytest.skip("example-robot-data not installed")
    return kl.Robot.load(path)


@pytest.fixture(scope="module")
def light(tmp_path_factory):
    d = tmp_path_factory.mktemp("light")
    urdf = light_quadruped_urdf(d / "light_dog.urdf")
    return kl.Robot.load(minimal_robot_file(d, "light_dog", urdf))


@pytest.mark.parametrize("which", ["go1", "light", "quadruped"])
def test_composite_inertia_and_com_match_pinocchio(which, request):
    pytest.importorskip("pinocchio")
    robot = kl.Robot.load("quadruped") if which == "quadruped" else request.getfixturevalue(which)
    c = controller_for(robot)
    q = dict(zip(c.joint_names, np.asarray(c.stand_pose)))
    # The URDF as kiloloop reads it (Go1's 1e-6 kg root link repaired: robot/urdf_doc.py).
    with robot.urdf_doc.as_file() as urdf:
        com, inertia, mass = pinocchio_com_and_inertia(urdf, q, robot.section("legs")["base"])
    assert c.mass == pytest.approx(mass, rel=1e-9)
    np.testing.assert_allclose(c.com, com, atol=1e-9)
    np.testing.assert_allclose(c.inertia, inertia, atol=1e-9)


def test_light_robot_derivation(light):
    c = controller_for(light)
    d = c.config
    assert 2.4 < d.mass < 2.7
    assert d.foot_radius == pytest.approx(0.012)
    assert all(k == kl.KneeDirection.FORWARD for k in d.knees)
    # Forward knees: the knee joint bends positive, the thigh leans back.
    stand = np.asarray(c.stand_pose).reshape(4, 3)
    assert np.all(stand[:, 2] > 0) and np.all(stand[:, 1] < 0)
    # Each foot below its hip at the derived height, the knee offset along the hip axis included.
    for i in range(4):
        foot = c.foot_position(i, stand[i])
        assert foot[2] == pytest.approx(-(d.body_height - d.foot_radius), abs=1e-9)


def forward_knee_robot(directory, **kwargs):
    urdf = forward_knee_quadruped_urdf(directory / "forward_knee_dog.urdf", **kwargs)
    return kl.Robot.load(minimal_robot_file(directory, "forward_knee_dog", urdf))


def assert_stands_within_limits(c, robot):
    """Every leg's stand and crouch pose inside the URDF's joint limits, each foot
    body_height - foot_radius below the trunk origin standing."""
    model = robot.model()
    index = {n: k for k, n in enumerate(model.joint_names)}
    lower = np.asarray(model.lower)[[index[n] for n in c.joint_names]]
    upper = np.asarray(model.upper)[[index[n] for n in c.joint_names]]
    for pose in (np.asarray(c.stand_pose), np.asarray(c.crouch_pose)):
        assert np.all(pose >= lower - 1e-12) and np.all(pose <= upper + 1e-12), pose
    stand = np.asarray(c.stand_pose).reshape(4, 3)
    for i in range(4):
        assert c.foot_position(i, stand[i])[2] == pytest.approx(
            -(c.config.body_height - c.config.foot_radius), abs=1e-9)


def test_forward_knees_with_a_sliver_of_backward_bend_stand_forward(tmp_path):
    """Knee limits [0, pi] with each foot 1 cm ahead of its shank's line also allow 0.04 rad of
    backward bend. The knee bend chosen stands: forward. Before, an unreachable IK (a
    degradation status, not a failure) passed as a solution: the knees were resolved backward
    and the derived stand pose was all zeros (straight legs), and the 27 kg robot fell in every
    scenario."""
    robot = forward_knee_robot(tmp_path)
    c = controller_for(robot)
    assert 26 < c.config.mass < 28
    assert all(k == kl.KneeDirection.FORWARD for k in c.config.knees)
    assert c.config.stand_extension == pytest.approx(0.58)  # the limits allow the default
    stand = np.asarray(c.stand_pose).reshape(4, 3)
    assert np.all(stand[:, 2] > 0.5) and np.all(stand[:, 1] < -0.3)
    assert_stands_within_limits(c, robot)


def test_stand_height_moves_where_the_hip_limit_forbids_the_default(tmp_path):
    """A hip pitch that turns only 0.9 rad forward cannot put a forward-knee foot under the hip at
    0.58 of the leg (the thigh would lean 0.95 rad forward) nor lift it from there: the derived
    stand extension moves up to where every leg stands and lifts its foot within its limits."""
    robot = forward_knee_robot(tmp_path, hip_lower=-0.9)
    c = controller_for(robot)
    assert 0.6 < c.config.stand_extension <= 0.9
    assert_stands_within_limits(c, robot)
    # The swing apex (swing_height above the stand) is reachable too.
    stand = np.asarray(c.stand_pose).reshape(4, 3)
    assert np.all(stand[:, 1] >= -0.9)


def test_no_standing_height_within_the_limits_is_refused_by_name(tmp_path):
    """A hip pitch that turns only 0.5 rad forward: a forward-knee foot fits under the hip only
    near a straight leg, with no room to lift it. Refused at configure, naming the leg and its
    limits, instead of a stand pose outside them."""
    robot = forward_knee_robot(tmp_path, hip_lower=-0.5)
    with pytest.raises(Exception, match=r"no standing height within the joint limits: leg 'FL_foot'"
                                        r".*hip pitch limits \[-0\.5, 2\.5\] rad"):
        controller_for(robot)


# Stands, and on the 5 deg slope. Its 20 s trot still falls (seed 0 at 17.7 s, roll/pitch 7.6 deg
# RMS), where the same robot mirrored to backward knees passes: docs/robots.md.
@pytest.mark.parametrize("name,duration", [("quadruped-stand", 2.0), ("quadruped-slope", None)])
def test_forward_knee_robot_stands(tmp_path, name, duration):
    r = scenarios.run_named(name, forward_knee_robot(tmp_path), seed=0, duration=duration)
    print(name, {k: round(v, 4) for k, v in r.metrics.items() if isinstance(v, float)})
    assert_criteria(r)


def test_swapped_feet_are_refused_with_the_reason(tmp_path, go1):
    feet = ["FR_foot", "FL_foot", "RL_foot", "RR_foot"]
    robot = kl.Robot.load(minimal_robot_file(tmp_path, "go1_swapped", go1.urdf, go1.package_dirs,
                                             feet=feet))
    with pytest.raises(ValueError, match="'FR_foot' is listed as front-left"):
        controller_for(robot)


def test_go1_plant_repairs_the_dummy_root_and_keeps_mass(go1):
    c = controller_for(go1)
    plant = FloatingBasePlant(go1.urdf, plant_overlay(go1, c), package_dirs=go1.package_dirs)
    assert any("link 'base'" in n and "inertia repaired" in n for n in plant.notes)
    assert float(np.sum(plant.model.body_mass)) == pytest.approx(c.mass, rel=1e-6)
    # Start height from the geometry: the feet touch the floor.
    bottom = plant.foot_positions()[:, 2] - c.config.foot_radius
    assert np.max(np.abs(bottom)) < 1e-6


# The light robot trots at 0.3 m/s: its 0.28 m legs at 0.5 m/s would be a Froude number
# v^2 / (g L) of 0.09, against 0.05 for the 17.6 kg model at 0.5 m/s (0.3 m/s: 0.033). Measured:
# at 0.5 m/s it rolls +-3 deg and falls with the 10 ms delay (the swing legs' own torques read as
# early touch-downs at its 3.6 N contact threshold).
@pytest.mark.parametrize("name,sets", [("quadruped-stand", {}), ("quadruped-trot", {"speed": 0.3})])
def test_light_robot_stands_and_trots(light, name, sets):
    r = scenarios.run_named(name, light, sets, seed=0, duration=6.0 if name == "quadruped-trot" else 3.0)
    print(name, {k: round(v, 4) for k, v in r.metrics.items() if isinstance(v, float)})
    assert_criteria(r)


@pytest.mark.parametrize("name", ["quadruped-stand", "quadruped-trot", "quadruped-push",
                                  "quadruped-slope", "quadruped-tilt-stop"])
def test_go1_from_a_minimal_robot_file(go1, name):
    duration = {"quadruped-trot": 6.0, "quadruped-stand": 2.0, "quadruped-slope": 3.0}.get(name)
    r = scenarios.run_named(name, go1, seed=0, duration=duration)
    print(name, {k: round(v, 4) for k, v in r.metrics.items() if isinstance(v, float)})
    assert_criteria(r)


# The issue's push, 6 N s per 15 kg: with the QP's moment weights fixed at 100 Go1 (moments cost
# 3x less against forces than on our model) swayed 86 mm sideways on one diagonal and rolled
# 5.10 deg (limit 5); derived from its mass, inertia and CoM height, 1.63 deg peak.
def test_go1_recovers_from_the_issues_push(go1):
    r = scenarios.run_named("quadruped-push", go1, {"impulse_per_kg": 0.4}, seed=0)
    print(r.metrics)
    assert_criteria(r)


# A foot held up by ground higher than the estimate (soft ground: the stance feet sink after
# their footholds latch; stones: a higher stone) read more clearance than the touch-down
# test allows and was never loaded: Go1 fell within 1 s on soft ground, 0.3 m into the stones,
# our model 2 m into them. Now a late foot's reach counts (quadruped_controller.cpp).
@pytest.mark.parametrize("which,name,duration", [("go1", "quadruped-compliant", 4.5),
                                                 ("go1", "quadruped-stones", 4.5),
                                                 ("quadruped", "quadruped-stones", 10.0)])
def test_trots_on_ground_higher_than_estimated(which, name, duration, request):
    robot = kl.Robot.load("quadruped") if which == "quadruped" else request.getfixturevalue(which)
    r = scenarios.run_named(name, robot, seed=0, duration=duration)
    print(name, {k: round(v, 4) for k, v in r.metrics.items() if isinstance(v, float)})
    assert_criteria(r)
    assert r.metrics["stances"] >= 12  # really trotted: >= 3 steps per leg were judged


@pytest.mark.parametrize("which", ["quadruped", "go1"])
def test_qp_moment_weights_are_derived(which, request):
    robot = kl.Robot.load("quadruped") if which == "quadruped" else request.getfixturevalue(which)
    c = controller_for(robot)
    cfg = c.config
    lever = cfg.body_height + np.asarray(c.com)[2]  # CoM above the ground, standing
    expected = (cfg.mass * lever / np.asarray(cfg.inertia_diag)) ** 2
    assert np.asarray(cfg.force.wrench_weight)[3:] == pytest.approx(expected, rel=1e-12)
    assert np.asarray(cfg.force.wrench_weight)[:3] == pytest.approx([1.0, 1.0, 1.0])
    # Given values are kept.
    given = controller_config(robot)
    force = given.force
    force.wrench_weight = [1, 1, 1, 100, 100, 100]
    given.force = force
    cfg = kl.QuadrupedController(robot.model(), given).config
    assert np.asarray(cfg.force.wrench_weight)[3:] == pytest.approx([100, 100, 100])


# 35 ms command delay: standing holds on both robots (the state predicted over the delay with the
# commands in flight, loop bandwidths bounded by the delay). Trotting at 35 ms passes on our model
# (gait schedule for the commands, joint-level Smith predictor on the swing legs) and on Go1
# (seeds 0-4: bench/quadruped_matrix_realistic_seeds.md).
@pytest.mark.parametrize("which", ["quadruped", "go1"])
def test_stands_with_a_35ms_command_delay(which, request):
    robot = kl.Robot.load("quadruped") if which == "quadruped" else request.getfixturevalue(which)
    r = scenarios.run_named("quadruped-stand", robot, {"motor_delay": 0.035}, seed=0, duration=2.0)
    print(which, r.metrics)
    assert_criteria(r)


def test_our_model_trots_with_a_35ms_command_delay():
    # Without the swing predictor the feet were still 50-60 mm up at touch-down and it fell.
    # Realistic sensors (the default; this 5 s run once missed with them while the gyro bias was
    # learnt, 1.99 deg roll/pitch RMS): measured 0.65 deg since the attitude filter learns it.
    r = scenarios.run_named("quadruped-trot", kl.Robot.load("quadruped"),
                            {"motor_delay": 0.035}, seed=0, duration=5.0)
    print(r.metrics)
    assert_criteria(r)


# Go1 at 25 ms: with the trunk predictor on the composite inertia its roll rang at 9-11 Hz and it
# fell within 2 s; turned with the swing legs free (legs: 59 % of its mass) it trots at 0.29 deg.
def test_go1_trots_with_a_25ms_command_delay(go1):
    r = scenarios.run_named("quadruped-trot", go1, {"motor_delay": 0.025}, seed=0, duration=5.0)
    print(r.metrics)
    assert_criteria(r)


# Go1 at 30 ms: with the trunk's rotation predicted from the contact moment over a rigid inertia
# its roll rang at 10 Hz and it fell (realistic sensors; ideal: a +-3 deg limit cycle); predicted
# from the joint torques in flight through the legs' dynamics (trunk_rotation.hpp) it trots.
def test_go1_trots_with_a_30ms_command_delay(go1):
    r = scenarios.run_named("quadruped-trot", go1, {"motor_delay": 0.030}, seed=0, duration=5.0)
    print(r.metrics)
    assert_criteria(r)


@pytest.mark.parametrize("which", ["quadruped", "go1"])
def test_stands_on_a_15_degree_slope(which, request):
    robot = kl.Robot.load("quadruped") if which == "quadruped" else request.getfixturevalue(which)
    r = scenarios.run_named("quadruped-slope", robot, {"slope_deg": 15.0}, seed=0)
    print(which, r.metrics)
    assert_criteria(r)


# The inertia the Smith predictor turns the trunk with (swing legs free, quadruped_controller.hpp
# predict_legs_free): all legs free it is the floating base's articulated-body inertia, which
# MuJoCo's mass matrix gives as the Schur complement over the joints (about the CoM: the linear
# part eliminated too), in the controller's standing pose.
@pytest.mark.parametrize("which", ["go1", "quadruped"])
def test_free_leg_inertia_matches_mujoco_mass_matrix(which, request):
    import mujoco

    robot = kl.Robot.load("quadruped") if which == "quadruped" else request.getfixturevalue(which)
    c = controller_for(robot)
    plant = FloatingBasePlant(robot.urdf, plant_overlay(robot, c), package_dirs=robot.package_dirs)
    m, d = plant.model, plant.data
    stand = dict(zip(c.joint_names, np.asarray(c.stand_pose)))
    for name, q in stand.items():
        d.qpos[m.jnt_qposadr[m.joint(name).id]] = q
    d.qpos[plant._free_q + 3:plant._free_q + 7] = [1, 0, 0, 0]
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    base = list(range(plant._free_d, plant._free_d + 6))
    joints = [i for i in range(m.nv) if i not in base]
    B, C, J = M[np.ix_(base, base)], M[np.ix_(base, joints)], M[np.ix_(joints, joints)]

    def rotational_about_com(S):  # free joint: linear velocity first, angular in the body frame
        return S[3:, 3:] - S[3:, :3] @ np.linalg.solve(S[:3, :3], S[:3, 3:])

    composite = rotational_about_com(B)
    free = rotational_about_com(B - C @ np.linalg.solve(J, C.T))
    print(which, np.diag(composite), np.diag(free), np.diag(c.inertia_free))
    np.testing.assert_allclose(np.asarray(c.inertia), composite, atol=2e-3 * composite.max())
    np.testing.assert_allclose(np.asarray(c.inertia_free), free, atol=2e-3 * composite.max())
    assert np.asarray(c.inertia_free)[0, 0] < 0.5 * composite[0, 0]  # roll: the legs' share
