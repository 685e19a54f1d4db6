"""What an arm's actuators add to its URDF (robot/arm.py armature()): a joint whose URDF declares
its losses (<dynamics> damping or friction) gets a geared actuator's reflected rotor inertia, in
the plant and in every controller's model alike; a URDF without losses stays the rigid body. And
what the arm scenarios do with robots of other sources than kiloloop's (example-robot-data's
xArm7, kiloloop's geometry-free Panda): they pass, or refuse at start, never report NaN."""
import math

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.errors import ScenarioRefused
from kiloloop.robot import arm as arm_defaults
from kiloloop.sil.arm_family import build_plant

from robot_files import erd_urdf, minimal_arm, write_robot_file

XARM7 = ("xarm_description/urdf/xarm7.urdf", "link_base", "link7")


def xarm7(tmp_path):
    urdf = erd_urdf(XARM7[0])
    if not urdf.is_file():
        pytest.skip("xarm7 not in this example-robot-data")
    return minimal_arm(tmp_path, urdf, XARM7[1], XARM7[2], name="xarm7")


def own_panda(tmp_path):
    """The README's robot file for models/panda (a URDF with neither <dynamics> nor geometry)."""
    urdf = kl.models_dir() / "panda" / "panda.urdf"
    return write_robot_file(tmp_path, f'name = "my_arm"\nkind = "arm"\nurdf = "{urdf}"\n'
                                      '[chain]\nroot = "panda_link0"\ntip = "panda_link8"\n')


def test_armature_is_derived_where_the_urdf_declares_losses_and_given_wins(tmp_path):
    robot = kl.Robot.load(xarm7(tmp_path))
    model = robot.model()
    effort, velocity = np.asarray(model.effort_limit), np.asarray(model.velocity_limit)
    expected = effort * arm_defaults.ROTOR_ACCELERATION_TIME / velocity
    np.testing.assert_allclose(model.armature, expected, rtol=0, atol=0)
    # The plant has the same rotor inertia on the same joints.
    plant = build_plant(robot)
    np.testing.assert_array_equal(plant.model.dof_armature[plant.dof_addresses], expected)
    given = robot.with_overrides({"sim.joints.armature": 0.01})
    np.testing.assert_array_equal(given.model().armature, np.full(model.nq, 0.01))
    # No losses declared (kiloloop's UR5 gives 0 explicitly; the Panda's URDF has none).
    assert not kl.Robot.load("ur5").model().armature.any()
    assert not kl.Robot.load(own_panda(tmp_path)).model().armature.any()


def test_the_model_with_armature_is_the_plants_dynamics(tmp_path):
    """M(q) and the inverse dynamics of the controller's model with armature equal MuJoCo's with
    the same armature: the rigid body's plus a on M's diagonal and a * qdd on the torque."""
    robot = kl.Robot.load(xarm7(tmp_path))
    model = robot.model()
    a = np.asarray(model.armature)
    rigid = kl.RobotModel.from_urdf(robot.urdf_doc.model_source(), XARM7[1], XARM7[2])
    rng = np.random.default_rng(3)
    q, qd, qdd = (rng.uniform(-1, 1, model.nq) for _ in range(3))
    dyn, dyn_rigid = kl.Dynamics(model), kl.Dynamics(rigid)
    np.testing.assert_allclose(dyn.mass_matrix(q), dyn_rigid.mass_matrix(q) + np.diag(a),
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(dyn.inverse_dynamics(q, qd, qdd),
                               dyn_rigid.inverse_dynamics(q, qd, qdd) + a * qdd, atol=1e-9)
    plant = build_plant(robot)
    m, d = plant.model, mujoco.MjData(plant.model)
    d.qpos[plant.qpos_addresses] = q
    mujoco.mj_forward(m, d)
    full = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, full)
    idx = plant.dof_addresses
    np.testing.assert_allclose(full[np.ix_(idx, idx)], dyn.mass_matrix(q), atol=1e-9)


def test_with_armature_refuses_bad_values_naming_the_joint():
    model = kl.Robot.load("ur5").model()
    with pytest.raises(ValueError, match="shoulder_pan_joint"):
        model.with_armature(np.array([-1.0, 0, 0, 0, 0, 0]))
    with pytest.raises(ValueError, match="6 values"):
        model.with_armature(np.zeros(2))


def test_xarm7_tracks_its_quintic_despite_its_urdf_friction(tmp_path):
    """xArm7's URDF declares 1 N m of Coulomb friction on joint 7 (link inertia 1.4e-4 kg m^2):
    the rigid body alone held it radians off (1.375 rad on main); its rotor inertia lets the
    derived gains hold it."""
    result = scenarios.run_named("arm-track", xarm7(tmp_path))
    assert result.criteria["max_joint_error_rad"]["passed"], result.metrics
    assert result.passed, result.criteria


def test_arm_press_on_a_light_seven_joint_arm(tmp_path):
    """models/panda: 0.9 kg of operational-space inertia along the slide, where the UR5 has
    4.5: the slide's stiffness is derived from it (2.2 mm behind the reference on main)."""
    result = scenarios.run_named("arm-press", own_panda(tmp_path))
    assert result.passed, result.criteria


def test_arm_rrt_refuses_a_chain_without_collision_geometry(tmp_path):
    with pytest.raises(ScenarioRefused, match="collision"):
        scenarios.run_named("arm-rrt", own_panda(tmp_path))


def test_arm_estop_that_never_stops_fails_with_figures_not_nan():
    result = scenarios.run_named("arm-estop", overrides=["stopped_speed=1e-300"])
    assert result.metrics["stopped"] == 0
    assert not result.criteria["stopped"]["passed"]
    assert all(math.isfinite(c["value"]) for c in result.criteria.values()), result.criteria
