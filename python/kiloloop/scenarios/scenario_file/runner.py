"""Running a scenario file: the robot (file's, or --robot) with its overrides, the family's
settings ([settings] < --set), the family's run, then the criteria and the baseline.

Settings layer as for the built-in scenarios: the family's DEFAULTS < the file's [settings] <
`--set`. A key with a dot (`controller.kp`) or naming a robot-file table sets the robot file.
"""
from __future__ import annotations

import math

from ...errors import InputError
from .. import ScenarioResult, parse_settings, split_overrides
from . import aerial, arm, quadruped
from . import baseline as baseline_mod
from . import criteria as criteria_mod
from .errors import ScenarioFileError
from .schema import ScenarioFile
from .signals import BY_FAMILY

FAMILIES = {"arm": arm, "quadruped": quadruped, "aerial": aerial}


def defaults(family: str) -> dict:
    """The settings a scenario file of this family may give (and their defaults)."""
    return dict(FAMILIES[family].DEFAULTS)


def prepare(scenario: ScenarioFile, robot=None, overrides=None):
    """(robot, settings) for one run; ScenarioFileError naming the key otherwise. robot: None
    (the file's), a name or path (the file's robot-file settings, then the overrides', applied
    to it), or a loaded Robot (taken as it is)."""
    from ...robot import Robot

    where = scenario.where
    robot_file_sets, family_sets = split_overrides(scenario.settings)
    try:
        cli_robot, cli_family = split_overrides(overrides)
    except ValueError as e:
        raise ScenarioFileError(where, "--set", str(e)) from None
    if isinstance(robot, Robot):   # loaded, its overrides applied by the caller
        loaded, robot_file_sets, cli_robot = robot, {}, {}
    else:
        try:
            loaded = Robot.load(robot or scenario.robot)
        except (ValueError, FileNotFoundError) as e:
            raise ScenarioFileError(where, "robot" if robot is None else "--robot",
                                    str(e)) from None
    for source, sets in (("settings", robot_file_sets), ("--set", cli_robot)):
        if sets:
            try:
                loaded = loaded.with_overrides(sets)
            except ValueError as e:
                raise ScenarioFileError(where, source, str(e)) from None
    if loaded.kind != scenario.family:
        raise ScenarioFileError(where, "robot", f"the reference ({scenario.reference.kind}) is "
                                f"for the {scenario.family} family; {loaded.name} is a "
                                f"{loaded.kind}")
    settings = defaults(scenario.family)
    for source, sets in (("settings", family_sets), ("--set", cli_family)):
        try:
            settings = parse_settings(settings, sets)
        except ValueError as e:
            raise ScenarioFileError(where, source, str(e)) from None
    return loaded, settings


def run(scenario: ScenarioFile, robot=None, overrides=None, seed: int | None = None,
        duration: float | None = None, video: str | None = None,
        baseline: str | None = None) -> ScenarioResult:
    """One run of the scenario file; ScenarioFileError for anything the file (or the robot, or
    the overrides) cannot do, before or while the run is set up."""
    where = scenario.where
    robot, settings = prepare(scenario, robot, overrides)
    seed = scenario.seed if seed is None else int(seed)
    duration = scenario.duration if duration is None else duration
    if isinstance(duration, bool) or not isinstance(duration, (int, float)) or \
            not math.isfinite(duration) or duration <= 0:
        raise ScenarioFileError(where, "duration", f"expected a number of seconds > 0, got "
                                f"{duration!r}")
    shortest = criteria_mod.min_duration(scenario.criteria)
    if duration + 1e-9 < shortest:
        raise ScenarioFileError(where, "duration", f"{duration:g} s is shorter than the "
                                f"criteria's windows: give at least {shortest:g} s")
    late = [e for e in scenario.events if e.t >= duration]
    if late:
        raise ScenarioFileError(where, "events", f"{type(late[0]).__name__} at {late[0].t:g} s "
                                f"lies beyond the run's {duration:g} s")
    family = FAMILIES[scenario.family]
    try:   # what the robot cannot do with this file (a joint count, a rotor, a link name)
        log, components = family.run(scenario, robot, settings, seed, duration, video)
    except InputError as e:
        raise ScenarioFileError(where, "", str(e)) from None
    table = criteria_mod.evaluate(scenario.criteria, log["t"],
                                  {n: log[n] for n in _signals_read(scenario) if n in log},
                                  components)
    spec = scenario.baseline
    path = baseline if baseline is not None else (spec.file if spec is not None else None)
    if path is not None:
        try:
            table["baseline"] = baseline_mod.compare(log, path, spec.signals if spec else {},
                                                     components)
        except ValueError as e:
            raise ScenarioFileError(where, "baseline", str(e)) from None
    describe(log, scenario.family, robot, components)
    metrics = {k: row["value"] for k, row in table.items()}
    settings = dict(settings, robot=robot.name, robot_digest=robot.digest(), seed=seed,
                    duration=duration)
    return ScenarioResult(scenario.name, metrics, table, log, settings, components, scenario)


def describe(log, family: str, robot, components: dict) -> None:
    """Units and component names of the log: the loop's raw channels as every scenario's
    (scenarios/signals.py), then the family's signals (signals.py here) over them."""
    from ..signals import describe as describe_raw

    describe_raw(log, family, robot)
    for name, signal in BY_FAMILY[family].items():
        if name in log:
            names = components.get(name)
            shape = log[name].shape
            fits = names is not None and len(shape) == 2 and shape[1] == len(names)
            log.describe(name, signal.unit, names if fits else None, signal.description,
                         signal.frame)


def _signals_read(scenario: ScenarioFile) -> set:
    return {c.signal for c in scenario.criteria}
