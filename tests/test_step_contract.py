"""One step contract across the controllers' Python faces (issue 12, item 4): every composed
controller has step, one reset() (no reset_* variants) and StatusCounters under `counters`."""
import pytest

import kiloloop as kl

CONTROLLERS = ["ComputedTorqueController", "JointPdGravityController",
               "CartesianImpedanceController", "HybridForcePositionController",
               "CartesianTrackingController", "ArmSupervisor", "QuadrupedController",
               "AerialController"]


@pytest.mark.parametrize("name", CONTROLLERS)
def test_one_reset_name_and_status_counters(name):
    cls = getattr(kl, name)
    assert callable(getattr(cls, "step")) and callable(getattr(cls, "reset"))
    assert isinstance(cls.__dict__["counters"], property)
    assert [a for a in dir(cls) if a.startswith("reset_")] == []


def test_quadruped_counts_its_steps_and_reset_forgets_the_order():
    from kiloloop.robot.quadruped import controller_config

    robot = kl.Robot.load("quadruped")
    ctrl = kl.QuadrupedController(robot.model(), controller_config(robot))
    inp, out = kl.QuadrupedInput(), kl.QuadrupedOutput()
    inp.q = ctrl.stand_pose
    inp.t = inp.stamp = 0.010
    assert int(ctrl.step(inp, out)) >= 0
    inp.t = inp.stamp = 0.005  # older than the stamp already used
    assert ctrl.step(inp, out) == kl.Status.STALE_MEASUREMENT
    assert ctrl.counters.ticks == 2 and ctrl.counters.stale_measurement == 1
    ctrl.reset()
    assert int(ctrl.step(inp, out)) >= 0
