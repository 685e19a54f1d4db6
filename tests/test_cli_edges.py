"""The command line at its edges, tried as a new user would: a usage or input error is one line on
stderr naming the option or key (and the file), exit 2, no traceback; a bug keeps its traceback
and exits 3; exit 1 stays "criteria failed". Runs are refused before they start when they are
too short to judge; lists are taken as `0.1,0.2` or `[0.1, 0.2]` and checked against the robot."""
import math
import shutil
import subprocess
import sys
import warnings

import pytest

from kiloloop import cli, scenarios
from kiloloop.errors import InputError, UnreadKeyWarning
from kiloloop.scenarios import arm_estop, arm_press, arm_track, quadruped_push, quadruped_trot

UR5_Q = "0.0,-1.2,1.4,-1.6,-1.5,0.1"  # [rad] a UR5 pose (6 joints)


def one_line_exit_2(capsys, args, *needles):
    code = cli.main(args)
    err = capsys.readouterr().err
    lines = [line for line in err.strip().splitlines() if "warning:" not in line]
    assert code == 2, err
    assert len(lines) == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]


@pytest.mark.parametrize("value", ["-1", "0", "nan", "inf"])
def test_duration_that_is_no_duration(capsys, value):
    one_line_exit_2(capsys, ["run", "arm-track", "--duration", value], "--duration",
                    "finite number of seconds > 0")


@pytest.mark.parametrize("args, needles", [
    (["run", "arm-track", "--seed", "nonsense"], ["kiloloop run:", "--seed", "'nonsense'"]),
    (["run", "arm-track", "--seed", "-1"], ["--seed"]),
    (["run", "arm-track", "--duration", "abc"], ["--duration"]),
    (["run", "arm-track", "--set", "q_start"], ["--set 'q_start'", "KEY=VALUE"]),
    (["run", "no-such-scenario"], ["unknown scenario 'no-such-scenario'"]),
    (["run", "arm-track", "--set", "controller.kp=abc"], ["controller.kp", "'abc'", "robot.toml"]),
    (["run", "arm-track", "--set", "t_1=nan"], ["t_1", "finite"]),
    (["run", "arm-track", "--set", "measurement_delay=abc"], ["measurement_delay", "'abc'"]),
    (["run", "arm-track", "--set", "controller.kp=-5", "--duration", "0.1"], ["kp"]),
    (["run", "arm-track", "--set", "physics_dt=0.0007", "--duration", "0.1"], ["physics"]),
    (["run", "arm-press", "--set", "controller=hybird"], ["controller", "'hybird'"]),
    (["run", "aerial-rotor-fault", "--set", "rotor=9", "--duration", "1.5"], ["rotor", "9"]),
    (["run", "quadruped-stand", "--set", "controller.swing_kp=abc"], ["controller.swing_kp"]),
    (["run", "arm-press", "--set", "slide_time=0"], ["slide_time", "> 0", "got 0"]),
    (["run", "aerial-push", "--set", "push_duration=0"], ["push_duration", "> 0"]),
    (["run", "quadruped-tilt-stop", "--set", "push_duration=-0.1"], ["push_duration", "> 0"]),
    (["run", "arm-track", "--set", "t_1=5", "--set", "t_2=1"], ["t_1, t_2", "increasing"]),
    (["run", "arm-estop", "--set", "velocity_scale=0"], ["velocity_scale", "> 0"]),
    (["sweep", "arm-track", "--grid", "damping=0,abc", "--duration", "0.2"], ["damping", "'abc'"]),
    (["sweep", "arm-track", "--grid", "measurement_delay=0,-1", "--duration", "0.2"],
     ["measurement_delay"]),
    (["export", "ur5", "--out", "unused", "--set", "controller.kd=x"], ["controller.kd"]),
    (["b2b", "ur5", "--duration", "nan"], ["--duration"]),
    (["b2b", "ur5", "--seed", "x"], ["--seed"]),
])
def test_input_errors_are_one_line_exit_2(capsys, args, needles):
    one_line_exit_2(capsys, args, *needles)


def test_the_console_script_prints_no_traceback():
    for args in (["--duration", "nan"], ["--set", "controller.kp=abc"]):
        r = subprocess.run([sys.executable, "-m", "kiloloop.cli", "run", "arm-track", *args],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
        assert len(r.stderr.strip().splitlines()) == 1, r.stderr


@pytest.mark.parametrize("table, key", [("[controller]\nkp = \"abc\"", "controller.kp"),
                                        ("[scenario.arm-track]\nt_1 = \"soon\"",
                                         "scenario.arm-track.t_1")])
def test_a_robot_file_with_a_string_number_names_the_file_and_key(capsys, tmp_path, table, key):
    from kiloloop import models_dir

    src = models_dir() / "ur5"
    shutil.copy(src / "ur5.urdf", tmp_path / "ur5.urdf")
    text = (src / "robot.toml").read_text()
    if table.startswith("[scenario.arm-track]"):  # the file has that table: add to it
        text = text.replace("[scenario.arm-track]", table)
    else:
        text = text.replace("[chain]", f"{table}\n\n[chain]")
    (tmp_path / "robot.toml").write_text(text)
    line = one_line_exit_2(capsys, ["run", "arm-track", "--robot", str(tmp_path / "robot.toml")],
                           key, "expected")
    assert str(tmp_path / "robot.toml") in line


@pytest.mark.parametrize("args, needles", [
    (["--set", "q_start=0.1,0.2"], ["q_start", "expected 6 values", "got 2"]),
    (["--set", "q_start=[0.1, 0.2]"], ["q_start", "expected 6 values", "got 2"]),
    (["--set", "controller.kp=1,2"], ["--set controller.kp", "1 or 6", "got 2"]),
    (["--set", "controller.kp=[1, 2]"], ["--set controller.kp", "1 or 6", "got 2"]),
    (["--set", "sim.joints.q0=[0.1, 0.2, 0.3]"], ["sim.joints.q0", "expected 6", "got 3"]),
])
def test_per_joint_lists_are_checked_against_the_robot(capsys, args, needles):
    one_line_exit_2(capsys, ["run", "arm-track", *args], *needles)


def test_scenario_lists_on_other_scenarios_and_counts(capsys):
    one_line_exit_2(capsys, ["run", "arm-estop", "--set", "q_goal=[0.1]"], "q_goal", "got 1")
    one_line_exit_2(capsys, ["run", "arm-rrt", "--set", "box_center=0,0"], "box_center",
                    "expected 3", "got 2")
    one_line_exit_2(capsys, ["run", "aerial-reach", "--set", "q_start=0,0"], "q_start",
                    "expected 3", "got 2")


def test_both_list_forms_give_the_same_settings_and_robot():
    _, bare = scenarios.prepare(arm_track, None, [f"q_start={UR5_Q}"])
    _, toml = scenarios.prepare(arm_track, None, [f"q_start=[{UR5_Q}]"])
    assert bare["q_start"] == toml["q_start"] == [float(v) for v in UR5_Q.split(",")]
    _, python = scenarios.prepare(arm_track, None, ["q_start=[.5, 1., -.5, 0, 0, 0]"])
    assert python["q_start"] == [0.5, 1.0, -0.5, 0.0, 0.0, 0.0]  # numbers TOML would refuse
    _, empty = scenarios.prepare(arm_track, None, ["q_start=[]"])
    assert empty["q_start"] == []  # empty: derived, as the default
    kp = "100,200,300,400,500,600"
    robot_bare, _ = scenarios.prepare(arm_track, None, [f"controller.kp={kp}"])
    robot_toml, _ = scenarios.prepare(arm_track, None, [f"controller.kp=[{kp}]"])
    assert robot_bare.data == robot_toml.data
    assert robot_bare.data["controller"]["kp"] == [100, 200, 300, 400, 500, 600]


@pytest.mark.parametrize("args, minimum", [
    (["run", "quadruped-trot", "--duration", "1"],
     quadruped_trot.SETTLED + scenarios.JUDGED_WINDOW),
    (["run", "quadruped-push", "--duration", "2.5"], quadruped_push.MIN_DURATION),
    (["run", "arm-press", "--duration", "1"], None),
    (["run", "arm-estop", "--duration", "0.5"], None),
    (["sweep", "aerial-push", "--grid", "push_time=1,4", "--duration", "3"], 4.12),
])
def test_a_run_too_short_to_judge_is_refused_with_its_minimum(capsys, args, minimum):
    line = one_line_exit_2(capsys, args, args[1], "needs at least")
    if minimum is not None:
        assert f"needs at least {minimum:.4g} s" in line


def test_minimum_durations_come_from_the_scenarios_constants():
    assert quadruped_push.MIN_DURATION == pytest.approx(
        quadruped_push.PUSH_TIME + quadruped_push.PUSH_DURATION + quadruped_push.RECOVERY
        + scenarios.JUDGED_WINDOW)
    s = dict(arm_press.DEFAULTS, slide_time=3.0)
    assert scenarios.min_duration(arm_press, s) == pytest.approx(
        s["settle"] + 3.0 + scenarios.JUDGED_WINDOW)
    assert scenarios.min_duration(arm_track) == scenarios.JUDGED_WINDOW  # no window of its own
    with pytest.raises(InputError, match="needs at least"):
        scenarios.check_duration(2.0, quadruped_trot)
    assert scenarios.check_duration(None, quadruped_trot) is None  # the scenario's default


def test_at_its_minimum_a_run_judges_every_criterion():
    d = quadruped_trot.MIN_DURATION
    result = scenarios.run_named("quadruped-trot", duration=d)
    for name, c in result.criteria.items():
        assert math.isfinite(c["value"]), name


def test_an_unread_robot_key_warns_naming_key_and_scenario(capsys):
    with pytest.warns(UnreadKeyWarning, match="controller.bandwidth: arm-press"):
        scenarios.prepare(arm_press, None, ["controller.bandwidth=40"])
    with pytest.warns(UnreadKeyWarning, match="collision.margin: arm-track"):
        scenarios.prepare(arm_track, None, ["collision.margin=0.05"])
    with pytest.warns(UnreadKeyWarning, match="scenario.arm-line.t_start: arm-track"):
        scenarios.prepare(arm_track, None, ["scenario.arm-line.t_start=1.0"])
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnreadKeyWarning)
        scenarios.prepare(arm_track, None, ["controller.bandwidth=40", "sim.joints.damping=0.1",
                                            "scenario.arm-track.t_1=1.4"])
    # The command line: one warning line, the exit code the run's own (here 0, passed).
    code = cli.main(["run", "arm-track", "--duration", "0.2", "--set", "collision.margin=0.05"])
    err = capsys.readouterr().err
    assert code == 0, err
    assert err.strip() == ("kiloloop run: warning: --set collision.margin: arm-track does not "
                           "read it (no effect on this run)")


def test_arm_rrt_refusing_its_inputs_is_exit_2(capsys, monkeypatch):
    from kiloloop.scenarios import arm_rrt

    class Blocked:  # every pose collides: no box can stand between start and goal
        def clearance(self, q):
            return -1.0

    monkeypatch.setattr(arm_rrt, "make_checker", lambda *a, **k: Blocked())
    one_line_exit_2(capsys, ["run", "arm-rrt", "--set", "box_center=[]",
                             "--set", "box_half_extents=[]"], "no box fits")


def test_a_bug_keeps_its_traceback_and_is_not_exit_1(capsys, monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("simulated bug in a rollout")

    monkeypatch.setattr(scenarios, "run", broken)
    code = cli.main(["run", "arm-track", "--duration", "0.2"])
    err = capsys.readouterr().err
    assert code == 3
    assert "Traceback" in err and "RuntimeError: simulated bug" in err


def test_failed_criteria_stay_exit_1(capsys):
    assert cli.main(["run", "arm-track", "--duration", "2.0", "--set",
                     "controller=pd_gravity"]) == 1
    assert "FAILED" in capsys.readouterr().out


def test_arm_estop_minimum_is_derived_from_its_own_motion():
    # The e-stop (given, or half-way through the motion), then the planned stop from cruise
    # speed: the default duration (3 s) is above it; an e-stop given later moves it by as much.
    robot, settings = scenarios.prepare(arm_estop)
    rig = arm_estop.Rig(robot)
    _, _, trajectory, t_estop, cruise = arm_estop.motion(rig, settings)
    minimum = scenarios.min_duration(arm_estop, settings, robot)
    given = settings["t_estop"]  # the UR5's robot file gives it; < 0: half-way
    assert t_estop == pytest.approx(given if given >= 0 else 0.5 * trajectory.end_time)
    slack = arm_estop.CRITERIA["stop_time_over_plan_s"][1]  # [s] over the planned stop
    assert minimum == pytest.approx(t_estop + cruise / settings["stop_deceleration"] + slack
                                    + scenarios.JUDGED_WINDOW)
    assert t_estop < minimum < arm_estop.DURATION
    later = scenarios.min_duration(arm_estop, dict(settings, t_estop=t_estop + 1.0), robot)
    assert later == pytest.approx(minimum + 1.0)
