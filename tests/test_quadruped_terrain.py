"""Terrain scenarios on our quadruped, short runs (the trot's first 2 s after the start are judged:
SETTLED = 2 s, so 4.5 s judges 2.5 s, about four gait cycles), with the non-idealities on and on
estimated state: the same criteria as `kiloloop run quadruped-stones|-rough|-compliant`. The full
10 s runs on both robots and both delays are in `make matrix` (bench/quadruped_matrix.md)."""
from functools import lru_cache

import pytest

from kiloloop import scenarios

SHORT = 4.5  # [s]


@lru_cache(maxsize=None)  # one run per scenario for all the tests below (CI time)
def run(name):
    module = scenarios.get(name)
    return module.run(scenarios.parse_settings(module.DEFAULTS, {}), seed=0, duration=SHORT)


def assert_criteria(result):
    for name, c in result.criteria.items():
        assert c["passed"], f"{result.scenario}: {name} = {c['value']} (needs {c['op']} {c['threshold']})"


@pytest.mark.parametrize("name", ["quadruped-stones", "quadruped-rough", "quadruped-compliant"])
def test_terrain_trot_meets_its_criteria(name):
    r = run(name)
    assert_criteria(r)
    assert r.metrics["stances"] >= 12  # really trotted: >= 3 steps per leg were judged
    assert r.metrics["distance_m"] > 0.5 * 0.5 * (SHORT - 0.5)  # forward progress at 0.5 m/s


def test_stones_really_are_uneven_for_the_robot():
    r = run("quadruped-stones")
    # +-0.25 swing heights (the 17.6 kg model's swing height is 0.08 m): steps up to 4 cm.
    assert r.metrics["stone_spread_m"] == pytest.approx(0.25 * 0.08)


def test_compliant_ground_sinks_the_feet_by_load_over_stiffness():
    r = run("quadruped-compliant")
    # A trotting foot carries about half the weight (17.6 kg): 86 N / 1e3 N/m = 86 mm if the foot
    # alone bore it; the shank's lower end touches the soft ground too and shares the load.
    assert 0.02 < r.metrics["max_sinkage_m"] < 0.1
