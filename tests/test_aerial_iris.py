"""example-robot-data's iris (PX4/Gazebo quadrotor, no arm) from a minimal robot file with its
rotors typed in (tests/aerial_test_robots.py): hover, attitude step, rotor fault, wind and push
pass with everything else derived. The URDF is referenced where example-robot-data installed it."""
import json

import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.robot import Robot
from kiloloop.robot import aerial as aerial_robot
from kiloloop.robot_check import aerial as aerial_check

from aerial_test_robots import IRIS_THRUST_MAX, write_iris


@pytest.fixture(scope="module")
def iris(tmp_path_factory):
    return Robot.load(write_iris(tmp_path_factory.mktemp("iris")))


def test_iris_is_derived_from_its_urdf_and_rotors(iris):
    ctrl = kl.AerialController(aerial_robot.model(iris), aerial_robot.config(iris))
    assert not ctrl.has_arm and ctrl.nq == 0 and ctrl.n_rotors == 4
    assert ctrl.total_mass == pytest.approx(1.5 + 0.015 + 4 * 0.005, abs=1e-9)
    assert ctrl.allocation.max_collective == pytest.approx(4 * IRIS_THRUST_MAX, rel=0.05)
    print("\n".join(aerial_check.summary(iris, aerial_robot.model(iris))))


@pytest.mark.parametrize("name,duration", [
    ("aerial-hover", 3.0), ("aerial-attitude-step", None), ("aerial-rotor-fault", 4.0),
    ("aerial-wind", 6.0), ("aerial-push", 4.0)])
def test_iris_passes(iris, name, duration):
    r = scenarios.run_named(name, iris, duration=duration)
    print(name, json.dumps(r.metrics))
    failed = {k: c["value"] for k, c in r.criteria.items() if not c["passed"]}
    assert r.passed, failed
