"""The rig (sil/rig.py) on a quadruped (sil/quadruped_family.py, cpp/sil/quadruped_adapter.hpp):
command changes and pushes as events, the early stop, seeds, batch threads, both sensor paths and
the foothold-offset input."""
import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.sil import batch, native
from kiloloop.sil.events import FellBelow, Push
from kiloloop.sil.quadruped_family import stand_command
from kiloloop.scenarios.quadruped_settings import rig_from_settings
from kiloloop.scenarios.quadruped_metrics import trot_command
from kiloloop.scenarios import quadruped_trot

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")

def assert_same_log(a, b):
    assert sorted(a.names()) == sorted(b.names())
    for name in a.names():
        assert np.array_equal(a[name], b[name]), name


def rig(seed=0, **overrides):
    settings = scenarios.parse_settings(quadruped_trot.DEFAULTS, overrides)
    return rig_from_settings(settings, seed)


def test_trot_command_changes_and_a_push_fire_at_their_ticks():
    r = rig(seed=3)
    log = r.run(1.2, trot_command(0.5, 0.3), [(0.8, Push([0.0, 40.0, 0.0], 0.05))],
                stop=FellBelow(0.0))
    assert len(log["t"]) == 1200
    assert log["v_cmd"][299, 0] == 0.0 and log["v_cmd"][300, 0] == 0.5
    # The push moved the trunk sideways (world +y) within its 50 ms.
    vy = log["base_vel"][:, 1]
    assert vy[850] - vy[799] > 0.05


@pytest.mark.parametrize("ideal", ["true", "false"])
def test_both_sensor_paths_trot(ideal):
    """Realistic sensors (C++ IMU and encoder stages, the controller's own attitude) and ideal
    ones (white noise, the plant's orientation as an AHRS)."""
    r = rig(seed=5, ideal_sensors=ideal)
    assert r.config.estimator.external_attitude == (ideal == "true")
    log = r.run(0.6, trot_command(0.5, 0.2))
    assert len(log["t"]) == 600 and log["base_pos"][-1, 2] > r.fall_height


@pytest.mark.parametrize("ideal", ["true", "false"])
def test_ground_truth_feeds_the_simulators_trunk_state(ideal):
    """ground_truth (debugging): the trunk's position, quaternion and velocity follow y
    (qpos / qvel); the controller's estimate is then the simulator's state of the same tick."""
    r = rig(seed=5, ground_truth="true", ideal_sensors=ideal)
    m = r.family.measurement(r.parts, r.signals, 5, None)
    assert len(m.addresses) == 44 and m.sources[34:] == [1] * 7 + [2] * 3
    log = r.run(2.0, stand_command())
    assert log["base_pos"][:, 2].min() > 0.8 * r.config.body_height
    np.testing.assert_allclose(log["est_pos"], log["base_pos"], atol=1e-12)
    np.testing.assert_allclose(log["est_vel"], log["base_vel"], atol=1e-12)
    adapter = native._native.quadruped_adapter(r.controller, [int(i) for i in r.to_ctrl],
                                               ground_truth=True)
    with pytest.raises(ValueError, match="measurement"):
        native._native.Rollout(r.plant.model, r.plant.data, adapter, ticks=10,
                               measurement=r.measurement_addresses(),
                               actuators=[int(a) for a in r.plant._act])


def test_design_delay_is_apart_from_the_plants_delay():
    held = rig(motor_delay="0.02", design_delay="0.01")
    assert held.config.actuation_delay == pytest.approx(0.01)
    assert rig(motor_delay="0.02").config.actuation_delay == pytest.approx(0.02)
    assert held.family.motor(held.parts, held.signals).delay_ticks == 20


def test_same_seed_same_log_other_seed_other_noise():
    a = rig(seed=5).run(0.2, stand_command())
    b = rig(seed=5).run(0.2, stand_command())
    c = rig(seed=6).run(0.2, stand_command())
    assert_same_log(a, b)
    assert not np.array_equal(a["est_vel"], c["est_vel"])


def test_stop_condition_ends_the_run_after_the_first_tick_below():
    log = rig().run(0.5, stand_command(), stop=FellBelow(10.0))
    assert len(log["t"]) == 1  # the first tick's trunk is below 10 m


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
            rollouts.append(r.rollout(0.4, command, data=data, seed=seed,
                                      adapter=r.adapter(command, controller)))
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
        adapter = r.adapter(command)
        native._native.set_foothold_offset(adapter, np.tile([dx, 0.0, 0.0], 4))
        ro = r.rollout(0.8, command, adapter=adapter)
        ro.run()
        assert ro.ok
        feet[dx] = native.signal_log(ro)["foot_pos"]
    shift = (feet[0.03] - feet[0.0])[:, :, 0]
    assert shift.max() > 0.01  # swing feet land further forward
