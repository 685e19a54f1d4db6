"""The rig (sil/rig.py) on a multirotor (sil/aerial_family.py, cpp/sil/aerial_adapter.hpp):
events (pushes at the vehicle's CoM, rotor faults) and the wind act, seeds reproduce, batch threads,
the reference table and the adapter's checks, a non-finite state."""
import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.errors import InputError
from kiloloop.scenarios import aerial_hover
from kiloloop.scenarios.aerial_settings import rig_from_settings
from kiloloop.sil import aerial_family, aerial_signals, batch, native
from kiloloop.sil.aerial_signals import Wind, reference_table
from kiloloop.sil.events import GAIN, Push, RotorFault
from kiloloop.scenarios.aerial_metrics import hold

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")


def assert_same_log(a, b):
    assert sorted(a.names()) == sorted(b.names())
    for name in a.names():
        x, y = a[name], b[name]
        assert x.shape == y.shape, name
        assert np.array_equal(x, y, equal_nan=True), f"{name}: max diff {np.abs(x - y).max()}"


def rig(seed=0, **overrides):
    return rig_from_settings(scenarios.parse_settings(aerial_hover.DEFAULTS, overrides), seed)


def test_events_and_wind_act_on_the_vehicle():
    quiet = rig(seed=2).run(1.0, hold(rig()))
    r = rig(seed=2)
    pushed = r.run(1.0, hold(r), events=[(0.5, Push(np.array([0.0, 20.0, 0.0]), 0.02))])
    vy = pushed["base_vel"][:, 1] - quiet["base_vel"][:, 1]
    assert vy[:500].max() == 0.0 and vy[530] > 0.1  # 20 N x 20 ms on ~1.8 kg: ~0.2 m/s
    r = rig(seed=2)
    fault = r.run(1.0, hold(r), events=[(0.5, RotorFault(0, 0.5))])
    # Rotor 0's thrust over its command, averaged (the 30 ms rotor lag and noise in between).
    ratio = fault["thrust"][:, 0] / fault["thrust_cmd"][:, 0]
    assert abs(ratio[300:500].mean() - 1.0) < 0.05 and abs(ratio[800:1000].mean() - 0.5) < 0.05
    r = rig(seed=2)
    wind = Wind(np.array([5.0, 0.0, 0.0]), 0.2, 1.0, 0.5, 0.05, seed=7)
    windy = r.run(1.0, hold(r), disturbances=[wind])
    f = windy["wind_force"]
    # Ramped in from zero; then about 1/2 1.225 0.05 5^2 = 0.77 N along the wind.
    assert abs(f[0, 0]) < 0.1 and f[900:, 0].mean() > 0.5
    assert not np.array_equal(windy["base_pos"], quiet["base_pos"])


def test_same_seed_same_log_other_seed_other_noise():
    a = rig(seed=5).run(0.2, hold(rig()))
    b = rig(seed=5).run(0.2, hold(rig()))
    c = rig(seed=6).run(0.2, hold(rig()))
    assert_same_log(a, b)
    assert not np.array_equal(a["quat_des"], c["quat_des"])


def test_batch_on_two_threads_equals_one_by_one():
    r = rig()
    command = hold(r)
    logs = {}
    for threads in (1, 2):
        rollouts = []
        for seed in (0, 1, 2):
            data = mujoco.MjData(r.plant.model)
            mujoco.mj_copyData(data, r.plant.model, r.plant.data)
            adapter = r.adapter(command, kl.AerialController(r.model, r.config), 300)
            rollouts.append(r.rollout(0.3, command, data=data, seed=seed, adapter=adapter))
        batch.run(rollouts, threads=threads)
        assert all(x.ok and x.ticks_run == 300 for x in rollouts)
        logs[threads] = [native.signal_log(x) for x in rollouts]
    for a, b in zip(logs[1], logs[2]):
        assert_same_log(a, b)
    assert not np.array_equal(logs[1][0]["quat_des"], logs[1][1]["quat_des"])  # seeds differ


def test_reference_table_is_what_the_command_sets_each_tick():
    r = rig()
    step = np.array([np.cos(0.05), np.sin(0.05), 0.0, 0.0])

    def command(t, inp):
        inp.position_ref[:] = (0.0, 0.0, 1.0 + t)
        inp.flight_mode = kl.FlightMode.ATTITUDE if t >= 0.002 else kl.FlightMode.POSITION
        inp.quat_ref[:] = step

    table = reference_table(r.controller, command, 4)
    assert aerial_signals.REFERENCE_WIDTH == native._native.AERIAL_REFERENCE_WIDTH
    assert table.shape == (4, native._native.AERIAL_REFERENCE_WIDTH + 3 * r.controller.nq)
    np.testing.assert_array_equal(table[:, 2], [1.0, 1.001, 1.002, 1.003])
    np.testing.assert_array_equal(table[:, 10], [0, 0, 1, 1])
    np.testing.assert_array_equal(table[3, 11:15], step)
    log = r.run(0.004, command)
    np.testing.assert_array_equal(log["pos_ref"][:, 2], table[:, 2])


def test_bad_tables_and_events_are_refused():
    r = rig()
    width = native._native.AERIAL_REFERENCE_WIDTH + 3 * r.controller.nq
    to_ctrl = [int(i) for i in r.to_ctrl]
    with pytest.raises(ValueError, match="references"):
        native._native.aerial_adapter(r.controller, to_ctrl, np.zeros((3, width - 1)))
    bad = np.zeros((2, width))
    bad[1, 0] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        native._native.aerial_adapter(r.controller, to_ctrl, bad)
    with pytest.raises(InputError, match="rotor"):
        r.rollout(0.1, hold(r), events=[(0.0, RotorFault(99, 0.5))])
    adapter = native._native.aerial_adapter(r.controller, to_ctrl, np.zeros((1, width)))
    m = r.family.measurement(r.parts, r.signals, 0, None)
    addr, source = m.addresses, m.sources
    with pytest.raises(ValueError, match="gain event"):
        native._native.Rollout(r.plant.model, r.plant.data, adapter, ticks=1, measurement=addr,
                               measurement_source=source,
                               actuators=[int(a) for a in r.plant._rotor_act] + [int(a) for a in r.plant._act],
                               events=[(0.0, GAIN, [1e6, 0.5])])
    with pytest.raises(ValueError, match="measurement_source"):
        native._native.Rollout(r.plant.model, r.plant.data, adapter, ticks=1, measurement=addr,
                               measurement_source=[5] * len(addr),
                               actuators=[int(a) for a in r.plant._rotor_act] + [int(a) for a in r.plant._act])


def test_a_non_finite_state_gives_a_status_and_finite_commands(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to MUJOCO_LOG.TXT in the cwd
    r = rig()
    r.plant.data.qvel[:] = np.nan  # the controller sees NaN; MuJoCo warns and resets the state
    log = r.run(0.05, hold(r))
    assert log["status"][0] == int(kl.Status.NON_FINITE_MEASUREMENT)
    assert np.all(np.isfinite(log["thrust_cmd"]))


def test_attitude_noise_is_a_small_unit_rotation_of_the_given_sigma():
    sigma, n = 0.002, 16
    stage = native._native.AttitudeNoise(12, sigma, 3, n)
    q = np.array([np.cos(0.3), 0.0, np.sin(0.3), 0.0])
    y = np.zeros(n)
    y[12:16] = q
    angles = []
    for _ in range(4000):
        out = stage.apply(0.0, y)
        assert np.array_equal(out[:12], y[:12])
        assert abs(np.linalg.norm(out[12:16]) - 1.0) < 1e-12
        angles.append(2 * np.arccos(min(1.0, abs(out[12:16] @ q))))
    # The angle of a 3-D rotation vector of N(0, sigma^2) per axis: RMS sigma sqrt(3).
    assert abs(np.sqrt(np.mean(np.square(angles))) / (sigma * np.sqrt(3)) - 1.0) < 0.05


def test_wind_force_is_the_drag_of_the_logged_wind_on_the_logged_velocity():
    r = rig(seed=1)
    wind = Wind(np.array([3.0, 4.0, 0.0]), 0.3, 1.5, 0.5, 0.05, seed=11)
    log = r.run(0.6, hold(r), disturbances=[wind])
    rel = log["wind"] - log["base_vel"]
    expected = 0.5 * 1.225 * 0.05 * np.linalg.norm(rel, axis=1)[:, None] * rel
    np.testing.assert_allclose(log["wind_force"], expected, rtol=1e-12, atol=1e-15)
    gust = log["wind"][400:] - np.array([3.0, 4.0, 0.0])  # ramp over after 0.3 s
    assert 0.3 < gust[:, 0].std() < 3.0 and gust[:, 2].std() < gust[:, 0].std()


@pytest.mark.parametrize("module", ["aerial_attitude_step", "aerial_arm_sweep", "aerial_reach"])
def test_a_commands_own_table_equals_sampling_it_tick_by_tick(module, monkeypatch):
    # The scenarios give their references as a table at once; the generic sampler calls the
    # command every tick on one input. Both must give the same rows.
    import importlib

    seen = {}
    real = aerial_family.reference_table

    def both(controller, command, ticks):
        fast = real(controller, command, ticks)
        table = command.table
        del command.table
        slow = real(controller, command, ticks)
        command.table = table
        seen["fast"], seen["slow"] = fast, slow
        return fast

    monkeypatch.setattr(aerial_family, "reference_table", both)
    mod = importlib.import_module(f"kiloloop.scenarios.{module}")
    scenarios.run_named(mod.NAME, duration=1.2)
    np.testing.assert_array_equal(seen["fast"], seen["slow"])
    assert np.ptp(seen["fast"], axis=0).max() > 0  # the references do change over the run
