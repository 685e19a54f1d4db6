"""arm-estop SIL scenario: the same criteria as `kiloloop run arm-estop`, plus the supervisor's
behaviour around it (no false trips, stop time scales with the deceleration, Python bindings)."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios

arm_estop = scenarios.get("arm-estop")


def run(duration=None, **overrides):
    return scenarios.run_named("arm-estop", overrides=overrides, duration=duration)


@pytest.fixture(scope="module")
def estop():
    return run()


def test_estop_passes_its_criteria(estop):
    for name, c in estop.criteria.items():
        assert c["passed"], f"{name} = {c['value']} (needs {c['op']} {c['threshold']})"
    assert estop.metrics["estop_status_ticks"] > 0


def test_no_estop_no_trip():
    r = run(duration=1.5, t_estop=100.0)
    assert r.metrics["trips_before_estop"] == 0
    assert r.metrics["holding_at_end"] == 0


def test_stop_time_scales_with_deceleration(estop):
    slow = run(duration=2.0, stop_deceleration=2.5)
    assert slow.passed, {k: c for k, c in slow.criteria.items() if not c["passed"]}
    ratio = slow.metrics["stop_time_s"] / estop.metrics["stop_time_s"]
    assert 1.8 < ratio < 2.2  # a_stop halved: twice the time (same speed at the e-stop)


def test_supervisor_from_python():
    model = kl.RobotModel.from_urdf(str(kl.models_dir() / "ur5" / "ur5.urdf"))
    sup = kl.ArmSupervisor(model)
    inp, out = sup.make_input(), sup.make_output()
    inp.q[:] = [0.0, -1.2, 1.6, -1.97, -1.57, 0.0]
    inp.tau_command[:] = 1.0
    assert sup.step(inp, out) == kl.Status.OK
    np.testing.assert_array_equal(out.tau, inp.tau_command)
    inp.t = inp.stamp = 0.001
    inp.estop = True
    assert sup.step(inp, out) == kl.Status.EMERGENCY_STOP
    assert out.mode in (kl.SupervisorMode.STOPPING, kl.SupervisorMode.HOLDING)
    assert sup.counters.estops == 1
    inp.q[0] = np.nan
    assert sup.step(inp, out) == kl.Status.NON_FINITE_MEASUREMENT
    assert np.all(np.isfinite(out.tau))
    cfg = kl.ArmSupervisorConfig()
    cfg.stop_deceleration = np.array([-1.0])
    with pytest.raises(ValueError, match="stop_deceleration"):
        kl.ArmSupervisor(model, cfg)
