"""The native SIL loop (sil/native.py, cpp/sil/) against the per-tick Python loop on the arm:
same seed -> bit-identical logs, with and without sensor/motor models and events; the extension
steps the very libmujoco the `mujoco` module loaded."""
import json
import os

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.scenarios import arm_track
from kiloloop.sil import native
from kiloloop.sil.arm_adapters import JointTrackingTick, SupervisedTick
from kiloloop.sil.arm_rig import ArmRig, controller

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")


def assert_same_log(a, b):
    assert sorted(a.names()) == sorted(b.names())
    for name in a.names():
        x, y = a[name], b[name]
        assert x.shape == y.shape, name
        # Bit for bit: the same compiled code on the same inputs in the same order.
        assert np.array_equal(x, y), f"{name}: max diff {np.abs(x - y).max()}"


def test_one_libmujoco_in_the_process():
    native.check()
    lib = os.path.realpath(kl.sil.native.library())
    wheel = os.path.dirname(mujoco.__file__)
    assert lib.startswith(os.path.realpath(wheel)), lib
    with open("/proc/self/maps") as f:
        paths = {line.split()[-1] for line in f if "libmujoco" in line}
    assert len({os.path.realpath(p) for p in paths}) == 1, paths


@pytest.mark.parametrize("name", ["arm-track", "arm-line", "arm-estop"])
def test_scenario_native_equals_python_loop(name):
    duration = 1.0
    fast = scenarios.run_named(name, duration=duration)
    slow = scenarios.run_named(name, overrides={"native": "false"}, duration=duration)
    assert_same_log(fast.log, slow.log)
    assert json.dumps(fast.metrics) == json.dumps(slow.metrics)  # NaN-safe equality
    assert len(fast.log["t"]) == 1000


def _track_rig(robot, settings):
    rig = ArmRig(robot)
    points = arm_track.waypoints(rig, settings)
    rig.plant.q0 = points[0]
    rig.plant.reset()
    traj = kl.QuinticTrajectory(points, np.array([0.0, settings["t_1"], settings["t_2"]]))
    return rig, points, traj


@pytest.fixture(scope="module")
def ur5():
    return scenarios.prepare(arm_track)


def test_nonideal_and_delay_native_equals_python_loop(ur5):
    robot, settings = ur5
    nonideal = native.NonIdeal(q_sigma=1e-4, qd_sigma=1e-3, encoder_resolution=np.deg2rad(0.01),
                               motor_delay_ticks=2, motor_time_constant=0.003, seed=7)
    logs = []
    for use_native in (True, False):
        rig, points, traj = _track_rig(robot, settings)
        tick = JointTrackingTick(controller(robot, rig.model, "computed_torque", points[0],
                                            delay_ticks=2), traj)
        logs.append(rig.run(tick, 0.5, delay_ticks=2, observe=native.Observe("q_true", "qd_true"),
                            native=use_native, nonideal=nonideal))
    assert_same_log(*logs)
    fast = logs[0]
    # The models act: the measured q is quantized and noisy, not the true q two ticks earlier.
    assert not np.array_equal(fast["q"][10:], fast["q_true"][8:-2])
    assert np.all(np.abs(fast["q"][10:] - fast["q_true"][8:-2]) < 1e-3)


def test_seed_gives_the_same_log_and_another_seed_another(ur5):
    robot, settings = ur5

    def run(seed):
        rig, points, traj = _track_rig(robot, settings)
        tick = JointTrackingTick(controller(robot, rig.model, "computed_torque", points[0]), traj)
        return rig.run(tick, 0.2, observe=native.Observe("q_true"),
                       nonideal=native.NonIdeal(q_sigma=1e-4, seed=seed))

    a, b, c = run(3), run(3), run(4)
    assert np.array_equal(a["tau"], b["tau"])
    assert not np.array_equal(a["tau"], c["tau"])


def test_estop_event_native_equals_python_supervised_tick(ur5):
    robot, settings = ur5
    logs = []
    for use_native in (True, False):
        rig, points, traj = _track_rig(robot, settings)
        ctrl = controller(robot, rig.model, "computed_torque", points[0])
        supervisor = kl.ArmSupervisor(rig.model)
        tick = SupervisedTick(ctrl, supervisor, traj, t_estop=0.4)
        logs.append(rig.run(tick, 0.8, observe=native.Observe("q_true", "qd_true"),
                            native=use_native))
    assert_same_log(*logs)
    mode = logs[0]["mode"]
    assert mode[399] == 0 and mode[400] != 0  # the e-stop fires at the first tick t >= 0.4 s


def test_force_event_pushes_the_arm(ur5):
    robot, settings = ur5
    tips = []
    for push in (False, True):
        rig, points, traj = _track_rig(robot, settings)
        tick = JointTrackingTick(controller(robot, rig.model, "pd_gravity", points[0]), traj)
        body = rig.plant.model.body(robot.section("chain")["tip"]).id
        events = [native.force(0.1, body, [0, 0, -50.0, 0, 0, 0], 0.05)] if push else []
        log = native.run(rig.plant, tick.native_adapter(), 0.3, events=events,
                         observe=native.Observe("ee"))
        tips.append(log["ee"])
    before = slice(0, 100)
    assert np.array_equal(tips[0][before], tips[1][before])  # nothing before the push
    assert np.abs(tips[1][150:] - tips[0][150:]).max() > 1e-4  # pushed


def test_bad_arguments_raise_value_error(ur5):
    robot, settings = ur5
    rig, points, traj = _track_rig(robot, settings)
    tick = JointTrackingTick(controller(robot, rig.model, "computed_torque", points[0]), traj)
    adapter = tick.native_adapter()
    with pytest.raises(ValueError, match="measurement/actuator"):
        native._native.Rollout(rig.plant.model, rig.plant.data, adapter, ticks=10,
                               measurement=[0], actuators=[0])
    with pytest.raises(ValueError, match="force event"):
        native.rollout(rig.plant, adapter, 0.1, events=[native.force(0.0, 9999, [0] * 6, 1.0)])
    with pytest.raises(ValueError, match="controller"):
        native.joint_tracking_adapter(object(), traj)
