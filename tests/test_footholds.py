"""scenarios/footholds.py on synthetic logs: stance intervals (bounces ignored, unfinished ones left
out), slip as the centre's largest travel while loaded, touch-down heights against a terrain."""
import numpy as np
import pytest

from kiloloop.scenarios import footholds

WEIGHT = 100.0  # [N]
DT = 0.001


def log_with(fz_leg0, pos_leg0=None):
    n = len(fz_leg0)
    force = np.zeros((n, 4, 3))
    force[:, 0, 2] = fz_leg0
    pos = np.zeros((n, 4, 3)) if pos_leg0 is None else np.repeat(pos_leg0[:, None, :], 4, axis=1)
    return {"t": np.arange(n) * DT, "foot_force": force, "foot_pos": pos}


def test_stances_skip_bounces_and_unfinished_ones():
    loaded = 50.0
    fz = np.zeros(1000)
    fz[100] = loaded            # a 1-tick bounce at touch-down
    fz[110:400] = loaded        # a stance of 0.29 s
    fz[600:620] = loaded        # 20 ms: shorter than MIN_STANCE
    fz[800:] = loaded           # still loaded when the log ends
    assert footholds.stances(log_with(fz), WEIGHT) == [(0, 110, 399)]
    assert footholds.stances(log_with(fz), WEIGHT, since=0.2) == []


def test_slip_is_the_largest_travel_while_loaded():
    fz = np.zeros(500)
    fz[100:300] = 50.0
    pos = np.zeros((500, 3))
    pos[100:300, 0] = np.linspace(0.0, 0.004, 200)   # 4 mm forward while loaded
    pos[300:, 0] = 0.2                                # swinging away afterwards: not slip
    intervals = footholds.stances(log_with(fz, pos), WEIGHT)
    assert footholds.slip(log_with(fz, pos), intervals) == pytest.approx([0.004])


def test_touchdown_height_against_the_terrain():
    fz = np.zeros(300)
    fz[100:200] = 50.0
    pos = np.zeros((300, 3))
    pos[:, 2] = 0.05 + 0.02     # sphere of radius 0.02 resting on ground at 0.05
    log = log_with(fz, pos)
    intervals = footholds.stances(log, WEIGHT)
    h = footholds.touchdown_heights(log, intervals, lambda x, y: 0.05, 0.02)
    assert h == pytest.approx([0.0])
    h = footholds.touchdown_heights(log, intervals, lambda x, y: 0.03, 0.02)  # centre over a dip
    assert h == pytest.approx([0.02])
