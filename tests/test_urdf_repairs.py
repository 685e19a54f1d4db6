"""URDF repairs with a name (issue 33, items 2 and 4): an inertia MuJoCo refuses is refused naming
the link, the inequality with its numbers and the fix, or balanced on request (a warning naming the
link and by how much), and the controller's model and the plant then agree; a link fixed to its
parent moves into it exactly; joints without limits draw a `robot check` warning, and
[limits.<joint>] sets them in both models. Small two-link arms written here; nothing is run."""
import contextlib
import io

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import robot_check as check
from kiloloop.errors import UrdfRepairWarning
from kiloloop.sil.arm_family import build_plant
from kiloloop.sil.plant import MujocoPlant

from robot_files import write_robot_file

GOOD = "0.01 0.01 0.01"
# Principal moments 0.001 + 0.001 < 0.01: A + B >= C broken (no rigid body has them).
BROKEN = "0.001 0.001 0.01"


def _inertial(mass, moments):
    ixx, iyy, izz = moments.split()
    return (f"<inertial><origin xyz='0 0 0.1'/><mass value='{mass}'/><inertia ixx='{ixx}' "
            f"iyy='{iyy}' izz='{izz}' ixy='0' ixz='0' iyz='0'/></inertial>")


def arm_urdf(tmp_path, link2=GOOD, joint2="<limit lower='-2' upper='2' velocity='3' effort='50'/>",
             joint2_type="revolute", extra="", name="arm.urdf"):
    """A two-link arm (base -> link1 -> link2, 1 kg each, y axes); `extra`: more links."""
    path = tmp_path / name
    path.write_text(f"""<robot name='arm'>
  <link name='base'>{_inertial(1.0, GOOD)}</link>
  <joint name='joint1' type='revolute'><parent link='base'/><child link='link1'/>
    <origin xyz='0 0 0.2'/><axis xyz='0 1 0'/><limit lower='-2' upper='2' velocity='3' effort='50'/></joint>
  <link name='link1'>{_inertial(1.0, GOOD)}</link>
  <joint name='joint2' type='{joint2_type}'><parent link='link1'/><child link='link2'/>
    <origin xyz='0 0 0.2'/><axis xyz='0 1 0'/>{joint2}</joint>
  <link name='link2'>{_inertial(1.0, link2)}</link>
{extra}</robot>
""")
    return path


def robot_file(tmp_path, urdf, more=""):
    return write_robot_file(tmp_path, f'name = "arm"\nkind = "arm"\nurdf = "{urdf}"\n{more}'
                                      f'[chain]\nroot = "base"\ntip = "link2"\n')


def robot_check(path) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err):
        code = check.check(path, stream=out)
    return code, out.getvalue(), err.getvalue()


def mass_matrices(robot, q):
    """M(q) of the controller's model and of the plant, (nq, nq) each."""
    plant = build_plant(robot)
    d = mujoco.MjData(plant.model)
    d.qpos[plant.qpos_addresses] = q
    mujoco.mj_forward(plant.model, d)
    M = np.zeros((plant.model.nv, plant.model.nv))
    mujoco.mj_fullM(plant.model, d, M)
    return kl.Dynamics(robot.model()).mass_matrix(q), M


def test_a_broken_inertia_is_refused_with_the_link_the_inequality_and_the_fix(tmp_path):
    path = robot_file(tmp_path, arm_urdf(tmp_path, link2=BROKEN))
    code, out, err = robot_check(path)
    assert code == 2 and out == ""
    assert "'link2'" in err and "0.001 + 0.001 = 0.002 < 0.01" in err and str(path) in err
    assert "balance_inertia = true" in err and "<inertia>" in err
    assert "balanceinertia" not in err  # MuJoCo's own words no longer reach the user


def test_balance_inertia_warns_and_the_model_and_the_plant_agree(tmp_path):
    path = robot_file(tmp_path, arm_urdf(tmp_path, link2=BROKEN), "balance_inertia = true\n")
    robot = kl.Robot.load(path)
    with pytest.warns(UrdfRepairWarning, match=r"link 'link2'.*0.001, 0.001, 0.01\] -> "):
        model = robot.model()
    # Moved to the nearest valid inertia: A, B up and C down by (C - A - B) / 3.
    t = (0.01 - 0.002) / 3
    M, M_plant = mass_matrices(robot, np.array([0.3, -0.7]))
    np.testing.assert_allclose(M, M_plant, atol=1e-12)
    assert M[1, 1] == pytest.approx(1.0 * 0.1 ** 2 + 0.001 + t, rel=1e-6)
    assert model.nq == 2
    code, out, _ = robot_check(path)
    assert code == 0 and "URDF changes" in out and "link 'link2'" in out and "balance_inertia" in out


def test_balance_inertia_as_an_override_rescues_a_refused_file(tmp_path):
    robot = kl.Robot.load(robot_file(tmp_path, arm_urdf(tmp_path, link2=BROKEN)))
    with pytest.warns(UrdfRepairWarning):
        assert robot.with_overrides({"balance_inertia": "true"}).model().nq == 2


def test_a_fixed_link_moves_into_its_parent_exactly_without_asking(tmp_path):
    # A camera fixed to link2, its own inertia broken: the composite is a valid rigid body.
    camera = (f"  <joint name='camera_joint' type='fixed'><parent link='link2'/><child "
              f"link='camera'/><origin xyz='0.05 0 0.15' rpy='0.3 0 0'/></joint>\n"
              f"  <link name='camera'>{_inertial(0.2, BROKEN)}</link>\n")
    urdf = arm_urdf(tmp_path, extra=camera)
    robot = kl.Robot.load(robot_file(tmp_path, urdf))
    assert any("'camera'" in r and "moved into its parent 'link2'" in r
               for r in robot.urdf_doc.repairs)
    q = np.array([0.4, 1.1])
    as_written = kl.Dynamics(kl.RobotModel.from_urdf(str(urdf), "base", "link2")).mass_matrix(q)
    M, M_plant = mass_matrices(robot, q)
    np.testing.assert_allclose(M, as_written, atol=1e-12)  # KDL takes the broken one as is
    np.testing.assert_allclose(M_plant, M, atol=1e-12)


def test_a_negligible_repair_is_made_without_asking_and_listed(tmp_path):
    # A dummy frame of 1 g whose inertia is singular (all entries equal): MuJoCo refuses it.
    dummy = ("  <joint name='tool_joint' type='fixed'><parent link='link2'/><child link='tool'/>"
             "<origin xyz='0 0 0.2'/></joint>\n  <link name='tool'><inertial><mass value='0.001'/>"
             "<inertia ixx='1e-6' iyy='1e-6' izz='1e-6' ixy='1e-6' ixz='1e-6' iyz='1e-6'/>"
             "</inertial></link>\n")
    plant = MujocoPlant(arm_urdf(tmp_path, extra=dummy), joints=["joint1", "joint2"],
                        overlay={"ee": {"body": "link2"}})
    assert any("'tool'" in n and "without asking" in n for n in plant.notes)


def test_a_dummy_link_whose_inertia_is_not_positive_semi_definite_is_repaired(tmp_path):
    # tiago_description's antenna links: 1 mg, products of inertia larger than the moments (a
    # negative principal moment, -5e-8 kg m^2): refused by the loader before, for nothing.
    antenna = ("  <joint name='antenna_joint' type='fixed'><parent link='link1'/><child "
               "link='antenna'/><origin xyz='0 0.1 0'/></joint>\n  <link name='antenna'><inertial>"
               "<mass value='0.000001'/><inertia ixx='0.00000002371' ixy='0.00000006119' "
               "ixz='0.00000001179' iyy='0.00000002833' iyz='0.00000000774' izz='0.00000003849'/>"
               "</inertial></link>\n")
    plant = MujocoPlant(arm_urdf(tmp_path, extra=antenna), joints=["joint1", "joint2"],
                        overlay={"ee": {"body": "link2"}})
    assert any("'antenna'" in n and "without asking" in n and "not positive" in n
               for n in plant.notes)


def test_a_real_link_whose_inertia_is_not_positive_semi_definite_is_refused(tmp_path):
    bad = ("<inertial><mass value='1'/><inertia ixx='0.01' iyy='0.01' izz='0.01' ixy='0.05' "
           "ixz='0' iyz='0'/></inertial>")
    urdf = arm_urdf(tmp_path)
    urdf.write_text(urdf.read_text().replace(f"<link name='link2'>{_inertial(1.0, GOOD)}",
                                             f"<link name='link2'>{bad}"))
    code, out, err = robot_check(robot_file(tmp_path, urdf))
    assert code == 2 and "'link2'" in err and "smallest principal moment -0.04 kg m^2 not positive" in err


def test_a_moving_link_without_mass_is_refused_in_the_urdfs_terms(tmp_path):
    urdf = arm_urdf(tmp_path)
    urdf.write_text(urdf.read_text().replace(f"<link name='link2'>{_inertial(1.0, GOOD)}</link>",
                                             "<link name='link2'/>"))
    with pytest.raises(ValueError,
                       match=r"link 'link2' moves on a joint of its own.*<inertial>"):
        MujocoPlant(urdf, overlay={"ee": {"body": "link2"}})


CONTINUOUS = dict(joint2="", joint2_type="continuous")


def test_missing_limits_are_named_by_robot_check(tmp_path):
    path = robot_file(tmp_path, arm_urdf(tmp_path, **CONTINUOUS))
    code, out, _ = robot_check(path)
    assert code == 0
    warning = [line for line in out.splitlines() if "warning:" in line]
    assert len(warning) == 1 and "joint 'joint2'" in warning[0]
    assert "no effort and no velocity limit (continuous joint without <limit>)" in warning[0]
    assert "[limits.joint2] effort = ... [N m], velocity = ... [rad/s]" in warning[0]
    # A <limit> of effort 0 (URDF's "not given") is named too.
    zero = robot_file(tmp_path, arm_urdf(tmp_path, joint2="<limit lower='-1' upper='1' "
                                                          "velocity='2' effort='0'/>", name="z.urdf"))
    assert "joint 'joint2': no effort limit (its <limit> gives effort 0)" in robot_check(zero)[1]


def test_limits_from_the_robot_file_reach_the_model_and_the_plant(tmp_path):
    path = robot_file(tmp_path, arm_urdf(tmp_path, **CONTINUOUS),
                      "[limits.joint2]\neffort = 20\nvelocity = 4\nlower = -3\nupper = 3\n")
    robot = kl.Robot.load(path)
    model, plant = robot.model(), build_plant(robot)
    assert list(model.effort_limit) == [50, 20] and list(model.velocity_limit) == [3, 4]
    assert list(model.lower) == [-2, -3] and list(model.upper) == [2, 3]
    j2 = plant.model.joint("joint2")
    assert list(j2.range) == [-3, 3] and j2.limited
    assert list(plant.model.actuator("joint2").ctrlrange) == [-20, 20]
    code, out, _ = robot_check(path)
    assert code == 0 and "warning:" not in out
    assert ("joint 'joint2' (continuous -> revolute): lower -3 rad (URDF: none), upper 3 rad "
            "(URDF: none), velocity 4 rad/s (URDF: none), effort 20 N m (URDF: none)") in out


@pytest.mark.parametrize("table, words", [
    ("[limits.joint9]\neffort = 1\n", "limits.joint9: the URDF has no revolute"),
    ("[limits.joint2]\ntorque = 1\n", "limits.joint2.torque: unknown key"),
    ("[limits.joint2]\neffort = 0\n", "limits.joint2.effort: expected > 0"),
    ("[limits.joint2]\nlower = 1\nupper = -1\n", "lower 1 is not below upper -1"),
    ("[limits.joint2]\nlower = 1\n", "give both lower and upper"),
    ("[limits]\njoint2 = 5\n", "limits.joint2: expected a table"),
])
def test_bad_limits_are_refused_at_load_naming_the_key(tmp_path, table, words):
    path = robot_file(tmp_path, arm_urdf(tmp_path, **CONTINUOUS), table)
    with pytest.raises(kl.RobotFileError, match=words) as e:
        kl.Robot.load(path)
    assert str(path) in str(e.value)


def test_the_firmware_export_reads_the_changed_urdf(tmp_path):
    path = robot_file(tmp_path, arm_urdf(tmp_path, **CONTINUOUS), "[limits.joint2]\neffort = 20\n")
    doc = kl.Robot.load(path).urdf_doc
    with doc.as_file() as urdf:
        exported = kl._core.firmware.description_source(str(urdf))
        assert urdf != doc.path and urdf.read_text() == doc.xml()
    as_written = kl._core.firmware.description_source(str(doc.path))
    assert exported != as_written  # joint2's effort limit: 20 N m instead of none
    unchanged = kl.Robot.load(robot_file(tmp_path, arm_urdf(tmp_path, name="ok.urdf"))).urdf_doc
    with unchanged.as_file() as urdf:
        assert urdf == unchanged.path
