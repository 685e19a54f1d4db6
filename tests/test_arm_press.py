"""arm-press SIL scenario: the same criteria as `kiloloop run arm-press` (hybrid force/position on
a MuJoCo table with a force sensor), plus the behaviour around it."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios

arm_press = scenarios.get("arm-press")


def run(duration=None, **overrides):
    return scenarios.run_named("arm-press", overrides=overrides, duration=duration)


@pytest.fixture(scope="module")
def hybrid():
    return run()


def test_hybrid_passes_its_criteria(hybrid):
    r = hybrid
    for name, c in r.criteria.items():
        assert c["passed"], f"{name} = {c['value']} (needs {c['op']} {c['threshold']})"
    assert r.metrics["failed_ticks"] == 0
    assert abs(r.metrics["mean_force_N"] - 10.0) < 0.05
    # Friction really acts while sliding (the force loop rejects a real disturbance).
    assert r.metrics["max_tangential_force_N"] > 2.0


def test_high_friction_still_passes():
    # Friction 1.0 doubles the tangential disturbance the force and x loops must reject.
    r = run(friction=1.0)
    assert r.passed, {k: c["value"] for k, c in r.criteria.items()}
    assert r.metrics["max_tangential_force_N"] > 8.0


def test_projected_motion_wrench_rejects_friction_better(hybrid):
    # The full Lambda Omega a pushes on the force axis whenever friction holds an x error.
    full = run(project_motion_wrench=False)
    assert full.metrics["failed_ticks"] == 0
    assert full.metrics["max_force_error_N"] > 2 * hybrid.metrics["max_force_error_N"]


def test_force_follows_its_reference():
    r = run(duration=1.0, force=5.0)
    assert abs(r.metrics["mean_force_N"] - 5.0) < 0.1
    assert r.metrics["max_force_error_N"] < 0.5


def test_impedance_without_force_feedback_is_worse(hybrid):
    imp = run(controller="impedance")
    assert imp.metrics["failed_ticks"] == 0
    assert imp.metrics["max_force_error_N"] > 2 * hybrid.metrics["max_force_error_N"]


def test_cartesian_controllers_bad_input_from_python():
    model = kl.RobotModel.from_urdf(str(kl.models_dir() / "ur5" / "ur5.urdf"))
    for c in (kl.HybridForcePositionController(model), kl.CartesianImpedanceController(model)):
        inp, out = c.make_input(), c.make_output()
        inp.q[:] = scenarios.prepare(arm_press)[1]["q0"]  # the UR5's pressing pose
        T = kl.Dynamics(model).forward_kinematics(inp.q)
        inp.p_ref[:], inp.R_ref = T[:3, 3], T[:3, :3]
        assert c.step(inp, out) == kl.Status.OK
        inp.qd[2] = np.nan
        assert c.step(inp, out) == kl.Status.NON_FINITE_MEASUREMENT
        assert np.all(np.isfinite(out.tau))
        inp.qd[2] = 0.0
        inp.R_ref = 2.0 * np.eye(3)
        assert c.step(inp, out) == kl.Status.NON_FINITE_REFERENCE
        assert np.all(np.isfinite(out.tau))
    cfg = kl.HybridForcePositionConfig()
    cfg.selection = np.array([1, 1, 0.5, 1, 1, 1.0])
    with pytest.raises(ValueError, match="selection"):
        kl.HybridForcePositionController(model, cfg)
