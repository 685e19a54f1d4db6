"""arm-track SIL scenario: the same criteria as `kiloloop run arm-track`."""
import pytest

from kiloloop import scenarios

arm_track = scenarios.get("arm-track")


def run(**overrides):
    return scenarios.run_named("arm-track", overrides=overrides)


@pytest.fixture(scope="module")
def computed_torque():
    return run()


def test_computed_torque_passes_its_criteria(computed_torque):
    r = computed_torque
    for name, c in r.criteria.items():
        assert c["passed"], f"{name} = {c['value']} (needs {c['op']} {c['threshold']})"
    assert r.metrics["failed_ticks"] == 0 and r.metrics["saturated_ticks"] == 0
    assert r.metrics["ticks"] == 4500


def test_pd_gravity_tracks_far_worse_than_computed_torque(computed_torque):
    pd = run(controller="pd_gravity")
    assert pd.metrics["failed_ticks"] == 0
    # Same bandwidth at q0; without the model's inertia and Coriolis terms PD lags by far more.
    assert pd.metrics["max_joint_error_rad"] > 20 * computed_torque.metrics["max_joint_error_rad"]
    assert pd.metrics["max_joint_error_rad"] < 0.1  # but it is stable and follows


def test_one_tick_measurement_delay_costs_about_one_tick_of_motion(computed_torque):
    # The controller acts on q from 1 ms ago: the error grows to about |qd| * 1 ms (~1 mrad
    # here), stays bounded, and the loop stays stable.
    r = run(measurement_delay=0.001)
    assert r.metrics["failed_ticks"] == 0
    assert computed_torque.metrics["max_joint_error_rad"] < r.metrics["max_joint_error_rad"] < 3e-3


def test_unmodelled_plant_damping_degrades_tracking(computed_torque):
    r = run(damping=2.0)
    assert r.metrics["max_joint_error_rad"] > computed_torque.metrics["max_joint_error_rad"]


def test_unknown_setting_is_rejected():
    with pytest.raises(ValueError, match="unknown setting"):
        scenarios.parse_settings(arm_track.DEFAULTS, ["nope=1"])
