"""Scenario files: a user's own SIL test as data (docs/scenarios.md is the user's guide).

    from kiloloop.scenarios import scenario_file
    scenario = scenario_file.load("my_mission.toml")        # checked: ScenarioFileError otherwise
    result = scenario_file.run(scenario, robot=None, overrides=["controller.kp=400"])
    result.passed, result.criteria, result.log["ee_error"]

The same runs back `kiloloop run FILE.toml`, `kiloloop sweep FILE.toml`, the batch runner, the
pytest plugin (test_*.toml files) and `kiloloop b2b ROBOT --scenario FILE.toml`.
"""
from __future__ import annotations

from .errors import ScenarioFileError  # noqa: F401
from .runner import defaults, prepare, run  # noqa: F401
from .schema import ScenarioFile, from_dict, load, looks_like_robot_file  # noqa: F401
from .signals import BY_FAMILY as SIGNALS  # noqa: F401


def is_scenario_file(arg) -> bool:
    """Whether a `kiloloop run` argument names a scenario file rather than a built-in scenario."""
    return str(arg).endswith(".toml")
