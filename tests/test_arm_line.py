"""arm-line SIL scenario: the same criteria as `kiloloop run arm-line`."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios

arm_line = scenarios.get("arm-line")


def run(duration=None, **overrides):
    return scenarios.run_named("arm-line", overrides=overrides, duration=duration)


@pytest.fixture(scope="module")
def default_run():
    return run()


def test_arm_line_passes_its_criteria(default_run):
    r = default_run
    for name, c in r.criteria.items():
        assert c["passed"], f"{name} = {c['value']} (needs {c['op']} {c['threshold']})"
    assert r.metrics["failed_ticks"] == 0 and r.metrics["saturated_ticks"] == 0
    assert r.metrics["ticks"] == 3000
    # The line is not trivial: 29 cm and 37 deg.
    assert r.metrics["line_length_m"] > 0.25 and r.metrics["line_angle_rad"] > 0.5


def test_end_effector_ends_on_the_line_end(default_run):
    log = default_run.log
    end = log["pose_ref"][-1]
    assert np.linalg.norm(log["ee"][-1] - end[:3, 3]) < 2e-4


def test_one_tick_delay_still_within_a_millimetre(default_run):
    r = run(measurement_delay=0.001)
    assert r.passed and r.metrics["failed_ticks"] == 0
    assert r.metrics["max_ee_error_m"] > default_run.metrics["max_ee_error_m"]


def test_clik_feedback_removes_the_integration_drift(default_run):
    # K = 0 integrates J^+ v open loop: the joint reference drifts off the line.
    r = run(task_gain=0.0)
    assert r.metrics["max_ik_reference_error_m"] > 10 * default_run.metrics["max_ik_reference_error_m"]


def test_line_sampling_is_a_straight_line_with_fixed_axis_rotation(ur5_model):
    q0 = np.array([0.0, -1.5707963267948966, 1.5707963267948966, -1.5707963267948966,
                   -1.5707963267948966, 0.0])
    _, settings = scenarios.prepare(arm_line)  # the UR5's robot file gives the line
    line = arm_line.make_line(ur5_model, q0, settings)
    T0, v0, _ = line.sample(line.start_time)
    T1, v1, _ = line.sample(line.end_time)
    assert np.allclose(v0, 0) and np.allclose(v1, 0)
    d = T1[:3, 3] - T0[:3, 3]
    _, v_mid, _ = line.sample(0.5 * (line.start_time + line.end_time))
    axis = v_mid[3:] / np.linalg.norm(v_mid[3:])
    for t in np.linspace(line.start_time, line.end_time, 17)[1:-1]:
        T, v, _ = line.sample(t)
        off = T[:3, 3] - T0[:3, 3]
        assert np.linalg.norm(np.cross(off, d)) < 1e-12  # on the segment
        # Rotation about one fixed axis, at a rate proportional to the linear speed.
        assert np.allclose(v[3:] / np.linalg.norm(v[3:]), axis, atol=1e-12)
        ratio = np.linalg.norm(v[3:]) / np.linalg.norm(v[:3])
        assert abs(ratio - line.angle / line.length) < 1e-9
    # Mid-way by time, the orientation is halfway along the rotation (quintic is symmetric).
    Tm, _, _ = line.sample(0.5 * (line.start_time + line.end_time))
    R = T0[:3, :3].T @ Tm[:3, :3]
    half = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    assert abs(half - line.angle / 2) < 1e-10


def test_controller_bad_reference_holds_with_finite_torque(ur5_model):
    c = kl.CartesianTrackingController(ur5_model)
    inp, out = c.make_input(), c.make_output()
    inp.q[:] = [0.0, -1.57, 1.57, -1.57, -1.57, 0.0]
    inp.pose_ref = kl.Dynamics(ur5_model).forward_kinematics(inp.q)
    assert c.step(inp, out) == kl.Status.OK
    bad = inp.pose_ref.copy()
    bad[0, 3] = np.nan
    inp.pose_ref = bad
    inp.t = inp.stamp = 0.001
    assert c.step(inp, out) == kl.Status.NON_FINITE_REFERENCE
    assert np.all(np.isfinite(out.tau)) and np.allclose(out.qd_ref, 0)
    inp.q[0] = np.inf
    assert c.step(inp, out).failed and np.all(np.isfinite(out.tau))
    config = kl.CartesianTrackingConfig()
    config.task_gain = np.full(6, 2000.0)
    with pytest.raises(ValueError, match="task_gain"):
        kl.CartesianTrackingController(ur5_model, config)
