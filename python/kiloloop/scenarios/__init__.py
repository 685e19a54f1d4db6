"""SIL scenarios, one file per scenario, registered by name (`kiloloop list`).

A scenario module defines NAME, DESCRIPTION, ROBOT (the robot it runs on by default, a name in
models/), DEFAULTS (settings a user may --set), CRITERIA (metric -> (comparison, threshold)) and
run(settings, seed, duration, robot) -> ScenarioResult; optionally derive(robot) -> settings that
depend on the robot (waypoints, sizes: from its limits and geometry, never from one model). The
criteria live beside the scenario and are the very ones its pytest asserts.

Settings are layered: DEFAULTS < derive(robot) < the robot file's [scenario.<name>] < --set.
A --set key with a dot (`controller.kp=400`) or naming a robot-file table sets the robot file.

Every scenario runs its closed loop in C++ through the one rig (sil/rig.py: Rig over the native
Rollout; video frames and payload attachments between ticks). docs/native_sil.md has the loop.

Optional declarations a scenario module may make, checked here before anything runs:
- MIN_DURATION [s], or min_duration(settings[, robot]) -> [s]: the shortest run whose metrics
  it can judge (its metric windows and events, plus JUDGED_WINDOW), from its own constants (and
  what it derives from the robot, arm-estop); default JUDGED_WINDOW. `check_duration` refuses a
  shorter --duration.
- SIZES: setting -> "nq" (one value per joint of the robot's controlled chain) or a count; a
  list setting given with another count is refused (an empty list, where it means "derived",
  is always accepted).
- LIMITS: setting -> (comparison, bound) as in CRITERIA (`"slide_time": (">", 0.0)`): what a
  value must satisfy to mean anything (a zero duration, a negative speed scale).
- ROBOT_KEYS: the robot-file tables (dotted prefixes) it reads; a --set of any other robot-file
  key has no effect on it and draws a warning (UnreadKeyWarning). Default: every table.

Errors a user's input causes are kiloloop.errors.InputError (a ValueError): the CLI prints them as
one line and exits 2. prepare() runs the family's start checks (feasibility.py): a robot whose
data rule a scenario out (an effort limit that cannot hold its weight standing, rotors that cannot
lift it) is refused with errors.ScenarioRefused, an InputError, before anything runs.

A metric a scenario cannot compute is NaN with a reason (NotComputed, or evaluate's `reasons`):
its criterion fails and says "not computed: <why>".
"""
from __future__ import annotations

import importlib
import math
import numbers
import warnings
from dataclasses import dataclass, field

from ..robot import Robot, RobotFileError
from ..robot.robot_file import register_table_check
from ..errors import InputError, UnknownName, UnreadKeyWarning
from ..robot.robot_file import parse_value  # noqa: F401  (one parser for every --set value)
from ..sil.log import SignalLog

# [s] the shortest stretch of a run a metric is judged over (100 ticks): a scenario's minimum
# duration is where its last metric window starts (or its last event ends) plus this.
JUDGED_WINDOW = 0.1
# Robot-file keys every scenario reads (the robot itself).
_ROBOT_BASICS = ("name", "kind", "urdf", "package_dirs", "description")

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


class NotComputed(float):
    """A metric a scenario could not compute, and why: a NaN that carries its reason
    (`metrics["stop_time"] = NotComputed("the e-stop never stopped the arm")`). It is a float, so
    every table and log that formats metrics still takes it; `evaluate` fails its criterion with
    the reason, and the CLI and the zoo print "not computed: <reason>", never a number."""

    reason: str

    def __new__(cls, reason: str):
        value = super().__new__(cls, float("nan"))
        value.reason = str(reason)
        return value

    def __repr__(self) -> str:
        return f"NotComputed({self.reason!r})"

    def __reduce__(self):   # pickled (process pools) with its reason
        return (NotComputed, (self.reason,))


def evaluate(criteria: dict[str, tuple[str, float]], metrics: dict[str, float],
             reasons: dict[str, str] | None = None) -> dict[str, dict]:
    """Checks each metric against its criterion. A metric that is missing, NaN (or NotComputed)
    fails, and its row carries `reason`: "not computed: ..." with the scenario's reason (a
    NotComputed value, or `reasons[name]`) or what is known (missing; NaN with no reason given)."""
    out = {}
    for name, (op, threshold) in criteria.items():
        value = metrics.get(name, float("nan"))
        row = {"value": value, "op": op, "threshold": threshold,
               "passed": bool(_OPS[op](value, threshold))}
        why = not_computed_reason(name, metrics, reasons)
        if why:
            row["passed"], row["reason"] = False, why
        out[name] = row
    return out


def not_computed_reason(name: str, metrics: dict, reasons: dict | None = None) -> str:
    """"not computed: <why>" for a metric that is missing or not a finite-or-infinite number
    (NaN), "" for one that is a number."""
    if name not in metrics:
        why = (reasons or {}).get(name) or "the scenario did not report it"
    else:
        value = metrics[name]
        try:
            nan = math.isnan(float(value))
        except (TypeError, ValueError):
            nan = True
        if not nan:
            return ""
        why = getattr(value, "reason", "") or (reasons or {}).get(name) or _nan_context(metrics)
    return f"not computed: {why}"


# Flags the families' metrics set when a run ends before its script does (quadrupeds: a fall;
# multirotors: divergence): the metric windows after it hold no samples.
_ENDED_EARLY = ("fell", "diverged")


def _nan_context(metrics: dict) -> str:
    """What is known about a NaN the scenario gave no reason for."""
    for flag in _ENDED_EARLY:
        value = metrics.get(flag)
        if isinstance(value, (int, float)) and value == value and value > 0.5:
            return f"NaN, the run ended early ({flag})"
    return "NaN (the scenario gave no reason)"


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
        raise UnknownName(f"unknown scenario {name!r}; known: {', '.join(_MODULES)}")
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
                raise InputError(f"--set {item!r}: expected KEY=VALUE")
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


def prepare(module, robot=None, overrides: list[str] | dict | None = None, *,
            warn: bool = True):
    """The robot (loaded, --set applied) and the scenario settings for one run.

    robot: None (the scenario's own), a name, a robot file or directory, or a loaded Robot.
    Raises InputError (RobotFileError included) with a message fit for one line; with `warn`,
    an UnreadKeyWarning for each robot-file key the scenario does not read.
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
        raise InputError(f"{module.NAME} needs a robot of kind '{kind_of(module)}'; "
                         f"{robot.name} is '{robot.kind}'")
    if "robot" not in inspect.signature(module.run).parameters and (
            robot.name != default_robot(module) or robot_sets):
        raise InputError(f"{module.NAME} runs only on its own robot '{default_robot(module)}' so "
                         f"far (it does not read robot files yet)")
    for key in unread_keys(module, robot_sets) if warn else []:
        warnings.warn(f"--set {key}: {module.NAME} does not read it (no effect on this run)",
                      UnreadKeyWarning, stacklevel=2)
    nq = check_robot_sizes(robot)
    from .feasibility import check as check_feasible

    check_feasible(module.NAME, robot)   # ScenarioRefused: what the robot's data rule out
    settings = dict(module.DEFAULTS)
    if hasattr(module, "derive"):
        settings.update(module.derive(robot))
    settings = parse_settings(settings, robot.scenario_overrides(module.NAME),
                              where=f"{robot.path}: scenario.{module.NAME}.")
    settings = parse_settings(settings, scenario_sets)
    check_settings(module, settings, nq)
    return robot, settings


def unread_keys(module, keys) -> list[str]:
    """The dotted robot-file keys among `keys` that `module` does not read: another scenario's
    [scenario.<name>] table, and any table outside the module's ROBOT_KEYS (when it declares
    them)."""
    reads = getattr(module, "ROBOT_KEYS", None)
    out = []
    for key in keys:
        table = key.split(".")[0]
        if table == "scenario":
            if key.split(".")[1:2] != [module.NAME]:
                out.append(key)
        elif reads is not None and table not in _ROBOT_BASICS and not any(
                key == r or key.startswith(r + ".") for r in reads):
            out.append(key)
    return out


def check_robot_sizes(robot) -> int | None:
    """The joints a per-joint setting has one value for: an arm's controlled chain (after checking
    the robot file's per-joint values against it, robot/arm.py check_sizes), an aerial robot's
    arm (when it has one); None otherwise."""
    if robot.kind == "arm":
        from ..robot import arm

        model = robot.model()
        arm.check_sizes(robot, model)
        return model.nq
    if robot.kind == "aerial" and robot.section("vehicle").get("ee"):
        return robot.model().nq
    return None


def check_settings(module, settings: dict, nq: int | None) -> None:
    """The settings against the module's SIZES and LIMITS (module doc); nq: the robot's joints
    (check_robot_sizes). Raises InputError naming the setting, what it expects and what it got."""
    check_sizes(module, settings, nq)
    for key, (op, bound) in getattr(module, "LIMITS", {}).items():
        value = settings.get(key)
        if _is_number(value) and not _OPS[op](value, bound):
            raise InputError(f"{key}: expected {op} {bound:g}, got {value:g}")


def check_sizes(module, settings: dict, nq: int | None) -> None:
    """Each list setting the module sizes (SIZES: "nq" or a count) has that many values, or none
    (derived). Raises InputError naming the setting, the expected and the given count."""
    for key, size in getattr(module, "SIZES", {}).items():
        value = settings.get(key)
        if not isinstance(value, (list, tuple)) or not len(value):
            continue
        expected = nq if size == "nq" else size
        if expected is not None and len(value) != expected:
            what = f"{expected} values" + (" (one per joint of the chain)" if size == "nq" else "")
            raise InputError(f"{key}: expected {what}, got {len(value)}")


def min_duration(module, settings: dict | None = None, robot=None) -> float:
    """[s] the shortest run whose metrics `module` can judge: its min_duration(settings[, robot])
    (robot: where it depends on what the scenario derives from the robot) or MIN_DURATION (see
    the module doc), else JUDGED_WINDOW."""
    import inspect

    if hasattr(module, "min_duration"):
        settings = dict(module.DEFAULTS, **(settings or {}))
        if "robot" in inspect.signature(module.min_duration).parameters:
            return float(module.min_duration(settings, robot=robot))
        return float(module.min_duration(settings))
    return float(getattr(module, "MIN_DURATION", JUDGED_WINDOW))


def check_duration(duration, module=None, settings: dict | None = None, robot=None, *,
                   minimum: float | None = None, where: str = "--duration"):
    """A run's duration [s] as given (None: the scenario's default, returned as None), checked:
    a finite number > 0 and, for a module (or with `minimum`), at least what the scenario needs
    to judge its metrics (min_duration). Raises InputError with one line naming `where`. Used by
    `kiloloop run` and `sweep` (the scenario's own minimum, for `robot`) and `b2b` (just > 0)."""
    if duration is None:
        return None
    try:
        d = float(duration)
    except (TypeError, ValueError):
        raise InputError(f"{where} {duration!r}: expected a number of seconds") from None
    if not math.isfinite(d) or d <= 0:
        raise InputError(f"{where} {d:g}: expected a finite number of seconds > 0")
    if minimum is None and module is not None:
        minimum = min_duration(module, settings, robot)
    if minimum is not None and d < minimum - 1e-9:
        name = module.NAME if module is not None else "the scenario"
        raise InputError(f"{where} {d:g}: {name} needs at least {minimum:.4g} s to judge its "
                         f"metrics")
    return d


def run_named(name: str, robot=None, overrides: list[str] | dict | None = None, seed: int = 0,
              duration=None) -> ScenarioResult:
    """What `kiloloop run NAME --robot ROBOT --set ...` runs (tests and scripts use it)."""
    module = get(name)
    robot, settings = prepare(module, robot, overrides)
    return run(module, settings, robot, seed=seed, duration=duration)


def run(module, settings: dict, robot, seed: int | None = 0, duration=None):
    """module.run with the robot when the scenario reads robot files; the log comes back
    described (units, component names, frames: scenarios/signals.py) and saying what run made
    it (log.info: scenario, robot, settings, criteria; run_info.py). seed None: the scenario's
    own (a scenario file's `seed`, else 0)."""
    import inspect

    from .run_info import attach
    from .signals import describe

    seed = getattr(module, "SEED", 0) if seed is None else seed

    if "robot" in inspect.signature(module.run).parameters:
        result = module.run(settings, seed=seed, duration=duration, robot=robot)
    else:
        result = module.run(settings, seed=seed, duration=duration)
    if result.log is not None and result.scenario_file is None:   # a file's run describes its own
        describe(result.log, kind_of(module), robot)
    attach(result, module, robot, seed, duration)
    return result


def parse_settings(defaults: dict, overrides: list[str] | dict | None, where: str = "") -> dict:
    """Applies `key=value` overrides to a scenario's DEFAULTS, converting to the default's type;
    `where` prefixes an error (`FILE: scenario.NAME.` for a robot file's table)."""
    settings = dict(defaults)
    items = overrides.items() if isinstance(overrides, dict) else (
        item.split("=", 1) for item in (overrides or []))
    for key, value in items:
        if key not in defaults:
            raise InputError(f"unknown setting {key!r}; known: {', '.join(sorted(defaults))}")
        try:
            settings[key] = _convert(defaults[key], value, key)
        except InputError as e:
            raise InputError(f"{where}{e}") from None
    return settings


def _convert(default, value, key):
    """A --set string as the default's type: a bool (true/false, on/off, 1/0), an int, a finite
    float, a list of finite numbers (`0.1,-0.2` or `[0.1, -0.2]`; empty: `[]` or nothing), a
    number or `none` where the default is None, a string otherwise. Values that are not strings
    (a robot file's [scenario.*] table, a script's dict) are taken as they are, once checked to
    be of the default's kind."""
    if not isinstance(value, str):
        return _checked(default, value, key)
    if isinstance(default, bool):
        if value.lower() in ("1", "true", "yes", "on"):
            return True
        if value.lower() in ("0", "false", "no", "off"):
            return False
        raise InputError(f"{key}: expected a boolean, got {value!r}")
    if isinstance(default, (list, tuple)):
        parsed = parse_value(value) if value.strip() else []
        items = parsed if isinstance(parsed, list) else [parsed]
        if not all(_is_number(v) for v in items):
            raise InputError(f"{key}: expected a list of numbers (0.1,0.2 or [0.1, 0.2]), "
                             f"got {value!r}")
        return _finite(key, [float(v) for v in items], value)
    if default is None and value.strip().lower() in ("", "none"):
        return None
    if isinstance(default, (int, float)) or default is None:
        try:
            number = int(value) if isinstance(default, int) else float(value)
        except ValueError:
            kind = {int: "a whole number", float: "a number"}.get(type(default), "a number or none")
            raise InputError(f"{key}: expected {kind}, got {value!r}") from None
        return _finite(key, number, value)
    return value


def _is_number(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool)


def _checked(default, value, key):
    """A value that is not a string, as given, when it is of the default's kind (a number for a
    number, a whole one for an int, a sequence of numbers for a list, a number or None for None);
    anything else is an InputError naming the key."""
    if isinstance(default, bool):
        ok, kind = isinstance(value, bool), "true or false"
    elif isinstance(default, int):
        ok, kind = _is_number(value) and float(value) == int(value), "a whole number"
    elif isinstance(default, float):
        ok, kind = _is_number(value), "a number"
    elif isinstance(default, (list, tuple)):
        ok = hasattr(value, "__len__") and all(_is_number(v) for v in value)
        kind = "a list of numbers"
    elif default is None:
        ok, kind = value is None or _is_number(value), "a number or none"
    else:
        ok, kind = True, ""
    if not ok:
        raise InputError(f"{key}: expected {kind}, got {value!r}")
    return value


def _finite(key, value, text):
    """value (a float or a list of floats) when every number is finite; NaN and Inf mean no
    setting's value."""
    if not all(math.isfinite(v) for v in (value if isinstance(value, list) else [value])):
        raise InputError(f"{key}: not a finite number (NaN or Inf): {text!r}")
    return value
