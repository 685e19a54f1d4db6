"""`kiloloop margins` on a loop whose margins are known in closed form: one revolute joint about
the vertical (no gravity torque) with inertia J and viscous damping b, PD control (kp, kd) on the
measured position and velocity, the command delayed d ticks and lagged (time constant tau: the
motor model's y+ = y + a (u - y), a = h / (tau + h)). MuJoCo's step (Euler, damping implicit:
v+ = (J v + h tau) / (J + h b), q+ = q + h v+) makes the loop, broken at the torque,

    L(z) = z^-d  a / (1 - (1 - a) / z)  h / ((J + h b) z - J)  (kd + kp h z / (z - 1)),
    z = exp(j w h),

whose crossover and phase crossover are found here by root finding, apart from the module's own
margin code. Acceptance (issue 34): within 0.2 dB, 1 deg and one tick."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import kiloloop as kl
from kiloloop.margins import analyse, operating_point

J, B = 0.05, 0.4            # [kg m^2] link inertia about the axis, [N m s/rad] joint damping
KP, KD = 45.0, 2.1          # [N m/rad], [N m s/rad]: 30 rad/s on J, damping ratio 0.7
H = 0.001                   # [s] control period = physics step
EFFORT = 50.0               # [N m]

URDF = f"""<robot name="one_joint">
  <link name="base"/>
  <link name="link1">
    <inertial><origin xyz="0 0 0"/><mass value="1.0"/>
      <inertia ixx="0.03" iyy="0.03" izz="{J}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="{EFFORT}" velocity="10"/></joint>
</robot>
"""
ROBOT = f"""name = "one_joint"
kind = "arm"
urdf = "one_joint.urdf"

[chain]
root = "base"
tip = "link1"

[controller]
kp = {KP}
kd = {KD}
friction_compensation = false

[sim.physics]
timestep = {H}
integrator = "Euler"
floor = false

[sim.joints]
damping = {B}
q0 = [0.0]
"""


def analytic_loop(w, delay_ticks: int, lag: float = 0.0):
    z = np.exp(1j * np.asarray(w) * H)
    a = H / (lag + H)
    motor = z ** -delay_ticks * a / (1 - (1 - a) / z)
    return motor * H / ((J + H * B) * z - J) * (KD + KP * H * z / (z - 1))


def analytic_margins(delay_ticks: int, lag: float = 0.0) -> dict:
    L = lambda w: analytic_loop(w, delay_ticks, lag)   # noqa: E731
    wc = brentq(lambda w: abs(L(w)) - 1.0, 1.0, 3000.0)
    pm = math.degrees(np.angle(L(wc))) + 180.0
    grid = np.linspace(1.0, 3100.0, 20000)
    unwrapped = np.unwrap(np.angle(L(grid)))
    gm = math.inf
    if np.any(unwrapped < -np.pi):
        k = int(np.argmax(unwrapped < -np.pi))      # the first crossing of -180 deg
        near = unwrapped[k]
        wp = brentq(lambda w: np.angle(L(w) * np.exp(-1j * near)) + near + np.pi,
                    grid[k - 1], grid[k])
        gm = -20 * math.log10(abs(L(wp)))
    return {"gain_margin_db": gm, "phase_margin_deg": pm,
            "delay_margin_s": math.radians(pm) / wc, "crossover_rad_s": wc}


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    d = tmp_path_factory.mktemp("one_joint")
    (d / "one_joint.urdf").write_text(URDF)
    (d / "robot.toml").write_text(ROBOT)
    return kl.Robot.load(str(d / "robot.toml"))


@pytest.mark.parametrize("delay_ticks, lag", [(2, 0.0), (8, 0.0), (3, 0.005)])
def test_linearization_meets_the_analytic_margins(robot, delay_ticks, lag):
    op = operating_point(robot, {"controller": "pd_gravity", "motor_delay": delay_ticks * H,
                                 "motor_time_constant": lag})
    a = analyse(op, "joint:0", inject=False)
    want, got = analytic_margins(delay_ticks, lag), a.margins
    print(f"delay {delay_ticks} ticks, lag {lag} s: analytic {want}; measured {got}")
    assert got.gain_margin_db == pytest.approx(want["gain_margin_db"], abs=0.2)
    assert got.phase_margin_deg == pytest.approx(want["phase_margin_deg"], abs=1.0)
    assert got.delay_margin_s == pytest.approx(want["delay_margin_s"], abs=H)
    assert got.crossover_rad_s == pytest.approx(want["crossover_rad_s"], rel=0.01)
    # The whole curve, not only its crossings (the grid below a third of Nyquist).
    sel = a.w < np.pi / H / 3
    ratio = a.L[sel] / analytic_loop(a.w[sel], delay_ticks, lag)
    assert np.max(np.abs(20 * np.log10(np.abs(ratio)))) < 0.05
    assert np.max(np.abs(np.degrees(np.angle(ratio)))) < 0.3


def test_injection_agrees_with_the_linearization(robot):
    op = operating_point(robot, {"controller": "pd_gravity", "motor_delay": 8 * H})
    a = analyse(op, "joint:0", seed=3)
    print(a.as_dict())
    assert a.agreement["max_gain_difference_db"] < 1.0
    assert a.agreement["max_phase_difference_deg"] < 5.0
    want = analytic_margins(8)
    assert a.margins_injected.phase_margin_deg == pytest.approx(want["phase_margin_deg"], abs=2.0)


def test_an_unknown_loop_is_an_input_error(robot):
    from kiloloop.errors import InputError

    op = operating_point(robot, {"controller": "pd_gravity"})
    with pytest.raises(InputError, match="joint:<i>"):
        analyse(op, "pitch", inject=False)


def test_the_command_prints_the_margins_as_json(robot, capsys, tmp_path):
    import json

    from kiloloop.cli import main

    png = tmp_path / "bode.png"
    code = main(["margins", "arm-track", "--robot", str(robot.path), "--loop", "joint:0",
                 "--set", "controller=pd_gravity", "--json", "--plot", str(png)])
    d = json.loads(capsys.readouterr().out)
    assert code == 0 and png.stat().st_size > 0
    want = analytic_margins(0)["crossover_rad_s"]
    assert d["crossover_rad_s"] == pytest.approx(want, rel=0.01)
    for key in ("gain_margin_db", "phase_margin_deg", "delay_margin_s", "crossover_rad_s"):
        assert key in d and key in d["injection"] and key in d["linearization"]
    assert d["max_gain_difference_db"] < 1.0 and d["max_phase_difference_deg"] < 5.0
