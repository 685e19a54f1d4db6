"""kiloloop excite / identify on an arm: a UR5 whose true plant differs from its robot file
(friction, armature, a payload on the last link, an actuation delay) is recovered from a short
excitation log within the issue's tolerances, and the patch it writes loads as a robot file."""
from __future__ import annotations

import tomllib

import numpy as np
import pytest

import kiloloop as kl
from kiloloop.ident.arm import identify_arm
from kiloloop.ident.excite import excite
from kiloloop.ident.identify import identify
from kiloloop.ident.payload_urdf import link_inertial
from kiloloop.ident.truth import UR5_JOINTS, Hidden, nominal_joints, true_payload, write_true_robot

HIDDEN = Hidden(friction_scale=2.0, armature_scale=0.5, payload_fraction=0.3, delay=0.021)


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    """(nominal robot, true robot, excitation log path): 6 s of excitation, seed 0."""
    out = tmp_path_factory.mktemp("ident_arm")
    nominal = kl.Robot.load("ur5", UR5_JOINTS)
    true = kl.Robot.load(write_true_robot(nominal, HIDDEN, out / "true"))
    log = excite(true, 6.0, seed=0)
    log.save(out / "excite.npz")
    return nominal, true, out / "excite.npz", out


def test_recovers_the_hidden_plant_within_the_tolerances(case):
    nominal, _, log_path, _ = case
    ident, _, _ = identify(nominal, [log_path])
    damping, friction, armature = nominal_joints(nominal)
    s = HIDDEN.friction_scale
    assert np.allclose(ident.damping, damping * s, rtol=0.05)
    assert np.allclose(ident.frictionloss, friction * s, rtol=0.10)
    assert np.allclose(ident.armature, armature * HIDDEN.armature_scale, rtol=0.10)
    mass, com = true_payload(nominal, HIDDEN)
    assert ident.payload_mass == pytest.approx(mass, rel=0.05)
    assert np.linalg.norm(ident.payload_com - com) < 0.05 * np.linalg.norm(com)
    assert abs(ident.delay - HIDDEN.delay) <= 0.001 + 1e-12


def test_the_nominal_plant_itself_is_found_unchanged(case):
    """Logs of the nominal plant: its own values, no payload, the file's delay (0)."""
    nominal = case[0]
    log = excite(nominal, 4.0, seed=1)
    ident = identify_arm(nominal, [log])
    damping, friction, armature = nominal_joints(nominal)
    assert np.allclose(ident.damping, damping, rtol=0.05)
    assert np.allclose(ident.frictionloss, friction, rtol=0.10)
    assert np.allclose(ident.armature, armature, rtol=0.10)
    assert ident.payload_mass == 0.0 and ident.delay_ticks == 0


def test_the_patch_is_a_robot_file_with_the_estimates(case):
    nominal, _, log_path, out = case
    patch = out / "patch.toml"
    ident, _, report = identify(nominal, [log_path], patch)
    robot = kl.Robot.load(patch)
    joints = robot.sim["joints"]
    assert np.allclose(joints["damping"], ident.damping, rtol=1e-5)
    assert np.allclose(joints["armature"], ident.armature, rtol=1e-5)
    assert robot.scenario_overrides("arm-track")["measurement_delay"] == pytest.approx(ident.delay)
    link = ident.payload_link
    m0 = link_inertial(nominal.urdf, link)[0]
    assert link_inertial(robot.urdf, link)[0] == pytest.approx(m0 + ident.payload_mass)
    assert report["patch"] == str(patch)
    # What the nominal file says and identification does not touch is kept.
    assert robot.section("chain") == nominal.section("chain")
    with open(patch, "rb") as f:
        assert tomllib.load(f)["name"] == nominal.name


def test_cli_excite_and_identify(tmp_path, capsys):
    from kiloloop.cli import main

    log = tmp_path / "e.mcap"
    assert main(["excite", "ur5", "--out", str(log), "--duration", "2",
                 "--set", "sim.joints.damping=1.5"]) == 0
    assert main(["identify", "ur5", str(log), "--json"]) == 0
    import json

    report = json.loads(capsys.readouterr().out.split("\n", 1)[1], parse_constant=pytest.fail)
    assert report["damping"] == pytest.approx([1.5] * 6, rel=0.05)
    assert main(["identify", "ur5", str(tmp_path / "missing.npz")]) == 2
    assert main(["excite", "ur5", "--out", str(tmp_path / "e.txt")]) == 2


def test_a_scenario_log_identifies_what_it_moves_and_says_what_it_does_not(tmp_path):
    """arm-track's own log (4.5 s): the joints it moves are found, any it barely moves keep the
    nominal file's values and are named, and nothing raises. (With the friction-aware joint
    gains of robot/arm.py every UR5 joint moves enough: none is held.)"""
    from kiloloop import scenarios

    true = {**UR5_JOINTS, "sim.joints.damping": [10.0, 10.0, 6.0, 2.0, 2.0, 2.0]}
    result = scenarios.run_named("arm-track", robot=kl.Robot.load("ur5", true),
                                 overrides={"measurement_delay": 0.004})
    result.log.save(tmp_path / "track.npz")
    nominal = kl.Robot.load("ur5", UR5_JOINTS)
    ident, lines, _ = identify(nominal, [tmp_path / "track.npz"])
    assert ident.delay_ticks == 4
    held = [int(name.split("[")[1][:-1]) for name in ident.unidentified if "[" in name]
    moved = [j for j in range(6) if j not in held]
    assert moved[:3] == [0, 1, 2]
    truth = true["sim.joints.damping"]
    assert ident.damping[moved] == pytest.approx([truth[j] for j in moved], rel=0.05)
    damping, _, _ = nominal_joints(nominal)
    for j in held:
        assert ident.damping[j] == damping[j]
    assert all(np.isinf(ident.stderr["damping"][j]) for j in held)
    assert any("not identifiable" in line for line in lines) == bool(ident.unidentified)


def test_another_arm_from_a_minimal_robot_file(tmp_path):
    """example-robot-data's Panda (7 joints, 12 N m wrists, gravity taking half of joint 2's
    effort), nothing tuned: the same recovery from 6 s."""
    from robot_files import erd_urdf, minimal_arm

    path = minimal_arm(tmp_path, erd_urdf("panda_description/urdf/panda.urdf"), "panda_link0",
                       "panda_link8", "panda")
    nominal = kl.Robot.load(path, {"sim.joints.damping": 1.0, "sim.joints.frictionloss": 1.0,
                                   "sim.joints.armature": 0.05})
    true = kl.Robot.load(write_true_robot(nominal, HIDDEN, tmp_path / "true"))
    ident = identify_arm(nominal, [excite(true, 6.0, seed=2)])
    s = HIDDEN.friction_scale
    assert np.allclose(ident.damping, 1.0 * s, rtol=0.05)
    assert np.allclose(ident.frictionloss, 1.0 * s, rtol=0.10)
    assert np.allclose(ident.armature, 0.05 * HIDDEN.armature_scale, rtol=0.10)
    assert ident.payload_mass == pytest.approx(true_payload(nominal, HIDDEN)[0], rel=0.05)
    assert abs(ident.delay - HIDDEN.delay) <= 0.001 + 1e-12


def test_noisy_encoders_are_smoothed(case):
    """White encoder noise (2e-3 rad/s on qd, 1e-5 rad on q): the zero-phase filter keeps the
    estimates within the tolerances; without it the armatures are lost."""
    nominal, true, _, _ = case
    log = excite(true, 6.0, seed=0, noise={"q_sigma": 1e-5, "qd_sigma": 2e-3})
    _, friction, armature = nominal_joints(nominal)
    ident = identify_arm(nominal, [log])
    assert np.allclose(ident.frictionloss, friction * HIDDEN.friction_scale, rtol=0.10)
    assert np.allclose(ident.armature, armature * HIDDEN.armature_scale, rtol=0.10)
    assert abs(ident.delay - HIDDEN.delay) <= 0.001 + 1e-12
    raw = identify_arm(nominal, [log], smoothing=0.0)
    assert not np.allclose(raw.armature, armature * HIDDEN.armature_scale, rtol=0.10)


@pytest.mark.parametrize("args, needle", [
    (["excite", "ur5", "--out", "x.npz", "--duration", "inf"], "--duration"),
    (["excite", "ur5", "--out", "x.npz", "--duration", "nan"], "--duration"),
    (["excite", "ur5", "--out", "x.npz", "--seed", "-1"], "--seed"),
    (["excite", "ur5", "--out", "x.npz", "--delay", "-0.01"], "--delay"),
    (["excite", "quadruped", "--out", "x.npz", "--duration", "1"], "quadruped"),
    (["identify", "ur5", "x.npz", "--smoothing", "nan"], "--smoothing"),
    (["identify", "ur5", "x.npz", "--out", "p.txt"], "--out"),
])
def test_cli_input_errors_are_one_line_exit_2(capsys, args, needle):
    from kiloloop.cli import main

    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err


def test_a_log_of_another_family_is_refused_with_what_is_missing(case, capsys):
    from kiloloop.cli import main

    assert main(["identify", "aerial_manipulator", str(case[2])]) == 2
    assert "thrust_cmd" in capsys.readouterr().err


def test_a_motor_lag_is_told_from_the_delay(case):
    """12 ms of transport delay and an 8 ms first-order lag: a lag looks like more delay to a
    slow motion; both are found."""
    nominal = case[0]
    ident = identify_arm(nominal, [excite(nominal, 4.0, seed=3, delay=0.012, motor_lag=0.008)])
    assert ident.delay_ticks == 12
    assert ident.lag == pytest.approx(0.008, rel=0.05)
    damping, _, armature = nominal_joints(nominal)
    assert np.allclose(ident.damping, damping, rtol=0.05)
    assert np.allclose(ident.armature, armature, rtol=0.10)
