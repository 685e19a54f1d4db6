"""SIL scenarios, one file per scenario, registered by name (`kiloloop list`).

A scenario module defines NAME, DESCRIPTION, ROBOT (the robot it runs on by default, a name in
models/), DEFAULTS (settings a user may --set), CRITERIA (metric -> (comparison, threshold)) and
run(settings, seed, duration, robot) -> ScenarioResult; optionally derive(robot) -> settings that
depend on the robot (waypoints, sizes: from its limits and geometry, never from one model). The
criteria live beside the scenario and are the very ones its pytest asserts.

Settings are layered: DEFAULTS < derive(robot) < the robot file's [scenario.<name>] < --set.
A --set key with a dot (`controller.kp=400`) or naming a robot-file table sets the robot file.

Loops: arm-track, arm-line, arm-estop and quadruped-* run natively (C++ loop, sil/native.py)
unless `--set native=false` (or video / ground truth for the quadruped); every other scenario runs
per tick in Python: arm-press (tool force sensor each tick), arm-rrt (MuJoCo box contacts each
tick), aerial-* (no native adapter yet). README "Native SIL loop" says why.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass, field

from ..robot import Robot, RobotFileError
from ..robot.robot_file import register_table_check
from ..sil.log import SignalLog

# Scenario name -> module (one concept per file; the name is the CLI name).
_MODULES = {
    "arm-track": "arm_track",
    "quadruped-stand": "quadruped_stand",
    "quadruped-slope": "quadruped_slope",
    "quadruped-trot": "quadruped_trot",
    "quadruped-push": "quadruped_push",
    "quadruped-tilt-stop": "quadruped_tilt_stop",
    "quadruped-turn": "quadruped_turn",
    "quadruped-slope-trot": "quadruped_slope_trot",
    "quadruped-stones": "quadruped_stones",
    "quadruped-compliant": "quadruped_compliant",
    "quadruped-rough": "quadruped_rough",
    "arm-line": "arm_line",
    "arm-rrt": "arm_rrt",
    "arm-press": "arm_press",
    "arm-estop": "arm_estop",
    "aerial-hover": "aerial_hover",
    "aerial-attitude-step": "aerial_attitude_step",
    "aerial-arm-sweep": "aerial_arm_sweep",
    "aerial-reach": "aerial_reach",
    "aerial-rotor-fault": "aerial_rotor_fault",
    "aerial-wind": "aerial_wind",
    "aerial-push": "aerial_push",
}


@dataclass
class ScenarioResult:
    scenario: str
    metrics: dict[str, float]
    criteria: dict[str, dict] = field(default_factory=dict)
    log: SignalLog | None = None
    settings: dict = field(default_factory=dict)
    components: dict = field(default_factory=dict)   # signal -> component names (files' signals)
    scenario_file: object = None                      # the ScenarioFile a file's run came from

    @property
    def passed(self) -> bool:
        return all(c["passed"] for c in self.criteria.values())

    def to_json(self) -> dict:
        return {"scenario": self.scenario, "passed": self.passed, "metrics": self.metrics,
                "criteria": self.criteria, "settings": self.settings}


_OPS = {"<": lambda a, b: a < b, "<=": lambda a, b: a <= b,
        ">": lambda a, b: a > b, ">=": lambda a, b: a >= b}


def evaluate(criteria: dict[str, tuple[str, float]], metrics: dict[str, float]) -> dict[str, dict]:
    """Checks each metric against its criterion; a NaN or missing metric fails."""
    out = {}
    for name, (op, threshold) in criteria.items():
        value = metrics.get(name, float("nan"))
        out[name] = {"value": value, "op": op, "threshold": threshold,
                     "passed": bool(_OPS[op](value, threshold))}
    return out


def names() -> list[str]:
    return list(_MODULES)


def example_files() -> list:
    """The scenario files that ship with kiloloop (scenarios/files/), one or more per family."""
    from pathlib import Path

    return sorted((Path(__file__).parent / "files").glob("*.toml"))


def get(name: str):
    """A built-in scenario's module by name, or a scenario file (a path ending in .toml) seen as
    one (scenario_file/as_module.py: ScenarioFileError, a ValueError, when it is broken)."""
    if str(name).endswith(".toml"):
        from .scenario_file.as_module import FileScenario

        return FileScenario(name)
    if name not in _MODULES:
        raise KeyError(f"unknown scenario {name!r}; known: {', '.join(_MODULES)}")
    return importlib.import_module(f"{__name__}.{_MODULES[name]}")


def check_scenario_tables(tables, where: str) -> None:
    """A robot file's [scenario.<name>] tables: each names a scenario and sets only its settings;
    otherwise RobotFileError naming `where` and the key. Robot.load calls it once this module is
    imported (registered below); prepare() calls it for a robot loaded before that."""
    if not isinstance(tables, dict):
        raise RobotFileError(f"{where}: scenario: expected tables [scenario.<name>]")
    for name, values in tables.items():
        if name not in _MODULES:
            raise RobotFileError(f"{where}: unknown key 'scenario.{name}' (no such scenario)")
        if not isinstance(values, dict):
            raise RobotFileError(f"{where}: scenario.{name}: expected a table")
        known = get(name).DEFAULTS
        for key in values:
            if key not in known:
                raise RobotFileError(f"{where}: unknown key 'scenario.{name}.{key}'")


register_table_check("scenario", check_scenario_tables)


def split_overrides(items: list[str] | dict | None) -> tuple[dict, dict]:
    """--set items -> (robot-file overrides by dotted key, scenario settings)."""
    pairs = list(items.items()) if isinstance(items, dict) else []
    if not isinstance(items, dict):
        for item in items or []:
            if "=" not in item:
                raise ValueError(f"--set {item!r}: expected KEY=VALUE")
            pairs.append(item.split("=", 1))
    robot_sets, scenario_sets = {}, {}
    for key, value in pairs:
        (robot_sets if "." in key else scenario_sets)[key] = value
    return robot_sets, scenario_sets


def default_robot(module) -> str:
    return getattr(module, "ROBOT", None) or {"arm": "ur5", "quadruped": "quadruped",
                                              "aerial": "aerial_manipulator"}[module.NAME.split("-")[0]]


def kind_of(module) -> str:
    return getattr(module, "KIND", None) or module.NAME.split("-")[0]


def prepare(module, robot=None, overrides: list[str] | dict | None = None):
    """The robot (loaded, --set applied) and the scenario settings for one run.

    robot: None (the scenario's own), a name, a robot file or directory, or a loaded Robot.
    Raises ValueError (RobotFileError included) with a message fit for one line.
    """
    import inspect

    if hasattr(module, "prepare"):   # a scenario file: its own layering and error keys
        return module.prepare(robot, overrides)
    robot_sets, scenario_sets = split_overrides(overrides)
    if not isinstance(robot, Robot):
        robot = Robot.load(default_robot(module) if robot is None else robot)
    check_scenario_tables(robot.data.get("scenario", {}), str(robot.path))
    # A scenario file's own robot-file settings first, then the overrides'.
    for sets in (getattr(module, "ROBOT_OVERRIDES", {}), robot_sets):
        if sets:
            robot = robot.with_overrides(sets)
    if robot.kind != kind_of(module):
        raise ValueError(f"{module.NAME} needs a robot of kind '{kind_of(module)}'; "
                         f"{robot.name} is '{robot.kind}'")
    if "robot" not in inspect.signature(module.run).parameters and (
            robot.name != default_robot(module) or robot_sets):
        raise ValueError(f"{module.NAME} runs only on its own robot '{default_robot(module)}' so "
                         f"far (it does not read robot files yet)")
    settings = dict(module.DEFAULTS)
    if hasattr(module, "derive"):
        settings.update(module.derive(robot))
    settings = parse_settings(settings, robot.scenario_overrides(module.NAME))
    settings = parse_settings(settings, scenario_sets)
    return robot, settings


def run_named(name: str, robot=None, overrides: list[str] | dict | None = None, seed: int = 0,
              duration=None) -> ScenarioResult:
    """What `kiloloop run NAME --robot ROBOT --set ...` runs (tests and scripts use it)."""
    module = get(name)
    robot, settings = prepare(module, robot, overrides)
    return run(module, settings, robot, seed=seed, duration=duration)


def run(module, settings: dict, robot, seed: int | None = 0, duration=None):
    """module.run with the robot when the scenario reads robot files; the log comes back
    described (units, component names: scenarios/signals.py). seed None: the scenario's own
    (a scenario file's `seed`, else 0)."""
    import inspect

    from .signals import describe

    seed = getattr(module, "SEED", 0) if seed is None else seed

    if "robot" in inspect.signature(module.run).parameters:
        result = module.run(settings, seed=seed, duration=duration, robot=robot)
    else:
        result = module.run(settings, seed=seed, duration=duration)
    if result.log is not None and result.scenario_file is None:   # a file's run describes its own
        describe(result.log, kind_of(module), robot)
    return result


def parse_settings(defaults: dict, overrides: list[str] | dict | None) -> dict:
    """Applies `key=value` overrides to a scenario's DEFAULTS, converting to the default's type."""
    settings = dict(defaults)
    items = overrides.items() if isinstance(overrides, dict) else (
        item.split("=", 1) for item in (overrides or []))
    for key, value in items:
        if key not in defaults:
            raise ValueError(f"unknown setting {key!r}; known: {', '.join(sorted(defaults))}")
        settings[key] = _convert(defaults[key], value, key)
    return settings


def _convert(default, value, key):
    if not isinstance(value, str):
        return value
    if isinstance(default, bool):
        if value.lower() in ("1", "true", "yes", "on"):
            return True
        if value.lower() in ("0", "false", "no", "off"):
            return False
        raise ValueError(f"{key}: expected a boolean, got {value!r}")
    try:
        if isinstance(default, int):
            return int(value)
        if isinstance(default, float):
            return float(value)
        if isinstance(default, (list, tuple)):
            return [float(v) for v in value.split(",")]
    except ValueError:
        raise ValueError(f"{key}: expected {type(default).__name__}, got {value!r}") from None
    return value
