"""The quadruped adapter's ground-truth option (cpp/sil/quadruped_adapter.hpp, ground_truth=True):
the controller fed the simulator's base position, quaternion and linear velocity, appended to the
measurement from qpos / qvel, natively; against QuadrupedRig's per-tick Python loop with
RigSettings.ground_truth (sil/quadruped_rig.py `_loop`), same settings and seed."""
import numpy as np
import pytest

from kiloloop import scenarios
from kiloloop.scenarios import quadruped_stand
from kiloloop.sil import native
from kiloloop.sil.quadruped_rig import JOINTS, rig_from_settings, stand_command

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")

DURATION = 2.0  # [s]
SEED = 5
# Summed by numpy in the Python loop, by C++ natively: equal to rounding, never fed back
# (tests/test_native_quadruped.py).
ROUNDED = {"foot_force"}
# [q; qd; gyro; accel; quat] the rig measures, then the 10 ground-truth entries.
MEASURED = 2 * JOINTS + 10


def ground_truth_rig(ideal_sensors: bool):
    settings = scenarios.parse_settings(quadruped_stand.DEFAULTS,
                                        {"ground_truth": "true",
                                         "ideal_sensors": str(ideal_sensors).lower()})
    return rig_from_settings(settings, SEED)


def ground_truth_rollout(rig, duration: float):
    """A native Rollout built by hand: the rig's measurement plus the free joint's position and
    quaternion (qpos) and linear velocity (qvel), with the rig's sensor and motor models."""
    p, s = rig.plant, rig.signals
    fq, fd = int(p._free_q), int(p._free_d)
    measurement = rig.measurement_addresses() + list(range(fq, fq + 7)) + list(range(fd, fd + 3))
    source = [0] * MEASURED + [1] * 7 + [2] * 3
    command = stand_command()
    adapter = native._native.quadruped_adapter(rig.controller, [int(i) for i in rig.to_ctrl],
                                               command.segments[0][1], command.segments[0][2],
                                               ground_truth=True)
    assert adapter.measurement_size == MEASURED + 10
    # The sensor model's sigma / quantum cover y's first 34 entries (the rig's arrays as they are):
    # the appended ground truth is neither noised nor quantized and draws no normals, so the noise
    # stream is the Python loop's (34 normals a tick). Stages touch only their own slices.
    return native._native.Rollout(
        p.model, p.data, adapter, ticks=native.ticks_of(duration), control_dt=0.001,
        measurement=measurement, measurement_source=source, actuators=[int(a) for a in p._act],
        sigma=s.sigma, quantum=s.quantum, seed=s.seed, motor_delay_ticks=s.motor_delay_ticks,
        motor_limit=s.motor_limit, events=command.reference_events(), probes=rig.native_probes(),
        stages=s.stages())


@pytest.mark.parametrize("ideal_sensors", [False, True])
def test_ground_truth_native_stands_and_equals_python_loop(ideal_sensors):
    rig = ground_truth_rig(ideal_sensors)
    assert rig.settings.ground_truth and not rig.runs_natively(stand_command())
    r = ground_truth_rollout(rig, DURATION)
    r.run()
    assert r.ok and r.ticks_run == native.ticks_of(DURATION), r.error
    log = native.signal_log(r)
    # It stands: the trunk stays above 0.8 x its standing height for the 2 s.
    assert log["base_pos"][:, 2].min() > 0.8 * rig.config.body_height
    assert np.all(log["status"] >= 0)

    python = ground_truth_rig(ideal_sensors).run(DURATION, stand_command(), native=False)
    shared = sorted(set(log.names()) & set(python.names()))
    assert {"tau", "base_pos", "base_quat", "base_vel", "est_pos", "est_vel", "est_quat"} <= set(shared)
    for name in shared:
        a, b = log[name], python[name]
        assert a.shape == b.shape, name
        if name in ROUNDED:
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9, err_msg=name)
        else:
            assert np.array_equal(a, b), f"{name}: max diff {np.abs(a - b).max()}"


def test_ground_truth_changes_what_the_controller_sees():
    # With ground truth the estimator's outputs are the simulator's state, so the controller's
    # estimate equals the logged ground truth (same tick, no delay).
    rig = ground_truth_rig(False)
    r = ground_truth_rollout(rig, 0.2)
    r.run()
    log = native.signal_log(r)
    np.testing.assert_allclose(log["est_pos"], log["base_pos"], atol=1e-12)
    np.testing.assert_allclose(log["est_vel"], log["base_vel"], atol=1e-12)


def test_ground_truth_needs_the_longer_measurement():
    rig = ground_truth_rig(False)
    adapter = native._native.quadruped_adapter(rig.controller, [int(i) for i in rig.to_ctrl],
                                               ground_truth=True)
    p = rig.plant
    with pytest.raises(ValueError, match="measurement"):
        native._native.Rollout(p.model, p.data, adapter, ticks=10,
                               measurement=rig.measurement_addresses(),
                               actuators=[int(a) for a in p._act])
