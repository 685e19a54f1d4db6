"""Other real quadrupeds from minimal robot files (bench/quadruped_robots.md has all of
example-robot-data's): Solo12, 2.5 kg with mesh feet, and Go2, a mesh-footed Unitree, stand and
trot with nothing but their URDFs' base and foot names. Both fell or failed before the foot
radius and the plant's start height were read from the feet's real geometry."""
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.bench.quadruped_robots import robot_file


@pytest.mark.parametrize("name", ["solo12", "go2"])
@pytest.mark.parametrize("scenario,duration", [("quadruped-stand", 2.0), ("quadruped-trot", 4.0)])
def test_stands_and_trots_from_a_minimal_robot_file(tmp_path, name, scenario, duration):
    path = robot_file(name, tmp_path)
    if path is None:
        pytest.skip("example-robot-data not installed")
    r = scenarios.run_named(scenario, kl.Robot.load(path), seed=0, duration=duration)
    for key, c in r.criteria.items():
        assert c["passed"], f"{name} {scenario}: {key} = {c['value']} (needs {c['op']} {c['threshold']})"
