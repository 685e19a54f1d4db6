"""Any multirotor from a minimal robot file (issue 11): URDFs written here (a hexarotor and an
octorotor with a 2-joint arm and a body CoM away from the base origin, a hexarotor with tilted
rotors), each hovering, sweeping its arm with the reaction feed-forward and surviving a rotor
fault, judged by the scenarios' own criteria; example-robot-data's iris (no arm) in
test_aerial_iris.py. Robot-file errors name the key. Shortened runs: ~100 s in all on one free core."""

import numpy as np
import pytest

import kiloloop as kl
from kiloloop.robot import Robot
from kiloloop.robot import aerial as aerial_robot
from kiloloop.robot_check import aerial as aerial_check
from kiloloop.robot.robot_file import RobotFileError

from aerial_test_robots import run_passing as run
from aerial_test_robots import write_multirotor

VEHICLES = {
    "hexa_arm": dict(n_rotors=6, arm_joints=2, com=(0.03, -0.02, 0.01)),
    "octo_arm": dict(n_rotors=8, arm_joints=2, com=(-0.025, 0.03, -0.01), thrust_max=7.0),
    "hexa_tilt": dict(n_rotors=6, arm_joints=2, com=(0.0, 0.0, 0.015), tilt_deg=20.0),
}


@pytest.fixture(scope="module", params=list(VEHICLES))
def vehicle(request, tmp_path_factory):
    d = tmp_path_factory.mktemp(request.param)
    return Robot.load(write_multirotor(d, request.param, **VEHICLES[request.param]))


def test_derived_controller(vehicle):
    spec = VEHICLES[vehicle.name]
    ctrl = kl.AerialController(aerial_robot.model(vehicle), aerial_robot.config(vehicle))
    assert ctrl.n_rotors == spec["n_rotors"] and ctrl.nq == 2
    np.testing.assert_allclose(ctrl.body_com, np.array(spec["com"]) * 1.6 / (
        1.6 + 0.05 * spec["n_rotors"]) + [0, 0, 0.02 * 0.05 * spec["n_rotors"] / (
            1.6 + 0.05 * spec["n_rotors"])], atol=1e-12)
    assert ctrl.allocation.uses_lateral_rows == ("tilt_deg" in spec)
    lines = aerial_check.summary(vehicle, aerial_robot.model(vehicle))
    print("\n".join(lines))
    assert any("hover thrust" in line for line in lines)


def test_hovers(vehicle):
    run("aerial-hover", vehicle, duration=3.0)


def test_sweeps_its_arm_with_the_feedforward(vehicle):
    r = run("aerial-arm-sweep", vehicle, duration=4.0, period=3.0)
    assert r.settings["sweep_joint"] == 0  # the pitch joint at the root moves the CoM most
    assert r.metrics["attitude_ptp_deg_ff"] < r.metrics["attitude_ptp_deg_no_ff"]


def test_survives_a_rotor_fault(vehicle):
    run("aerial-rotor-fault", vehicle, duration=4.0)


def test_robot_file_errors_name_the_key(tmp_path):
    path = write_multirotor(tmp_path, "bad", 6, 0)
    text = path.read_text()
    path.write_text(text.replace("spin = 1\n", "spin = 2\n", 1))
    with pytest.raises(RobotFileError, match=r"rotors\[1\]\.spin"):
        aerial_robot.rotors(Robot.load(path))
    path.write_text(text.replace("thrust_max", "thrust_maximum", 1))
    with pytest.raises(RobotFileError, match=r"rotors\[0\]\.thrust_maximum"):
        aerial_robot.rotors(Robot.load(path))
    # Coplanar rotors without drag torque: no yaw authority, said at configure.
    path.write_text(text.replace("torque_coefficient = 0.016", "torque_coefficient = 0.0"))
    robot = Robot.load(path)
    with pytest.raises(ValueError, match="yaw"):
        kl.AerialController(aerial_robot.model(robot), aerial_robot.config(robot))
