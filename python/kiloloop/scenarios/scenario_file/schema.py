"""A scenario file (TOML) read and checked: every key known, every value of its type, the
reference, events and criteria consistent with one robot family. What depends on the robot
(joint counts, rotor indices, link names) is checked when the run starts (runner.py).

    name = "my_mission"
    robot = "my_arm.toml"   # a robot file (relative to this file), a directory, a name in models/
    duration = 6.0          # [s] simulated
    seed = 0
    [settings]              # the family's settings (the keys `--set` takes) and robot-file keys
    [reference]             # exactly one table: joint | cartesian | velocity | position
    [[events]]              # push | rotor_fault | estop | sensor_dropout | payload
    [criteria]              # "function(signal[, t0[, t1]])" = "op threshold"
    [baseline]              # file = "base.npz", signals = { name = tolerance }
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from . import baseline as baseline_mod
from . import criteria as criteria_mod
from . import events as events_mod
from . import reference as reference_mod
from .errors import ScenarioFileError
from .signals import BY_FAMILY

TOP_KEYS = ("name", "description", "robot", "duration", "seed", "settings", "reference",
            "events", "criteria", "baseline")
DEFAULT_ROBOT = {"arm": "ur5", "quadruped": "quadruped", "aerial": "aerial_manipulator"}


@dataclass
class ScenarioFile:
    path: Path | None           # None: built from a dict (tests, the fixture)
    name: str
    family: str                 # arm | quadruped | aerial (from the reference)
    robot: str                  # a path (resolved against the file) or a name in models/
    duration: float             # [s]
    seed: int
    settings: dict              # flat: family settings and dotted robot-file keys
    reference: reference_mod.Reference
    events: list = field(default_factory=list)
    criteria: list = field(default_factory=list)
    baseline: baseline_mod.BaselineSpec | None = None
    description: str = ""
    source: dict | None = None  # the TOML table as read (what a log records of a dict-built file)

    @property
    def where(self) -> str:
        return str(self.path) if self.path is not None else f"scenario {self.name!r}"


def looks_like_robot_file(data: dict) -> bool:
    """A robot file (kind = ...), not a scenario file: the pytest plugin leaves it alone."""
    return "kind" in data and "reference" not in data


def read(path) -> dict:
    """The file's TOML as a dict; ScenarioFileError for a missing file or a syntax error."""
    path = Path(path)
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise ScenarioFileError(path, "", "no such file") from None
    except tomllib.TOMLDecodeError as e:
        raise ScenarioFileError(path, "", f"not valid TOML: {e}") from None


def load(path) -> ScenarioFile:
    path = Path(path).resolve()
    return from_dict(read(path), path)


def flatten_settings(table: dict, prefix: str = "") -> dict:
    """[settings] with nested tables as dotted keys (`[settings.controller] kp = 400` ->
    `controller.kp`: a robot-file key; `controller = "pd_gravity"` stays a family setting)."""
    out = {}
    for key, value in table.items():
        dotted = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(flatten_settings(value, dotted + "."))
        else:
            out[dotted] = value
    return out


def from_dict(data: dict, path: Path | None = None, name: str | None = None) -> ScenarioFile:
    where = path if path is not None else f"scenario {name or data.get('name', '')!r}"

    def fail(key, what):
        raise ScenarioFileError(where, key, what)

    unknown = [k for k in data if k not in TOP_KEYS]
    if unknown:
        fail(unknown[0], f"unknown key; known: {', '.join(TOP_KEYS)}")
    if "reference" not in data:
        fail("reference", "missing: give exactly one of joint, cartesian (arm), velocity "
                          "(quadruped), position (aerial)")
    try:
        reference = reference_mod.parse(data["reference"])
    except ValueError as e:
        raise_at(where, str(e), "reference")
    family = reference.family
    signals = BY_FAMILY[family]

    name_value = data.get("name", path.stem if path is not None else name or "scenario")
    if not isinstance(name_value, str) or not name_value:
        fail("name", f"expected a string, got {name_value!r}")
    duration = data.get("duration", None)
    if duration is None:
        duration = max(reference.end_time + 1.0, 1.0)
    if isinstance(duration, bool) or not isinstance(duration, (int, float)) or \
            not math.isfinite(duration) or duration <= 0:
        fail("duration", f"expected a number of seconds > 0, got {duration!r}")
    seed = data.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        fail("seed", f"expected an integer >= 0, got {seed!r}")
    robot = data.get("robot", DEFAULT_ROBOT[family])
    if not isinstance(robot, str) or not robot:
        fail("robot", f"expected a robot file, directory or name, got {robot!r}")
    if path is not None and ("/" in robot or robot.endswith(".toml")):
        robot = str((path.parent / robot).resolve())
    elif path is not None and (path.parent / robot).exists():
        robot = str((path.parent / robot).resolve())
    settings = data.get("settings", {})
    if not isinstance(settings, dict):
        fail("settings", "expected a table of settings")
    events_table = data.get("events", [])
    if not isinstance(events_table, list):
        fail("events", "expected [[events]] tables")
    events = []
    for i, table in enumerate(events_table):
        try:
            events.append(events_mod.parse(i, table, family))
        except ValueError as e:
            raise_at(where, str(e), "")
    criteria = []
    table = data.get("criteria", {})
    if not isinstance(table, dict):
        fail("criteria", "expected a table \"function(signal)\" = \"op threshold\"")
    for key, condition in table.items():
        try:
            criteria.append(criteria_mod.parse(key, condition, signals))
        except ValueError as e:
            fail(f'criteria."{key}"', str(e))
    spec = None
    if "baseline" in data:
        try:
            spec = baseline_mod.parse(data["baseline"],
                                      path.parent if path is not None else None, signals)
        except ValueError as e:
            raise_at(where, str(e), "baseline")
    description = data.get("description", "")
    if not isinstance(description, str):
        fail("description", "expected a string")
    return ScenarioFile(path, name_value, family, robot, float(duration), seed,
                        flatten_settings(settings), reference, events, criteria, spec,
                        description, data)


def raise_at(where, message: str, table: str):
    """ScenarioFileError from a part's parser's message, "key: what" (the key under `table`)
    or a bare "what" (about the table itself)."""
    key, sep, what = message.partition(": ")
    if sep and " " not in key:
        raise ScenarioFileError(where, f"{table}.{key}" if table else key, what) from None
    raise ScenarioFileError(where, table, message) from None
