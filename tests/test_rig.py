"""The one SIL rig (sil/rig.py) and its settings struct (sil/signals.py): one class for every
family, the family picked by the robot file's kind, options and events checked per family, delays
in seconds turned into whole ticks by one rule."""
import numpy as np
import pytest

import kiloloop as kl
from kiloloop.errors import InputError
from kiloloop.sil import native
from kiloloop.sil.events import EStop, FellBelow, Push, RotorFault
from kiloloop.sil.quadruped_family import stand_command
from kiloloop.sil.rig import FAMILIES, Rig, family_of
from kiloloop.sil.signals import Signals

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")


def test_signals_validate_and_turn_seconds_into_whole_ticks_half_up():
    s = Signals(motor_delay=0.0105, measurement_delay=0.0035)
    assert s.ticks("motor_delay", 0.001) == 11 and s.ticks("measurement_delay", 0.001) == 4
    assert Signals(enabled=False, motor_delay=0.02).ticks("motor_delay", 0.001) == 0
    for field, value in (("gyro_sigma", -1.0), ("motor_delay", float("nan")),
                         ("q_sigma", float("inf")), ("torque_limit_scale", 0.0)):
        with pytest.raises(InputError, match=field):
            Signals(**{field: value}).validate()


def test_one_rig_class_for_every_family():
    assert set(FAMILIES) == {"arm", "quadruped", "aerial"}
    with pytest.raises(ValueError, match="no SIL family"):
        family_of("submarine")
    for name, family in (("ur5", "arm"), ("quadruped", "quadruped"),
                         ("aerial_manipulator", "aerial")):
        rig = Rig(kl.Robot.load(name))
        assert type(rig) is Rig and rig.family.name == family
        assert rig.plant.model.opt.timestep == 0.001


def test_each_family_refuses_what_it_cannot_run():
    quadruped = Rig(kl.Robot.load("quadruped"))
    with pytest.raises(InputError, match="pushes"):
        quadruped.rollout(0.1, stand_command(), [(0.0, RotorFault(0, 0.5))])
    with pytest.raises(TypeError, match="scene"):
        Rig(kl.Robot.load("quadruped"), scene=None)
    with pytest.raises(InputError, match="quat_sigma"):
        Rig(kl.Robot.load("quadruped"), Signals(quat_sigma=0.01))
    aerial = Rig(kl.Robot.load("aerial_manipulator"))
    with pytest.raises(InputError, match="stops only"):
        aerial.rollout(0.1, None, stop=FellBelow(0.1))
    with pytest.raises(InputError, match="CoM"):
        aerial.rollout(0.1, None, [(0.0, Push([1.0, 0, 0], 0.1, body="base_link"))])
    with pytest.raises(InputError, match="EStop"):
        aerial.rollout(0.1, None, [(0.0, EStop())])


def test_a_quadruped_rollout_stands_and_logs_the_probes():
    rig = Rig(kl.Robot.load("quadruped"))
    log = rig.run(0.3, stand_command())
    assert len(log["t"]) == 300
    for name in ("base_pos", "base_quat", "foot_force", "tau", "status"):
        assert name in log, name
    assert np.all(log["base_pos"][:, 2] > rig.fall_height)
