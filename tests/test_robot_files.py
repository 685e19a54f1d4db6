"""Robot files: loading, validation (unknown keys, missing files, wrong names, packages), --set
dotted overrides, and `kiloloop robot check` failing with one clear line and exit code 2."""
import subprocess
import sys

import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.robot import arm as arm_defaults

from robot_files import erd_urdf, minimal_arm, write_robot_file

UR5 = kl.models_dir() / "ur5" / "ur5.urdf"


def cli(*args):
    return subprocess.run([sys.executable, "-m", "kiloloop.cli", *args], capture_output=True,
                          text=True, timeout=300)


def test_kiloloops_own_robots_load_with_their_kinds():
    kinds = {r: kl.Robot.load(r).kind for r in ("ur5", "quadruped", "aerial_manipulator")}
    assert kinds == {"ur5": "arm", "quadruped": "quadruped", "aerial_manipulator": "aerial"}
    ur5 = kl.Robot.load("ur5")
    assert ur5.model().nq == 6 and ur5.sim["physics"]["timestep"] == 0.001


HEAD = f'name = "x"\nkind = "arm"\nurdf = "{UR5}"\n'
CHAIN = '[chain]\nroot = "base_link"\ntip = "tool0"\n'


@pytest.mark.parametrize("text, key", [
    ("colour = 1\n" + HEAD + CHAIN, "colour"),
    (HEAD + CHAIN + "tipp = 'x'\n", "chain.tipp"),
    (HEAD + CHAIN + "[controller]\nkpp = 1\n", "controller.kpp"),
    (HEAD + CHAIN + "[sim.joints]\ndampng = 1\n", "sim.joints.dampng"),
    (HEAD + CHAIN + "[scenario.arm-track]\nnope = 1\n", "scenario.arm-track.nope"),
    (HEAD + CHAIN + "[scenario.arm-dance]\nt_1 = 1\n", "scenario.arm-dance"),
])
def test_unknown_keys_are_errors_naming_the_key_and_the_file(tmp_path, text, key):
    path = write_robot_file(tmp_path, text)
    with pytest.raises(kl.RobotFileError) as e:
        kl.Robot.load(path)
    assert f"'{key}'" in str(e.value) and str(path) in str(e.value)


def _broken_files(tmp_path):
    ok = f'name = "x"\nkind = "arm"\nurdf = "{UR5}"\n[chain]\nroot = "base_link"\ntip = "tool0"\n'
    ur10 = erd_urdf("ur_description/urdf/ur10_robot.urdf")
    return {
        "missing URDF": (ok.replace(str(UR5), str(tmp_path / "nope.urdf")), "file not found"),
        "wrong link name": (ok.replace('tip = "tool0"', 'tip = "tool9"'), "tool9"),
        "unknown key": (ok + "gains = 3\n", "'chain.gains'"),
        "package not found": (f'name = "x"\nkind = "arm"\nurdf = "{ur10}"\n[chain]\n'
                              f'root = "base_link"\ntip = "tool0"\n', "example-robot-data"),
        "unknown kind": (ok.replace('kind = "arm"', 'kind = "boat"'), "boat"),
        "not TOML": ("name = \n", "TOML"),
    }


@pytest.mark.parametrize("case", ["missing URDF", "wrong link name", "unknown key",
                                  "package not found", "unknown kind", "not TOML"])
def test_robot_check_on_a_broken_file_prints_one_line_and_exits_2(tmp_path, case):
    text, needle = _broken_files(tmp_path)[case]
    path = write_robot_file(tmp_path, text)
    out = cli("robot", "check", str(path))
    assert out.returncode == 2, out.stdout + out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    assert needle in lines[0], lines[0]
    assert out.stdout == ""


def test_robot_check_prints_the_summary_of_a_minimal_ur10(tmp_path):
    path = minimal_arm(tmp_path, erd_urdf("ur_description/urdf/ur10_robot.urdf"), "base_link",
                       "tool0", "ur10")
    out = cli("robot", "check", str(path))
    assert out.returncode == 0, out.stderr
    text = out.stdout
    for needle in ("shoulder_pan_joint", "total mass", "work pose", "computed torque kp",
                   "IK solver", "plant:", "replaced by a fitted box"):
        assert needle in text, needle
    assert len(text.splitlines()) < 40  # one screen


def test_set_takes_any_robot_file_key_as_a_dotted_path():
    robot = kl.Robot.load("ur5").with_overrides({"controller.bandwidth": "20",
                                                "sim.joints.damping": "0.5"})
    model = robot.model()
    kp, kd = arm_defaults.joint_gains(robot, model, "computed_torque", np.zeros(6))
    assert np.allclose(kp, 400.0) and np.allclose(kd, 40.0)
    assert robot.sim["joints"]["damping"] == 0.5
    with pytest.raises(kl.RobotFileError, match="controller.bandwith"):
        kl.Robot.load("ur5").with_overrides({"controller.bandwith": "20"})
    # The command line splits dotted (robot file) from plain (scenario) keys.
    r, settings = scenarios.prepare(scenarios.get("arm-track"), None,
                                    ["controller.kp=400", "t_1=1.6"])
    assert r.data["controller"]["kp"] == 400 and settings["t_1"] == 1.6


def test_set_controller_gain_changes_the_run():
    base = scenarios.run_named("arm-track", duration=1.0)
    soft = scenarios.run_named("arm-track", overrides=["controller.kp=100", "controller.kd=20"],
                               duration=1.0)
    assert soft.metrics["max_joint_error_rad"] > 2 * base.metrics["max_joint_error_rad"]


def test_a_scenario_of_another_family_refuses_the_robot():
    with pytest.raises(ValueError, match="kind 'quadruped'"):
        scenarios.prepare(scenarios.get("quadruped-stand"), "ur5")
