"""The loops `kiloloop margins` breaks (margins/loops.py): one unit along v is one unit of the
loop's signal (w . v = 1) and nothing of the other wrench components it names."""
from __future__ import annotations

import numpy as np
import pytest

from kiloloop import scenarios
from kiloloop.margins import operating_point
from kiloloop.margins.loops import FAMILY_LOOPS, WRENCH_ROW, loop_of


def settled(name: str):
    module = scenarios.get(name)
    robot, settings = scenarios.prepare(module, None, [])
    op = operating_point(robot, settings)
    op.settle = 1.0
    r, data = op.rollout(0)
    r.run()
    return op, data, robot.kind


@pytest.mark.parametrize("scenario", ["aerial-hover", "quadruped-stand"])
def test_each_loop_is_one_unit_of_its_own_signal(scenario):
    op, data, kind = settled(scenario)
    loops = {name: loop_of(op, data, name) for name in FAMILY_LOOPS[kind]}
    for name, loop in loops.items():
        assert loop.w @ loop.v == pytest.approx(1.0)
        assert np.isfinite(loop.authority) and loop.authority > 0
        for other_name, other in loops.items():
            if WRENCH_ROW[other_name] != WRENCH_ROW[name]:   # v of one is none of the others
                assert abs(other.w @ loop.v) < 1e-9, (name, other_name)


def test_a_multirotors_attitude_loops_inject_a_pure_couple():
    op, data, _ = settled("aerial-hover")
    fd = int(op.rig.plant._free_d)
    for name in ("roll", "pitch", "yaw"):
        qfrc = loop_of(op, data, name).qfrc
        assert np.abs(qfrc[fd:fd + 3]).max() < 1e-9     # no force on the vehicle
        assert np.abs(qfrc[fd + 3:fd + 6]).max() > 0.5
