"""quadruped-turn (0.5 m/s with 0.5 rad/s of yaw): our model and Go1 pass at 10 and 35 ms, and
report each leg's peak load. A turn places each foot where its hip will be at mid-stance (the
trunk turned on at the commanded yaw rate over half a stance) and feeds the centripetal
acceleration forward; before, Go1's yaw rate RMS error at 35 ms was 0.0954-0.0984 rad/s on seeds
0-4 (limit 0.1), now 0.080-0.083, so the 0.09 bound below fails on the old controller."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.bench.quadruped_robots import robot_file


def _robot(which, tmp_path):
    if which == "quadruped":
        return kl.Robot.load("quadruped")
    path = robot_file(which, tmp_path)
    if path is None:
        pytest.skip("example-robot-data not installed")
    return kl.Robot.load(path)


@pytest.mark.parametrize("which", ["quadruped", "go1"])
@pytest.mark.parametrize("delay", [0.010, 0.035])
def test_turning_trot_passes_and_reports_leg_loads(tmp_path, which, delay):
    r = scenarios.run_named("quadruped-turn", _robot(which, tmp_path), {"motor_delay": delay}, seed=0)
    for key, c in r.criteria.items():
        assert c["passed"], f"{which} {delay}: {key} = {c['value']} (needs {c['op']} {c['threshold']})"
    assert r.metrics["mean_yaw_rate"] == pytest.approx(0.5, abs=0.02)
    loads = [r.metrics[f"peak_load_{leg}_bw"] for leg in ("FL", "FR", "RL", "RR")]
    assert all(np.isfinite(loads)) and min(loads) > 0.3 and max(loads) < 2.0
    if delay == 0.035:
        assert r.metrics["yaw_rate_rms_error"] < 0.09
