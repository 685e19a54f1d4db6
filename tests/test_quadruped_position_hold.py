"""The trunk's position hold across the commanded heading (QuadrupedConfig::kp_position, x and y
along and across the heading): kept where the actuation delay leaves the roll loop as designed,
dropped where the delay lowers it. A push then leaves the robot walking on from where it was
pushed instead of back sideways on two diagonal feet, which asked for a roll moment the slowed
roll loop corrected too late: Go1's 0.4 N s/kg push at 35 ms rolled 1.103 deg after recovery on
seed 1 (limit 1) with the hold."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.bench.quadruped_robots import robot_file
from kiloloop.robot.quadruped import controller_config


def _derived(robot, delay):
    config = controller_config(robot, actuation_delay=delay)
    config.dt = 0.001
    return kl.QuadrupedController(robot.model(), config).config


def _robots(tmp_path):
    robots = [kl.Robot.load(kl.models_dir() / "quadruped" / "robot.toml")]
    go1 = robot_file("go1", tmp_path)
    if go1 is not None:
        robots.append(kl.Robot.load(go1))
    return robots


@pytest.mark.parametrize("delay", [0.0, 0.010, 0.020])
def test_hold_kept_where_the_roll_loop_is_not_lowered(tmp_path, delay):
    for robot in _robots(tmp_path):
        cfg = _derived(robot, delay)
        assert cfg.kp_orientation[0] == kl.QuadrupedConfig().kp_orientation[0]
        assert cfg.kp_position[1] == kl.QuadrupedConfig().kp_position[1]


@pytest.mark.parametrize("delay", [0.025, 0.035])
def test_hold_across_the_heading_dropped_where_the_delay_lowers_the_roll_loop(tmp_path, delay):
    for robot in _robots(tmp_path):
        cfg = _derived(robot, delay)
        w_max = cfg.trunk_delay_margin / (delay + cfg.dt)  # [rad/s] the delay's cap
        assert cfg.kp_orientation[0] == pytest.approx(w_max ** 2, rel=1e-12)
        assert cfg.kp_position[1] == 0.0
        assert cfg.kp_position[0] == kl.QuadrupedConfig().kp_position[0]  # along: kept


def test_go1_recovers_the_larger_push_at_35_ms(tmp_path):
    """Seed 1 failed with the hold (1.103 deg); every criterion passes without it."""
    path = robot_file("go1", tmp_path)
    if path is None:
        pytest.skip("example-robot-data not installed")
    r = scenarios.run_named("quadruped-push", kl.Robot.load(path),
                            {"motor_delay": 0.035, "impulse_per_kg": 0.4}, seed=1)
    for key, c in r.criteria.items():
        assert c["passed"], f"{key} = {c['value']} (needs {c['op']} {c['threshold']})"
    assert np.isfinite(r.metrics["roll_after_recovery_deg"])
