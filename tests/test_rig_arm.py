"""The rig (sil/rig.py) on an arm: the native loop's signal chain (noise, quantization, delays in
seconds, motor lag) acts as specified, seeds reproduce, events (pushes, the e-stop) fire at their
tick; the extension steps the very libmujoco the `mujoco` module loaded."""
import os

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.errors import InputError
from kiloloop.scenarios import arm_track
from kiloloop.scenarios.arm_controllers import controller
from kiloloop.sil import native
from kiloloop.sil.arm_adapters import JointTracking, Supervised
from kiloloop.sil.events import EStop, Push, force_event
from kiloloop.sil.rig import Rig
from kiloloop.sil.signals import Signals

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")


def test_one_libmujoco_in_the_process():
    native.check()
    lib = os.path.realpath(kl.sil.native.library())
    wheel = os.path.dirname(mujoco.__file__)
    assert lib.startswith(os.path.realpath(wheel)), lib
    with open("/proc/self/maps") as f:
        paths = {line.split()[-1] for line in f if "libmujoco" in line}
    assert len({os.path.realpath(p) for p in paths}) == 1, paths


@pytest.fixture(scope="module")
def ur5():
    return scenarios.prepare(arm_track)


def _track(robot, settings, signals=None, seed=0, law="computed_torque", **ctrl):
    rig = Rig(robot, signals, seed=seed)
    points = arm_track.waypoints(rig, settings)
    rig.plant.q0 = points[0]
    rig.plant.reset()
    traj = kl.QuinticTrajectory(points, np.array([0.0, settings["t_1"], settings["t_2"]]))
    return rig, JointTracking(controller(robot, rig.model, law, points[0], **ctrl), traj), traj


def test_signal_chain_acts_with_delays_in_seconds(ur5):
    robot, settings = ur5
    signals = Signals(q_sigma=1e-4, qd_sigma=1e-3, encoder_resolution=np.deg2rad(0.01),
                      measurement_delay=0.002, motor_delay=0.002, motor_time_constant=0.003)
    rig, reference, _ = _track(robot, settings, signals, seed=7, measurement_delay=0.002)
    log = rig.run(0.5, reference, observe=native.Observe("q_true", "qd_true"))
    assert len(log["t"]) == 500
    # The controller sees q two ticks old, quantized and noisy: close to, never equal to, the
    # true q two ticks earlier.
    assert not np.array_equal(log["q"][10:], log["q_true"][8:-2])
    assert np.all(np.abs(log["q"][10:] - log["q_true"][8:-2]) < 1e-3)
    ideal = _track(robot, settings)
    clean = ideal[0].run(0.5, ideal[1], observe=native.Observe("q_true"))
    assert np.array_equal(clean["q"], clean["q_true"])  # the default chain is ideal


def test_delays_are_whole_ticks_half_up(ur5):
    robot, settings = ur5
    for seconds, ticks in ((0.0015, 2), (0.00149, 1), (0.0, 0)):
        rig, reference, _ = _track(robot, settings, Signals(measurement_delay=seconds))
        log = rig.run(0.05, reference, observe=native.Observe("q_true"))
        lag = ticks
        assert np.array_equal(log["q"][lag + 1:], log["q_true"][1:len(log["q"]) - lag]), seconds


def test_seed_gives_the_same_log_and_another_seed_another(ur5):
    robot, settings = ur5

    def run(seed):
        rig, reference, _ = _track(robot, settings, Signals(q_sigma=1e-4), seed=seed)
        return rig.run(0.2, reference, observe=native.Observe("q_true"))

    a, b, c = run(3), run(3), run(4)
    assert np.array_equal(a["tau"], b["tau"])
    assert not np.array_equal(a["tau"], c["tau"])


def test_estop_fires_at_the_first_tick_after_its_time(ur5):
    robot, settings = ur5
    rig, reference, traj = _track(robot, settings)
    supervised = Supervised(reference.controller, kl.ArmSupervisor(rig.model), traj, t_estop=0.4)
    mode = rig.run(0.8, supervised)["mode"]
    assert mode[399] == 0 and mode[400] != 0
    # The same as an EStop event on a supervisor that is never pressed by its reference.
    rig2, reference2, traj2 = _track(robot, settings)
    late = Supervised(reference2.controller, kl.ArmSupervisor(rig2.model), traj2, t_estop=1e9)
    mode2 = rig2.run(0.8, late, [(0.4, EStop())])["mode"]
    assert np.array_equal(mode, mode2)


def test_push_moves_the_tool_and_nothing_before_it(ur5):
    robot, settings = ur5
    tips = []
    for push in (False, True):
        rig, reference, _ = _track(robot, settings, law="pd_gravity")
        events = [(0.1, Push([0, 0, -50.0], 0.05))] if push else []
        tips.append(rig.run(0.3, reference, events, observe=native.Observe("ee"))["ee"])
    assert np.array_equal(tips[0][:100], tips[1][:100])  # nothing before the push
    assert np.abs(tips[1][150:] - tips[0][150:]).max() > 1e-4  # pushed


def test_bad_arguments_are_refused(ur5):
    robot, settings = ur5
    rig, reference, traj = _track(robot, settings)
    adapter = reference.native_adapter()
    with pytest.raises(ValueError, match="measurement/actuator"):
        native._native.Rollout(rig.plant.model, rig.plant.data, adapter, ticks=10,
                               measurement=[0], actuators=[0])
    with pytest.raises(ValueError, match="force event"):
        native._native.Rollout(rig.plant.model, rig.plant.data, adapter, ticks=10,
                               measurement=list(range(2 * rig.plant.nq)),
                               actuators=[int(a) for a in rig.plant._act],
                               events=[force_event(0.0, 9999, [0] * 6, 1.0)])
    with pytest.raises(ValueError, match="controller"):
        native.joint_tracking_adapter(object(), traj)
    with pytest.raises(InputError, match="physics_dt"):
        Rig(robot, physics_dt=0.0007)
    with pytest.raises(InputError, match="motor_delay"):
        Rig(robot, Signals(motor_delay=-1.0))
    with pytest.raises(TypeError, match="slope_deg"):
        Rig(robot, slope_deg=3.0)  # a quadruped's option
    with pytest.raises(InputError, match="stop"):
        rig.rollout(0.1, reference, stop=object())
