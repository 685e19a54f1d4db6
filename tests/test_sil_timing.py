"""The SIL's time rules, once (sil/timing.py): seconds to whole periods, halves up, and a physics
timestep that must divide the control period, refused with one line naming physics_dt by every
family's rig."""
from __future__ import annotations

import pytest

from kiloloop import cli
from kiloloop.errors import InputError
from kiloloop.sil.timing import substeps, whole_periods


def test_whole_periods_rounds_halves_up_through_representation_error():
    assert whole_periods(0.0035) == 4            # 3.4999999999999996 periods as doubles
    assert whole_periods(0.0105) == 11
    assert whole_periods(0.0104) == 10
    assert whole_periods(4.5) == 4500
    assert whole_periods(0.00025, 0.0005) == 1


def test_substeps_divides_or_refuses():
    assert substeps(0.001) == 1 and substeps(0.0005) == 2 and substeps(0.00025) == 4
    for bad in (0.0007, 0.002, 0.0, -0.001, float("nan")):
        with pytest.raises(InputError, match="physics_dt"):
            substeps(bad)


@pytest.mark.parametrize("scenario", ["arm-track", "quadruped-stand", "aerial-hover"])
def test_every_rig_refuses_a_timestep_that_does_not_divide_1_ms(scenario, capsys):
    rc = cli.main(["run", scenario, "--duration", "5", "--set", "physics_dt=0.0007"])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1 and "physics_dt" in err and "Traceback" not in err
