"""Scenario files (issue 30): the format, the three families' runs, errors as one line naming
the file and key (exit 2), baselines, sensor dropouts and payloads, the pytest plugin in a
user's repository, b2b over a scenario file."""
from __future__ import annotations

import importlib.metadata
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import kiloloop as kl
from kiloloop import cli
from kiloloop.scenarios import scenario_file as sf

import user_repo

ARM = '''name = "arm_mission"
robot = "ur5"
duration = 2.5
[reference]
joint = { t = [0.0, 1.0, 2.0], q = [[0.0, -1.2, 1.4, -1.6, -1.5, 0.2], [0.3, -1.0, 1.2, -1.4, -1.5, 0.4], [0.0, -1.2, 1.4, -1.6, -1.5, 0.2]] }
[criteria]
"max(joint_error)" = "< 0.001"
"max(ee_error, 0.5)" = "< 0.001"
"max_abs(tau[shoulder_lift_joint])" = "< 150"
'''


def write(tmp_path: Path, text: str, name: str = "mission.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def run_cli(args, capsys):
    rc = cli.main(args)
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_arm_joint_waypoints_pass_and_name_their_signals(tmp_path, capsys):
    path = write(tmp_path, ARM)
    rc, out, _ = run_cli(["run", str(path), "--log", str(tmp_path / "a.npz"),
                          "--plot", str(tmp_path / "a.png")], capsys)
    assert rc == 0, out
    assert "PASSED" in out and "max(joint_error)" in out
    log = np.load(tmp_path / "a.npz")
    for name in sf.SIGNALS["arm"]:
        if name != "estop_mode":
            assert name in log.files, name
    assert (tmp_path / "a.png").stat().st_size > 10_000
    # The reference holds the last waypoint: the tool ends on the first waypoint's pose.
    assert log["joint_error"][-1] < 1e-6


def test_impossible_criterion_fails_with_exit_1(tmp_path, capsys):
    path = write(tmp_path, ARM.replace('"max(joint_error)" = "< 0.001"',
                                       '"max(joint_error)" = "< 1e-15"'))
    rc, out, _ = run_cli(["run", str(path)], capsys)
    assert rc == 1
    assert "FAIL max(joint_error)" in out


def test_cartesian_waypoints_reach_their_poses(tmp_path):
    robot = kl.Robot.load("ur5")
    dyn = kl.Dynamics(robot.model())
    q0 = np.array([0.0, -1.2, 1.4, -1.6, -1.5, 0.2])
    p0 = dyn.forward_kinematics(q0)[:3, 3]
    text = f'''robot = "ur5"
duration = 3.0
[reference]
cartesian = {{ t = [0, 1.5], xyz = [{p0.tolist()}, {(p0 + [0.05, 0.05, -0.05]).tolist()}], q0 = {q0.tolist()} }}
[criteria]
"max(ee_error)" = "< 0.001"
"final(ee_error)" = "< 1e-4"
'''
    result = sf.run(sf.load(write(tmp_path, text)))
    assert result.passed, result.criteria
    # The tool ends where the file put it (chain root frame: the UR5's base at the world origin).
    ee = result.log["ee"][-1]
    assert np.linalg.norm(ee - (p0 + [0.05, 0.05, -0.05])) < 2e-3, ee


@pytest.mark.parametrize("text, key", [
    ('robot = "ur5"\n[reference]\njoint = { t = [0, 1], q = [[0, 0], [0, 0]] }\n', "reference.joint.q"),
    ('[reference]\nvelocity = { t = [1, 2], vx = [0, 1] }\n', "reference"),
    ('bogus = 1\n[reference]\nvelocity = { t = [0], vx = [0] }\n', "bogus"),
    ('[reference]\nvelocity = { t = [0], vx = [0] }\n[criteria]\n"max(nosuch)" = "< 1"\n', "criteria"),
    ('[reference]\nvelocity = { t = [0], vx = [0] }\n[criteria]\n"max(roll)" = "about 3"\n', "criteria"),
    ('[reference]\nvelocity = { t = [0], vx = [0] }\n[[events]]\nt = 1.0\nkind = "estop"\n', "events[0].kind"),
    ('[reference]\nvelocity = { t = [0], vx = [0] }\n[[events]]\nt = 1.0\nkind = "teleport"\n', "events[0].kind"),
    ('duration = 1.0\n[reference]\nvelocity = { t = [0], vx = [0] }\n[criteria]\n"rms(roll, 2.0)" = "< 3"\n', "duration"),
    ('[reference]\nvelocity = { t = [0], vx = [0] }\n[settings]\nmotor_delay = "abc"\n', "settings"),
    ('[reference]\nvelocity = { t = [0], vx = [0] }\n[settings]\nnosuch = 1\n', "settings"),
    ('robot = "ur5"\n[reference]\nvelocity = { t = [0], vx = [0] }\n', "robot"),
    ('[reference]\nposition = { t = [0], xyz = [[0, 0, 1]] }\n[[events]]\nt = 0.5\nkind = "rotor_fault"\nrotor = 9\nefficiency = 0.5\n', "events[0].rotor"),
    ('[reference\n', "not valid TOML"),
])
def test_broken_file_is_one_line_exit_2(tmp_path, capsys, text, key):
    path = write(tmp_path, text)
    rc, out, err = run_cli(["run", str(path), "--duration", "1.0"] if "duration" not in text
                           else ["run", str(path)], capsys)
    assert rc == 2, (out, err)
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert str(path) in lines[0] and key in lines[0], lines[0]


def test_baseline_same_run_identical_changed_gain_names_first_difference(tmp_path, capsys):
    path = write(tmp_path, ARM)
    base = tmp_path / "base.npz"
    assert run_cli(["run", str(path), "--save-baseline", str(base)], capsys)[0] == 0
    rc, out, _ = run_cli(["run", str(path), "--baseline", str(base)], capsys)
    assert rc == 0 and "ok   baseline" in out, out
    rc, out, _ = run_cli(["run", str(path), "--baseline", str(base),
                          "--set", "controller.bandwidth=25"], capsys)
    assert rc == 1
    assert "FAIL baseline" in out and "first outside tolerance" in out and " at t = " in out
    # Tolerances from the file's [baseline] table: a loose one on the one signal compared passes.
    loose = write(tmp_path, ARM + f'[baseline]\nfile = "base.npz"\nsignals = {{ ee_error = {{ abs = 0.01 }} }}\n',
                  "loose.toml")
    rc, out, _ = run_cli(["run", str(loose), "--set", "controller.bandwidth=25"], capsys)
    assert rc == 0, out


def test_sensor_dropout_freezes_the_measurement(tmp_path):
    text = ARM + '[[events]]\nt = 0.5\nkind = "sensor_dropout"\nsensor = "joints"\nduration = 0.1\n'
    log = sf.run(sf.load(write(tmp_path, text)), duration=1.0).log
    t, q = log["t"], log["q_measured"]
    inside = (t >= 0.5 - 1e-9) & (t < 0.6 - 1e-9)
    assert np.all(q[inside] == q[np.argmax(inside) - 1]), "frozen at the last sample before"
    assert not np.all(q[t >= 0.6 - 1e-9][:5] == q[np.argmax(inside) - 1]), "updates again after"
    assert np.all(log["q"][inside][1:] != log["q"][inside][:-1]), "the arm itself moves on"


def test_payload_adds_the_point_masses_gravity(tmp_path):
    """attach_payload against MuJoCo's own Jacobian: the bias force at rest grows by J^T m g."""
    import mujoco

    from kiloloop.scenarios.scenario_file.common import attach_payload
    from kiloloop.sil.rig import Rig

    plant = Rig(kl.Robot.load("ur5")).plant
    m, d = plant.model, plant.data
    d.qpos[plant.qpos_addresses] = [0.3, -1.0, 1.2, -1.4, -1.5, 0.4]
    d.qvel[:] = 0
    mujoco.mj_forward(m, d)
    before = d.qfrc_bias.copy()
    body = int(m.site_bodyid[m.site(plant.ee_site).id])
    com = np.array([0.02, -0.01, 0.05])
    point = d.xpos[body] + d.xmat[body].reshape(3, 3) @ com
    jacp = np.zeros((3, m.nv))
    mujoco.mj_jac(m, d, jacp, None, point, body)
    attach_payload(m, body, 1.5, com)
    mujoco.mj_forward(m, d)
    expected = before + jacp.T @ (1.5 * -m.opt.gravity)
    assert np.allclose(d.qfrc_bias, expected, atol=1e-9), (d.qfrc_bias, expected)


def test_payload_event_in_a_run(tmp_path):
    text = ARM + '[[events]]\nt = 1.2\nkind = "payload"\nmass = 2.0\ncom = [0, 0, 0.05]\n'
    result = sf.run(sf.load(write(tmp_path, text)))
    plain = sf.run(sf.load(write(tmp_path, ARM, "plain.toml")))
    t = result.log["t"]
    assert np.array_equal(result.log["tau"][t < 1.2], plain.log["tau"][t < 1.2])
    assert not np.array_equal(result.log["tau"][t > 1.3], plain.log["tau"][t > 1.3])


def test_fixture_runs_a_scenario_as_a_dict(pytester):
    pytester.makepyfile('''
def test_mine(kiloloop_run):
    r = kiloloop_run({"robot": "ur5", "duration": 1.0,
                      "reference": {"joint": {"t": [0.0, 0.8], "q": [[0, -1.2, 1.4, -1.6, -1.5, 0.2], [0.2, -1.1, 1.3, -1.5, -1.5, 0.3]]}},
                      "criteria": {"max(joint_error)": "< 0.001"}}, settings={"controller.bandwidth": 40})
    assert r.passed, r.criteria
    assert r.settings["robot"] == "ur5"
''')
    result = pytester.runpytest_subprocess(*_plugin_args())
    result.assert_outcomes(passed=1)


def _plugin_args() -> list[str]:
    """-p for the plugin unless the installed distribution registers it already."""
    eps = importlib.metadata.entry_points(group="pytest11")
    return [] if any(e.value == "kiloloop.pytest_plugin" for e in eps) else ["-p", "kiloloop.pytest_plugin"]


def test_user_repository_collects_and_runs_three_scenario_files(tmp_path):
    """Issue 30's acceptance: a repository outside the tree, pytest there (the installed
    package), three scenario files pass; a copy with an impossible criterion fails with its
    criteria table and leaves log and plot; --junitxml is written."""
    repo = tmp_path / "repo"
    paths = user_repo.write(repo)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    if _plugin_args():   # a development checkout (PYTHONPATH): the plugin by -p
        env["PYTHONPATH"] = os.environ.get("PYTHONPATH", "")
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *_plugin_args()]
    proc = subprocess.run(cmd + ["--junitxml", "junit.xml"], cwd=repo, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "3 passed" in proc.stdout, proc.stdout
    assert (repo / "junit.xml").is_file() and 'tests="3"' in (repo / "junit.xml").read_text()
    impossible = paths["ur10"].read_text().replace('"max(joint_error)" = "< 0.001"',
                                                   '"max(joint_error)" = "< 1e-15"')
    (repo / "test_impossible.toml").write_text(impossible.replace("ur10_waypoints", "impossible"))
    proc = subprocess.run(cmd + ["test_impossible.toml"], cwd=repo, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "FAIL max(joint_error)" in proc.stdout and "1 failed" in proc.stdout, proc.stdout
    results = repo / "kiloloop-results" / "test_impossible"
    assert (results / "log.npz").is_file() and (results / "plot.png").is_file()


def test_sweep_and_batch_take_a_file(tmp_path, capsys):
    path = write(tmp_path, ARM)
    rc, out, _ = run_cli(["sweep", str(path), "--grid", "controller.bandwidth=20,40",
                          "--duration", "1.0", "--out", str(tmp_path / "sw")], capsys)
    assert rc == 0, out
    assert "2/2 passed" in out
    from kiloloop.scenarios.batch import run_scenarios

    runs = run_scenarios(str(path), [{"params": {"controller.bandwidth": "30"},
                                             "duration": 1.0}], threads=1)
    assert runs[0]["passed"], runs[0]


def test_signals_command_lists_units_and_components(capsys):
    rc, out, _ = run_cli(["signals", "ur5"], capsys)
    assert rc == 0 and "ee_error" in out and "[m]" in out and "shoulder_pan_joint" in out
    rc, out, _ = run_cli(["signals", "quadruped"], capsys)
    assert rc == 0 and "velocity_error" in out and "fell" in out


def test_builtin_files_ship_and_pass(capsys):
    from kiloloop import scenarios

    files = scenarios.example_files()
    rc, out, _ = run_cli(["list"], capsys)
    assert rc == 0 and all(str(f) in out for f in files)
    assert {f.stem for f in files} >= {"arm-waypoints", "quadruped-walk-push", "aerial-setpoints"}
    for path in files:
        rc, out, _ = run_cli(["run", str(path)], capsys)
        assert rc == 0, (path, out)


# Built-in scenarios shipped as files (scenarios/files/NAME.toml, the built-in's default robot and
# criteria): the file's run is the built-in's run, so its headline figure is the built-in's.
SAME_RUN = {"arm-track": ("max_joint_error_rad", "max(joint_error)"),
            "aerial-hover": ("max_position_error_m", "max(position_error)"),
            "aerial-rotor-fault": ("max_hover_deviation_m", "max(position_error)")}


@pytest.mark.parametrize("name", sorted(SAME_RUN))
def test_a_builtin_shipped_as_a_file_gives_the_builtins_figure(name):
    from kiloloop import scenarios

    [path] = [f for f in scenarios.example_files() if f.stem == name]
    builtin = scenarios.run_named(name)
    as_file = scenarios.run_named(str(path))
    metric, criterion = SAME_RUN[name]
    assert builtin.passed and as_file.passed
    assert as_file.metrics[criterion] == pytest.approx(builtin.metrics[metric], rel=1e-6)


@pytest.mark.parametrize("name", ["ur10", "go1", "iris"])
def test_b2b_over_a_scenario_file(firmware_prefix, tmp_path, name):
    """kiloloop b2b ROBOT --scenario FILE: that run's controller inputs replayed through the
    firmware build, bit for bit (one file of each family, from the user repository)."""
    from kiloloop.firmware.b2b import run_b2b

    paths = user_repo.write(tmp_path)
    robot = tmp_path / "robots" / f"{name}.toml"
    result = run_b2b(str(robot), scenario=str(paths[name]), prefix=firmware_prefix,
                     work=Path(__file__).resolve().parents[1] / "build" / "firmware",
                     echo=lambda *_: None)
    assert result.identical, result.replay_output
    assert result.ticks == int(round(sf.load(paths[name]).duration / 0.001))
