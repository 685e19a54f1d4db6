"""`design_delay` of the aerial scenarios: the delay the controller is designed for, apart from the
plant's motor_delay (the quadruped's: tests/test_rig_quadruped.py)."""
from __future__ import annotations

import pytest

from kiloloop.errors import InputError
from kiloloop.robot import aerial as aerial_robot
from kiloloop.scenarios.aerial_settings import COMMON_DEFAULTS, rig_from_settings
from kiloloop.scenarios.design_delay import design_delay
from kiloloop.sil.aerial_family import load_robot


def settings(**kw):
    return dict(COMMON_DEFAULTS, **{k: v for k, v in kw.items()})


def test_the_design_delay_defaults_to_the_plants():
    assert design_delay(settings(motor_delay=0.02)) == 0.02
    assert design_delay(settings(motor_delay=0.02, nonideal=False)) == 0.0
    assert design_delay(settings(motor_delay=0.02, design_delay="0.005")) == 0.005
    with pytest.raises(InputError, match="design_delay"):
        design_delay(settings(design_delay=-0.001))


def test_the_plants_delay_moves_apart_from_the_design():
    lag = aerial_robot.time_constant(load_robot(None))
    held = rig_from_settings(settings(motor_delay=0.03, design_delay=0.002), 0)
    # The plant's command delay is the swept one; the design (reaction lead) keeps its 2 ms.
    assert held.family.motor(held.parts, held.signals).delay_ticks == 30
    assert held.config.reaction_lead == pytest.approx(lag + 0.002)
    follows = rig_from_settings(settings(motor_delay=0.03), 0)
    assert follows.config.reaction_lead == pytest.approx(lag + 0.03)
