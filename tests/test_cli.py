"""The `kiloloop` command line, run as a user would."""
import json
import subprocess
import sys

import numpy as np


def kiloloop(*args):
    return subprocess.run([sys.executable, "-m", "kiloloop.cli", *args], capture_output=True,
                          text=True, timeout=300)


def test_list_names_arm_track():
    r = kiloloop("list")
    assert r.returncode == 0 and "arm-track" in r.stdout


def test_run_json_plot_and_log(tmp_path):
    png, npz = tmp_path / "a.png", tmp_path / "a.npz"
    r = kiloloop("run", "arm-track", "--duration", "1.0", "--json", "--plot", str(png),
                 "--log", str(npz))
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    assert report["scenario"] == "arm-track" and report["passed"] is True
    assert set(report["criteria"]) == {"max_joint_error_rad", "max_ee_error_m"}
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with np.load(npz) as log:
        assert log["q_true"].shape == (1000, 6) and log["t"].shape == (1000,)


def test_failing_scenario_exits_nonzero_and_bad_setting_exits_2():
    r = kiloloop("run", "arm-track", "--duration", "2.0", "--set", "controller=pd_gravity", "--json")
    assert r.returncode == 1 and json.loads(r.stdout)["passed"] is False
    r = kiloloop("run", "arm-track", "--set", "kp=abc")
    assert r.returncode == 2 and "kp" in r.stderr


def test_bench_quick_reports_zero_allocations():
    r = kiloloop("bench", "--quick", "--json")
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    names = {x["name"] for x in report["core"]["results"]}
    assert {"computed_torque.step", "joint_pd_gravity.step", "dynamics.inverse_dynamics"} <= names
    for x in report["core"]["results"]:
        assert x["allocations_per_call"] == 0, x["name"]
    assert report["sil"]["tick_over_mj_step"] > 0
    assert "quadruped.step" in names
    assert report["quadruped_sil"]["real_time_factor"] > 0
    if report["sil_native"]["available"]:
        quad = report["sil_native"]["quadruped"]
        for key in ("tick_over_mj_step", "real_time_factor", "real_time_factor_all_cores"):
            assert quad[key] > 0, key
        assert quad["env"]["steps_per_second"] > 0 and quad["env_vector"]["num_envs"] == 8
        aerial = report["sil_native"]["aerial"]
        for key in ("tick_over_mj_step", "real_time_factor", "real_time_factor_all_cores"):
            assert aerial[key] > 0, key
        assert not any(k.startswith("python_tick") for k in aerial)  # no Python loop to time
        assert aerial["scenario"] == "aerial-hover"
    assert report["qp"], "the QP comparison ran"
