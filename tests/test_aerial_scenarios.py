"""The aerial SIL scenarios (IMU noise on), each judged by the criteria that live beside it, plus
the controller's bad-input policy through the bindings. ~10 s in all on a laptop core."""
import json
import math

import numpy as np
import pytest

import kiloloop as kl
from kiloloop import cli, scenarios
from kiloloop.sil.aerial_family import aerial_paths, rotor_config


def run(name, **overrides):
    module = scenarios.get(name)
    result = module.run(scenarios.parse_settings(module.DEFAULTS, overrides), seed=0)
    print(name, json.dumps(result.metrics))
    return result


def test_hover_holds_position_and_attitude():
    r = run("aerial-hover")
    assert r.settings["nonideal"]  # noise on
    assert r.metrics["max_position_error_m"] < 0.02
    assert r.metrics["attitude_error_rms_deg"] < 0.5
    assert r.passed


def test_attitude_step_both_laws():
    r = run("aerial-attitude-step")
    for law in ("quaternion_pd", "geometric_so3"):
        assert r.metrics[f"overshoot_{law}"] < 0.15
        assert r.metrics[f"steady_state_error_rad_{law}"] < 0.01
    assert r.passed


def test_arm_sweep_feedforward_reduces_attitude_error():
    r = run("aerial-arm-sweep")
    assert r.metrics["attitude_ptp_deg_ff"] < r.metrics["attitude_ptp_deg_no_ff"]
    assert r.metrics["attitude_ptp_reduction"] >= 0.60
    assert r.passed


def test_reach_tracks_the_line():
    r = run("aerial-reach")
    assert r.metrics["max_ee_error_m"] < 0.01
    assert r.passed


def test_rotor_fault_stays_airborne_and_near_hover():
    r = run("aerial-rotor-fault")
    assert r.metrics["max_hover_deviation_m"] < 0.10
    assert r.passed


def test_cli_runs_a_scenario_as_json(capsys):
    code = cli.main(["run", "aerial-hover", "--duration", "1.5", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert out["scenario"] == "aerial-hover" and code == (0 if out["passed"] else 1)
    assert "max_position_error_m" in out["metrics"]


@pytest.fixture(scope="module")
def controller():
    model = kl.RobotModel.from_urdf(str(aerial_paths()[0]), tip="ee_link")
    config = kl.AerialConfig()
    config.rotors = rotor_config()
    return kl.AerialController(model, config)


@pytest.mark.parametrize("field,value,status", [
    ("gyro", math.nan, "NON_FINITE_MEASUREMENT"),
    ("accel", math.inf, "NON_FINITE_MEASUREMENT"),
    ("q", math.nan, "NON_FINITE_MEASUREMENT"),
    ("position_ref", math.nan, "NON_FINITE_REFERENCE"),
])
def test_bad_inputs_give_a_status_and_finite_commands(controller, field, value, status):
    controller.reset()
    inp, out = controller.make_input(), controller.make_output()
    inp.position[:] = inp.position_ref[:] = (0.0, 0.0, 1.0)
    getattr(inp, field)[0] = value
    assert controller.step(inp, out) == getattr(kl.Status, status)
    assert np.all(np.isfinite(out.thrust)) and np.all(np.isfinite(out.tau))


def test_wrong_sizes_and_stale_state(controller):
    controller.reset()
    inp, out = controller.make_input(), controller.make_output()
    inp.q = np.zeros(2)
    assert controller.step(inp, out) == kl.Status.BAD_SIZE
    inp = controller.make_input()
    inp.t, inp.stamp = 1.0, 0.5
    assert controller.step(inp, out) == kl.Status.STALE_MEASUREMENT
    assert np.all(np.isfinite(out.thrust))


def test_flipped_vehicle_stops_the_motors(controller):
    controller.reset()
    inp, out = controller.make_input(), controller.make_output()
    a = math.radians(70)
    inp.quat[:] = (math.cos(a / 2), 0.0, math.sin(a / 2), 0.0)
    assert controller.step(inp, out) == kl.Status.SAFE_STOP
    assert out.safe_stop and np.all(out.thrust == 0.0)
    controller.reset()
