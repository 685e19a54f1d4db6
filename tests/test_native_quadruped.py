"""The quadruped's native SIL loop (cpp/sil/quadruped_adapter.hpp) against its per-tick Python
loop (sil/quadruped_rig.py): the same C++ sensor and motor models, the same seed -> the same log;
events, early stop, batch threads and the foothold-offset input."""
import json

import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.sil import batch, native
from kiloloop.sil.quadruped_rig import FellBelow, push_event, rig_from_settings, stand_command
from kiloloop.scenarios.quadruped_metrics import trot_command
from kiloloop.scenarios import quadruped_trot

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")

# The plant's contact forces are summed by numpy (frame.T @ f, possibly through BLAS) in the
# Python loop and by the C++ probe in the native one: equal to rounding, and never fed back
# (foot_fz: their normal components, add_derived; on flat ground both sums are exact).
ROUNDED = {"foot_force", "foot_fz"}


def assert_same_log(a, b):
    assert sorted(a.names()) == sorted(b.names())
    for name in a.names():
        x, y = a[name], b[name]
        assert x.shape == y.shape, name
        if name in ROUNDED:
            np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-9, err_msg=name)
        else:
            assert np.array_equal(x, y), f"{name}: max diff {np.abs(x - y).max()}"


def rig(seed=0, **overrides):
    settings = scenarios.parse_settings(quadruped_trot.DEFAULTS, overrides)
    return rig_from_settings(settings, seed)


def test_trot_with_push_native_equals_python_loop():
    logs = []
    for native_loop in (True, False):
        r = rig(seed=3)
        events = [push_event(0.8, [0.0, 40.0, 0.0], 0.05)]
        if native_loop:
            assert r.runs_natively(trot_command(0.5, 0.3), events, FellBelow(0.0))
        logs.append(r.run(1.2, trot_command(0.5, 0.3), events=events, stop_when=FellBelow(0.0),
                          native=native_loop))
    assert_same_log(*logs)
    assert len(logs[0]["t"]) == 1200
    assert logs[0]["v_cmd"][299, 0] == 0.0 and logs[0]["v_cmd"][300, 0] == 0.5
    # The push moved the trunk sideways (world +y) within its 50 ms.
    vy = logs[0]["base_vel"][:, 1]
    assert vy[850] - vy[799] > 0.05


@pytest.mark.parametrize("ideal", ["true", "false"])
def test_both_sensor_paths_native_equal_python_loop(ideal):
    """Realistic sensors (C++ IMU and encoder stages, the controller's own attitude) and ideal
    ones (white noise, the plant's orientation as an AHRS): one implementation, one log."""
    logs = [rig(seed=5, ideal_sensors=ideal).run(0.6, trot_command(0.5, 0.2), native=n)
            for n in (True, False)]
    assert_same_log(*logs)
    assert len(logs[0]["t"]) == 600


@pytest.mark.parametrize("name, duration", [("quadruped-push", 3.0),    # the push at 2 s, recovery
                                            ("quadruped-rough", 2.5)])  # kiloloop's heightfield contact
def test_scenario_native_equals_python_loop(name, duration):
    fast = scenarios.run_named(name, duration=duration)
    slow = scenarios.run_named(name, overrides={"native": "false"}, duration=duration)
    assert_same_log(fast.log, slow.log)
    assert json.dumps(fast.metrics) == json.dumps(slow.metrics)


def test_same_seed_same_log_other_seed_other_noise():
    a = rig(seed=5).run(0.2, stand_command())
    b = rig(seed=5).run(0.2, stand_command())
    c = rig(seed=6).run(0.2, stand_command())
    assert_same_log(a, b)
    assert not np.array_equal(a["est_vel"], c["est_vel"])


def test_stop_condition_ends_both_loops_at_the_same_tick():
    for native_loop in (True, False):
        r = rig()
        log = r.run(0.5, stand_command(), stop_when=FellBelow(10.0), native=native_loop)
        assert len(log["t"]) == 1, native_loop  # the first tick's trunk is below 10 m


def test_batch_on_two_threads_equals_one_by_one():
    r = rig()
    command = trot_command(0.5, 0.2)
    logs = {}
    for threads in (1, 2):
        rollouts = []
        for seed in (0, 1, 2):
            data = mujoco.MjData(r.plant.model)
            mujoco.mj_copyData(data, r.plant.model, r.plant.data)
            controller = kl.QuadrupedController(r.model, r.config)
            rollouts.append(r.native_rollout(0.4, command, data=data, seed=seed,
                                             adapter=r.native_adapter(command, controller)))
        batch.run(rollouts, threads=threads)
        assert all(x.ok and x.ticks_run == 400 for x in rollouts)
        logs[threads] = [native.signal_log(x) for x in rollouts]
    for a, b in zip(logs[1], logs[2]):
        assert_same_log(a, b)
    assert not np.array_equal(logs[1][0]["est_vel"], logs[1][1]["est_vel"])  # seeds differ


def test_foothold_offset_moves_the_swing_feet_and_bad_offsets_are_caught():
    base = rig()
    inp, out = kl.QuadrupedInput(), kl.QuadrupedOutput()
    c = kl.QuadrupedController(base.model, base.config)
    inp.q[:] = c.stand_pose
    inp.foothold_offset[:] = np.nan
    status = c.step(inp, out)
    assert status != kl.Status.OK and np.all(np.isfinite(out.tau))

    feet = {}
    for dx in (0.0, 0.03):
        r = rig()
        command = trot_command(0.3, 0.1)
        adapter = r.native_adapter(command)
        native._native.set_foothold_offset(adapter, np.tile([dx, 0.0, 0.0], 4))
        ro = r.native_rollout(0.8, command, adapter=adapter)
        ro.run()
        assert ro.ok
        feet[dx] = native.signal_log(ro)["foot_pos"]
    shift = (feet[0.03] - feet[0.0])[:, :, 0]
    assert shift.max() > 0.01  # swing feet land further forward
