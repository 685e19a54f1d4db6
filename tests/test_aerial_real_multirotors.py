"""Multirotors from real descriptions (issue 33): example-robot-data's borinot (a hexarotor with a
2-joint arm, its body CoM 2.4 cm off the base origin, 5 ms rotors) hovers, sweeps its arm and
recovers from a push with the criteria of kiloloop's own vehicle, its gains derived from its rotors'
margin; hector (thrust/weight 1.38) is refused the rotor fault it cannot ride out, 2-joint arms the
reach. Robot files from tests/aerial_test_robots.py (rotor data typed from the vendors' models).
Shortened runs: ~15 s in all on one free core."""
import math

import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.errors import ScenarioRefused
from kiloloop.robot import Robot
from kiloloop.robot import aerial as aerial_robot

from aerial_test_robots import run_passing as run
from aerial_test_robots import write_borinot, write_hector, write_iris


@pytest.fixture(scope="module")
def robots(tmp_path_factory):
    d = tmp_path_factory.mktemp("real_multirotors")
    return {"borinot": Robot.load(write_borinot(d)), "hector": Robot.load(write_hector(d)),
            "iris": Robot.load(write_iris(d))}


def test_roll_pitch_authority_is_where_a_rotor_reaches_its_limit(robots):
    """The torque authority puts one rotor exactly at a limit and none beyond (brute force over
    the allocation's own pseudo-inverse, both axes and signs)."""
    robot = robots["borinot"]
    alpha = aerial_robot.roll_pitch_authority(robot)
    ctrl = kl.AerialController(aerial_robot.model(robot), aerial_robot.config(robot))
    alloc = ctrl.allocation
    f0 = np.asarray(alloc.collective_share) * ctrl.hover_thrust
    P = np.linalg.pinv(np.asarray(alloc.mixer))
    J = np.asarray(ctrl.rigid_inertia)
    hi = aerial_robot.rotors(robot)[0]["thrust_max"]
    slack = []
    for axis in (0, 1):
        for sign in (1.0, -1.0):
            f = f0 + sign * alpha * J[axis, axis] * P[:, 1 + axis]
            assert np.all(f >= -1e-9) and np.all(f <= hi + 1e-9)
            slack.append(min(f.min(), hi - f.max()))
    assert min(slack) == pytest.approx(0.0, abs=1e-9)


def test_attitude_bandwidth_bounded_by_the_rotors_margin(robots):
    """borinot's 5 ms rotors alone would allow 40 rad/s; its margin gives 2 sqrt(alpha / theta)
    (about 19); kiloloop's own vehicle stays at its rotor-lag bound, 0.6 / 30 ms = 20 rad/s."""
    borinot = robots["borinot"]
    alpha = aerial_robot.roll_pitch_authority(borinot)
    theta = aerial_robot.tilt_limit(borinot)
    bw = aerial_robot.bandwidths(borinot)
    assert 0.6 / aerial_robot.time_constant(borinot) > aerial_robot.MAX_ATTITUDE_BANDWIDTH
    assert bw["attitude"] == pytest.approx(2 * math.sqrt(alpha / theta))
    assert bw["attitude"] < aerial_robot.MAX_ATTITUDE_BANDWIDTH
    assert bw["position"] == pytest.approx(bw["attitude"] / 5)
    ours = Robot.load("aerial_manipulator")
    assert aerial_robot.bandwidths(ours)["attitude"] == pytest.approx(20.0)
    assert 2 * math.sqrt(aerial_robot.roll_pitch_authority(ours)
                         / aerial_robot.tilt_limit(ours)) > 20.0
    # A bandwidth the file gives wins.
    given = borinot.with_overrides({"controller.attitude_bandwidth": "30"})
    assert aerial_robot.bandwidths(given)["attitude"] == 30.0


def test_hover_weight_with_every_rotor_is_the_largest_collective(robots):
    """With no fault and the CoM on the rotors' axis (hector), the weight the rotors hold level
    with zero torque is the allocation's largest collective thrust."""
    hector = robots["hector"]
    ctrl = kl.AerialController(aerial_robot.model(hector), aerial_robot.config(hector))
    held, weight = aerial_robot.hover_weight_with(hector, np.ones(4))
    assert weight == pytest.approx(ctrl.hover_thrust)
    assert held == pytest.approx(ctrl.allocation.max_collective, rel=1e-6)


def test_borinot_hovers(robots):
    run("aerial-hover", robots["borinot"], duration=2.5)


def test_borinot_recovers_from_a_push(robots):
    r = run("aerial-push", robots["borinot"], duration=2.5)
    assert r.metrics["peak_tilt_deg"] < 45.0


def test_borinot_sweeps_its_arm_with_the_feedforward(robots):
    run("aerial-arm-sweep", robots["borinot"], duration=3.5, period=2.5)


def test_rotor_fault_refused_where_the_rotors_left_cannot_hold_the_weight(robots):
    with pytest.raises(ScenarioRefused, match=r"hector: aerial-rotor-fault: .*rotor 0 at 70%.*"
                                              r"14\.00 N.*14\.49 N"):
        scenarios.run_named("aerial-rotor-fault", robots["hector"], duration=2.0)
    # A milder fault is flown (the refusal is the physics, not the robot).
    held, weight = aerial_robot.hover_weight_with(robots["hector"], [0.9, 1, 1, 1])
    assert held > weight
    # iris keeps 31 % of margin with the same fault: not refused.
    held, weight = aerial_robot.hover_weight_with(robots["iris"], [0.7, 1, 1, 1])
    assert held > weight


def test_reach_refused_for_an_arm_of_two_joints(robots):
    with pytest.raises(ScenarioRefused, match="needs 3, the arm has 2"):
        scenarios.run_named("aerial-reach", robots["borinot"], duration=2.0)
    with pytest.raises(ScenarioRefused, match="has none"):
        scenarios.run_named("aerial-arm-sweep", robots["hector"], duration=2.0)


def test_rotors_that_cannot_lift_the_vehicle_are_an_input_error(tmp_path):
    """The derivation builds the allocation: rotors too weak for the vehicle are the robot file's
    error (exit 2, the figures), not a bug's traceback."""
    from kiloloop.errors import InputError

    path = write_hector(tmp_path)
    path.write_text(path.read_text().replace("thrust_max = 5.0", "thrust_max = 3.0"))
    with pytest.raises(InputError, match=r"cannot lift the vehicle .*12\.0+ N <= m g = 14\.4"):
        aerial_robot.bandwidths(Robot.load(path))
