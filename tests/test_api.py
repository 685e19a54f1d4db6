"""The public Python API of DESIGN.md: names, shapes, errors."""
import numpy as np
import pytest

import kiloloop as kl


def test_model_from_urdf_exposes_names_and_limits(ur5_model):
    assert ur5_model.nq == 6
    assert ur5_model.joint_names[0] == "shoulder_pan_joint"
    assert ur5_model.lower.shape == (6,) and ur5_model.upper.shape == (6,)
    assert np.all(ur5_model.lower < ur5_model.upper)
    np.testing.assert_array_equal(ur5_model.effort_limit, [150, 150, 150, 28, 28, 28])
    assert ur5_model.root_inertia_restored  # the UR5 base_link carries 4 kg


def test_model_from_xml_string_and_chain_selection(ur5_urdf):
    xml = ur5_urdf.read_text()
    model = kl.RobotModel.from_urdf(xml, root="base_link", tip="wrist_1_link")
    assert model.nq == 4 and model.tip_name == "wrist_1_link"


def test_missing_and_malformed_urdf_raise_clear_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="nope.urdf"):
        kl.RobotModel.from_urdf(str(tmp_path / "nope.urdf"))
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'>")
    with pytest.raises(ValueError, match="bad.urdf"):
        kl.RobotModel.from_urdf(str(bad))
    with pytest.raises(ValueError, match="tip link 'nose'"):
        kl.RobotModel.from_urdf("<robot name='r'><link name='a'><inertial><mass value='1'/>"
                                "<inertia ixx='1' iyy='1' izz='1' ixy='0' ixz='0' iyz='0'/>"
                                "</inertial></link></robot>", tip="nose")
    # A robot without any mass is refused first, naming why (tests/corpus has the rest).
    with pytest.raises(ValueError, match="no mass"):
        kl.RobotModel.from_urdf("<robot name='r'><link name='a'/></robot>", tip="nose")


def test_dynamics_shapes_and_consistency(ur5_model, rng):
    dyn = kl.Dynamics(ur5_model, gravity=(0.0, 0.0, -9.81))
    for _ in range(20):
        q, qd, qdd = rng.uniform(-2, 2, (3, 6))
        tau = dyn.inverse_dynamics(q, qd, qdd)
        M = dyn.mass_matrix(q)
        assert tau.shape == (6,) and M.shape == (6, 6)
        np.testing.assert_allclose(tau, M @ qdd + dyn.coriolis(q, qd) + dyn.gravity(q), atol=1e-10)
    assert dyn.forward_kinematics(q).shape == (4, 4)
    assert dyn.jacobian(q).shape == (6, 6)


@pytest.mark.parametrize("bad", [np.zeros(5), np.zeros((6, 1)), np.zeros((2, 6))])
def test_wrong_shapes_raise_value_error_naming_argument(ur5_model, bad):
    dyn = kl.Dynamics(ur5_model)
    with pytest.raises(ValueError, match=r"qd: expected shape \(6,\)"):
        dyn.inverse_dynamics(np.zeros(6), bad, np.zeros(6))
    with pytest.raises(ValueError, match=r"q: expected shape \(6,\)"):
        dyn.gravity(bad)


def test_non_finite_dynamics_input_raises(ur5_model):
    with pytest.raises(ValueError, match="non_finite"):
        kl.Dynamics(ur5_model).gravity(np.full(6, np.nan))


def test_dynamics_refuses_branching_model():
    xml = """<robot name="y"><link name="a"/>
      <link name="b"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="c"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
      <joint name="j2" type="continuous"><parent link="a"/><child link="c"/></joint></robot>"""
    model = kl.RobotModel.from_urdf(xml)
    assert not model.has_chain and model.nq == 2
    with pytest.raises(ValueError, match="serial chain"):
        kl.Dynamics(model)


def test_dh_model_from_python_matches_urdf_kinematics(ur5_model, rng):
    a = [0, -0.425, -0.39225, 0, 0, 0]
    alpha = [np.pi / 2, 0, 0, np.pi / 2, -np.pi / 2, 0]
    d = [0.089159, 0, 0, 0.10915, 0.09465, 0.0823]
    links = []
    for i in range(6):
        link = kl.DhLink()
        link.a, link.alpha, link.d, link.mass = a[i], alpha[i], d[i], 1.0
        link.inertia = np.eye(3) * 1e-3
        links.append(link)
    dh = kl.Dynamics(kl.RobotModel.from_dh(links, "standard"))
    urdf = kl.Dynamics(ur5_model)
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        np.testing.assert_allclose(dh.forward_kinematics(q), urdf.forward_kinematics(q), atol=1e-12)
    with pytest.raises(ValueError, match="convention"):
        kl.RobotModel.from_dh(links, "sideways")


def test_quintic_trajectory_api():
    traj = kl.QuinticTrajectory(np.array([[0.0, 0.0], [1.0, 2.0]]), np.array([0.0, 2.0]))
    q, qd, qdd = traj.sample(1.0)
    np.testing.assert_allclose(q, [0.5, 1.0])
    assert traj.end_time == 2.0 and traj.nq == 2
    with pytest.raises(ValueError, match="increasing"):
        kl.QuinticTrajectory(np.zeros((2, 2)), np.array([1.0, 1.0]))


def test_controller_config_errors_raise(ur5_model):
    cfg = kl.ComputedTorqueConfig()
    cfg.kp = np.ones(4)
    with pytest.raises(ValueError, match="kp"):
        kl.ComputedTorqueController(ur5_model, cfg)


def test_version_is_single_sourced():
    from importlib.metadata import version
    from pathlib import Path

    assert kl.__version__ == version("kiloloop")
    repo_version = Path(__file__).resolve().parents[1] / "VERSION"
    assert kl.__version__ == repo_version.read_text().strip()


def test_model_files_names_each_robots_urdf_and_sim_sections():
    for robot in ("ur5", "quadruped", "aerial_manipulator"):
        urdf, sim = kl.model_files(robot)
        assert urdf.is_file() and urdf.name == f"{robot}.urdf"
        assert sim["physics"]["timestep"] == 0.001
