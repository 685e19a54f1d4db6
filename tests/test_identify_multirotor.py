"""kiloloop excite / identify on a multirotor: the aerial manipulator whose rotors give 15 % less
thrust than commanded, behind a hidden command delay, is recovered from a short hover excitation
(gains, drag-torque coefficients, time constants within 5 %, the delay within one tick), and the
patch puts them where the plant reads them."""
from __future__ import annotations

import numpy as np
import pytest

import kiloloop as kl
from kiloloop.ident.excite import excite
from kiloloop.ident.identify import identify
from kiloloop.ident.truth import Hidden, write_true_robot

HIDDEN = Hidden(thrust_scale=0.85, delay=0.014)


def test_recovers_rotor_gains_drag_lags_and_delay(tmp_path):
    nominal = kl.Robot.load("aerial_manipulator")
    true = kl.Robot.load(write_true_robot(nominal, HIDDEN, tmp_path / "true"))
    assert true.sim["rotors"]["efficiency"] == pytest.approx([0.85] * 4)
    excite(true, 5.0, seed=0).save(tmp_path / "excite.npz")
    patch = tmp_path / "patch.toml"
    ident, _, _ = identify(nominal, [tmp_path / "excite.npz"], patch)
    rotors = nominal.data["rotors"]
    assert np.allclose(ident.gain, 0.85, rtol=0.05)
    assert np.allclose(ident.torque_coefficient, [r["torque_coefficient"] for r in rotors],
                       rtol=0.05)
    assert np.allclose(ident.time_constant, [r["time_constant"] for r in rotors], rtol=0.05)
    assert abs(ident.delay - HIDDEN.delay) <= 0.001 + 1e-12
    robot = kl.Robot.load(patch)
    assert robot.sim["rotors"]["efficiency"] == pytest.approx(ident.gain, rel=1e-5)
    assert robot.scenario_overrides("aerial-hover")["motor_delay"] == pytest.approx(ident.delay)
