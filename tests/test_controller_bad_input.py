"""Bad input through the bindings: a Status and a finite, safe torque, never an exception or NaN."""
import numpy as np
import pytest

import kiloloop as kl

CONTROLLERS = [kl.ComputedTorqueController, kl.JointPdGravityController]


def _valid_input(ctrl):
    inp = ctrl.make_input()
    inp.q[:] = [0.0, -1.5, 1.5, -1.5, -1.5, 0.0]
    inp.q_ref[:] = inp.q + 0.01
    return inp


@pytest.mark.parametrize("cls", CONTROLLERS)
def test_valid_step_is_ok(cls, ur5_model):
    ctrl = cls(ur5_model)
    out = ctrl.make_output()
    status = ctrl.step(_valid_input(ctrl), out)
    assert status == kl.Status.OK and out.status == status
    assert np.all(np.isfinite(out.tau))


@pytest.mark.parametrize("cls", CONTROLLERS)
@pytest.mark.parametrize("field,value,expected", [
    ("q", np.nan, kl.Status.NON_FINITE_MEASUREMENT),
    ("qd", np.inf, kl.Status.NON_FINITE_MEASUREMENT),
    ("q_ref", np.nan, kl.Status.NON_FINITE_REFERENCE),
    ("qdd_ref", -np.inf, kl.Status.NON_FINITE_REFERENCE),
])
def test_non_finite_inputs(cls, field, value, expected, ur5_model):
    ctrl = cls(ur5_model)
    good, out = _valid_input(ctrl), ctrl.make_output()
    ctrl.step(good, out)
    getattr(good, field)[2] = value
    assert ctrl.step(good, out) == expected
    assert expected.failed
    assert np.all(np.isfinite(out.tau))
    assert np.all(np.abs(out.tau) <= ur5_model.effort_limit)


@pytest.mark.parametrize("cls", CONTROLLERS)
def test_wrong_sizes_and_stale_data(cls, ur5_model):
    ctrl = cls(ur5_model)
    inp, out = _valid_input(ctrl), ctrl.make_output()
    inp.q = np.zeros(3)
    assert ctrl.step(inp, out) == kl.Status.BAD_SIZE
    assert np.all(np.isfinite(out.tau))
    inp = _valid_input(ctrl)
    inp.t, inp.stamp = 1.0, 0.5
    assert ctrl.step(inp, out) == kl.Status.STALE_MEASUREMENT
    small = kl.JointControlOutput()
    small.tau = np.zeros(2)
    assert ctrl.step(_valid_input(ctrl), small) == kl.Status.BAD_SIZE
    assert ctrl.counters.bad_size >= 2 and ctrl.counters.stale_measurement == 1


def test_step_is_bit_identical_across_instances(ur5_model, rng):
    a, b = kl.ComputedTorqueController(ur5_model), kl.ComputedTorqueController(ur5_model)
    for _ in range(50):
        inp = a.make_input()
        inp.q[:], inp.qd[:], inp.q_ref[:] = rng.uniform(-1, 1, (3, 6))
        oa, ob = a.make_output(), b.make_output()
        a.step(inp, oa)
        b.step(inp, ob)
        assert oa.tau.tobytes() == ob.tau.tobytes()


def test_input_fields_are_views_into_the_core(ur5_model):
    ctrl = kl.ComputedTorqueController(ur5_model)
    inp = ctrl.make_input()
    inp.q[:] = 0.25  # writes straight into the C++ struct
    np.testing.assert_array_equal(inp.q, np.full(6, 0.25))


@pytest.mark.parametrize("cls", CONTROLLERS)
def test_time_going_backwards_is_stale(cls, ur5_model):
    """A sample older than one already acted on is stale (control/rules.hpp); reset() forgets
    the order."""
    ctrl = cls(ur5_model)
    inp, out = _valid_input(ctrl), ctrl.make_output()
    inp.t, inp.stamp = 1.0, 0.999
    assert ctrl.step(inp, out) == kl.Status.OK
    inp.t, inp.stamp = 0.9985, 0.9985  # within the age limit, but older than the last sample
    assert ctrl.step(inp, out) == kl.Status.STALE_MEASUREMENT
    assert np.all(np.isfinite(out.tau))
    ctrl.reset()
    assert ctrl.step(inp, out) == kl.Status.OK


@pytest.mark.parametrize("cls", CONTROLLERS)
def test_extreme_finite_inputs_give_finite_torque_within_limits(cls, ur5_model):
    ctrl = cls(ur5_model)
    out = ctrl.make_output()
    for field in ("q", "qd", "q_ref", "qd_ref", "qdd_ref"):
        for value in (1e308, -1e308, 5e-324, 1e154):
            inp = _valid_input(ctrl)
            getattr(inp, field)[:] = value
            ctrl.step(inp, out)
            assert np.all(np.isfinite(out.tau)), (field, value)
            assert np.all(np.abs(out.tau) <= ur5_model.effort_limit), (field, value)


def test_status_counters_are_one_struct_with_the_former_names(ur5_model):
    ctrl = kl.ComputedTorqueController(ur5_model)
    inp, out = _valid_input(ctrl), ctrl.make_output()
    ctrl.step(inp, out)
    inp.q[0] = np.nan
    ctrl.step(inp, out)
    c = ctrl.counters
    assert isinstance(c, kl.StatusCounters)
    assert kl.StepCounters is kl.StatusCounters and kl.CartesianCounters is kl.StatusCounters
    assert c.ticks == 2 and c.ok == 1 and c.non_finite_measurement == 1
    assert c.count(kl.Status.NON_FINITE_MEASUREMENT) == 1 and c.failures == 1
    assert sum(c.as_dict().values()) == c.ticks
