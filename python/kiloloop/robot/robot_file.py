"""Robot: a parsed, validated robot file (TOML) and the URDF it names.

Only the file's own content lives here; what is derived from the URDF (start pose, gains,
scenario sizes) is computed by the family modules beside this one, so that a value the file gives
always wins and a value it omits always comes from the robot's own masses and geometry.
"""
from __future__ import annotations

import copy
import hashlib
import os
import tomllib
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Callable

from ..errors import InputError
from . import joint_limits, schema
from .aerial import model as aerial_model
from .arm import armature as arm_armature
from .errors import RobotFileError
from .urdf_doc import UrdfDoc, read as read_urdf

# Checks of top-level tables that a layer above robot/ owns: table name -> check(values, where),
# which raises RobotFileError naming `where` and the key. kiloloop.scenarios registers
# [scenario.<name>] (scenario names and their settings) when it is imported; robot/ imports no
# scenario, so that loading a robot file needs neither the scenarios nor MuJoCo.
_TABLE_CHECKS: dict[str, Callable[[object, str], None]] = {}


def register_table_check(table: str, check: Callable[[object, str], None]) -> None:
    """Makes every later load and --set of a robot file call check(file[table], where) when the
    file has that table."""
    _TABLE_CHECKS[table] = check



def _models_dir() -> Path:
    from .. import models_dir

    return models_dir()


def known_robots() -> list[str]:
    return sorted(p.parent.name for p in _models_dir().glob("*/robot.toml"))


def resolve_robot_path(name_or_path) -> Path:
    """A robot file: an existing .toml file, a directory holding robot.toml, or the name of a
    robot in kiloloop's models/ (models/<name>/robot.toml)."""
    p = Path(name_or_path)
    if p.is_file():
        return p
    if p.is_dir():
        if (p / "robot.toml").is_file():
            return p / "robot.toml"
        raise RobotFileError(f"{p}: directory has no robot.toml")
    if p.suffix == ".toml" or os.sep in str(name_or_path):
        raise RobotFileError(f"{p}: robot file not found")
    candidate = _models_dir() / str(name_or_path) / "robot.toml"
    if candidate.is_file():
        return candidate
    raise RobotFileError(f"no robot named '{name_or_path}' (not a file either); known: "
                         f"{', '.join(known_robots())}")


def parse_value(text: str):
    """A --set value as TOML would read it (1, 2.5, true, [1, 2], "s"); a list may also be given
    bare, `0.1,-0.2` as `[0.1, -0.2]` (what a shell user types; both forms work for every key),
    and numbers as Python writes them (`.5`, `1.`, which TOML refuses); anything else (a bare
    word) stays a str, for the reader to accept or refuse."""
    for form in (f"v = {text}", f"v = [{text}]" if "," in text else None):
        if form is None:
            continue
        try:
            return tomllib.loads(form)["v"]
        except tomllib.TOMLDecodeError:
            pass
    bare = text.strip()
    is_list = "," in bare or bare.startswith("[")
    try:
        numbers = [float(v) for v in bare.strip("[]").split(",")] if bare.strip("[] ") else []
    except ValueError:
        return text
    return numbers if is_list else (numbers[0] if numbers else text)


def _set_dotted(data: dict, dotted: str, value) -> None:
    keys = dotted.split(".")
    node = data
    for k in keys[:-1]:
        nxt = node.setdefault(k, {})
        if not isinstance(nxt, dict):
            raise RobotFileError(f"--set {dotted}: '{k}' is not a table")
        node = nxt
    node[keys[-1]] = value


@dataclass(frozen=True)
class Robot:
    path: Path              # the robot file
    data: dict              # its content, overrides applied
    overrides: dict = field(default_factory=dict)  # dotted key -> value, as applied

    # --- loading -------------------------------------------------------------------------------
    @classmethod
    def load(cls, name_or_path, overrides: dict | None = None) -> "Robot":
        path = resolve_robot_path(name_or_path).resolve()
        try:
            with open(path, "rb") as f:
                data = tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            raise RobotFileError(f"{path}: not valid TOML: {e}") from None
        robot = cls(path=path, data=data)
        robot._validate()
        return robot.with_overrides(overrides) if overrides else robot

    def with_overrides(self, overrides: dict) -> "Robot":
        """A copy with dotted keys set (`controller.kp`, `sim.joints.damping`); string values are
        read as TOML values. The result is validated like a file."""
        data = copy.deepcopy(self.data)
        applied = dict(self.overrides)
        for key, value in overrides.items():
            value = parse_value(value) if isinstance(value, str) else value
            _set_dotted(data, key, value)
            applied[key] = value
        robot = Robot(path=self.path, data=data, overrides=applied)
        robot._validate(source="--set")
        return robot

    def where(self, key: str) -> str:
        """Where a dotted key's value came from, for an error message: `--set KEY` when a --set
        gave it, else `FILE: KEY`."""
        return f"--set {key}" if key in self.overrides else f"{self.path}: {key}"

    def _validate(self, source: str | None = None) -> None:
        where = f"{self.path}" + (f" (with {source})" if source else "")
        d = self.data
        for key in ("name", "kind", "urdf"):
            if key not in d:
                raise RobotFileError(f"{where}: missing key '{key}'")
        if d["kind"] not in schema.KINDS:
            raise RobotFileError(f"{where}: kind = {d['kind']!r}; expected one of "
                                 f"{', '.join(schema.KINDS)}")
        template = schema.schema_for(d["kind"])
        bad = schema.unknown_keys(d, template)
        if bad:
            raise RobotFileError(f"{where}: unknown key '{bad[0]}'")
        bad = schema.bad_values(d, template)
        if bad:
            raise RobotFileError(f"{where}: {bad[0]}")
        for section, keys in _REQUIRED[d["kind"]].items():
            for k in keys:
                if not d.get(section, {}).get(k):
                    raise RobotFileError(f"{where}: missing key '{section}.{k}'")
        if not self.urdf.is_file():
            raise RobotFileError(f"{where}: urdf: file not found: {self.urdf}")
        if "limits" in d:  # its joints and values, against the URDF (the inertias: urdf_doc)
            joint_limits.check(self.urdf, d["limits"], self.where)
        for table, check in _TABLE_CHECKS.items():
            if table in d:
                check(d[table], where)

    # --- what the file says ----------------------------------------------------------------------
    @property
    def name(self) -> str:
        return str(self.data["name"])

    @property
    def kind(self) -> str:
        return str(self.data["kind"])

    @property
    def dir(self) -> Path:
        return self.path.parent

    @property
    def urdf(self) -> Path:
        p = Path(self.data["urdf"])
        return p if p.is_absolute() else (self.dir / p)

    @property
    def package_dirs(self) -> list[Path]:
        dirs = [Path(d) if Path(d).is_absolute() else self.dir / d
                for d in self.data.get("package_dirs", [])]
        # ROS's own search path comes last: a file's list wins.
        dirs += [Path(d) for d in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if d]
        return dirs

    def section(self, name: str) -> dict:
        """A top-level table (empty when absent): chain, legs, vehicle, controller, sim, ..."""
        return copy.deepcopy(self.data.get(name, {}))

    @property
    def sim(self) -> dict:
        """The plant's sections ([sim.physics], [sim.joints], ...) as the plants take them."""
        return self.section("sim")

    def scenario_overrides(self, scenario: str) -> dict:
        return dict(self.data.get("scenario", {}).get(scenario, {}))

    @cached_property
    def urdf_doc(self) -> UrdfDoc:
        """The URDF as the controller's model and the plant read it: [limits.<joint>] and
        balance_inertia applied, every change named (robot/urdf_doc.py). Read on first use (the
        model, a plant), not at load: with_overrides({"balance_inertia": True}) still applies to
        a file whose URDF would be refused without it."""
        return read_urdf(self.urdf, limits=self.data.get("limits"),
                         balance_inertia=bool(self.data.get("balance_inertia", False)),
                         owner=f"{self.path}" + (" (with --set)" if self.overrides else ""),
                         where=self.where)

    def urdf_text(self) -> str:
        return self.urdf.read_text()

    def digest(self) -> str:
        """SHA-256 of the robot file and its URDF (what a firmware export records)."""
        h = hashlib.sha256()
        h.update(self.path.read_bytes())
        h.update(self.urdf.read_bytes())
        return h.hexdigest()

    # --- the compiled model ----------------------------------------------------------------------
    def model(self):
        """kl.RobotModel of what the controller drives: the arm's root->tip chain (off-chain
        joints locked, their mass folded in); an aerial robot's arm chain (or its whole tree
        without an arm); the whole tree for other floating-base robots."""
        from .. import _core

        urdf = self.urdf_doc.model_source()
        if self.kind == "arm":
            chain = self.data["chain"]
            locked = {k: float(v) for k, v in chain.get("locked", {}).items()}
            try:
                if locked:
                    model = _core.RobotModel.from_urdf(urdf, chain["root"], chain["tip"], locked)
                else:
                    model = _core.RobotModel.from_urdf(urdf, chain["root"], chain["tip"])
            except (ValueError, RuntimeError) as e:
                raise RobotFileError(f"{self.path}: {e}") from None
            # The joints' rotor inertia, as the plant has it (robot/arm.py armature()): every
            # controller's dynamics then holds what the plant's does. Without any: the URDF's
            # rigid body, bit for bit.
            rotor = arm_armature(self, model)
            return model.with_armature(rotor) if rotor.any() else model
        if self.kind == "aerial":
            return aerial_model(self)  # the arm's chain base -> ee, or the whole tree (no arm)
        try:
            return _core.RobotModel.from_urdf(urdf)
        except (ValueError, RuntimeError) as e:
            raise RobotFileError(f"{self.path}: {e}") from None


# Keys a robot file of each kind must give.
_REQUIRED = {
    "arm": {"chain": ("root", "tip")},
    "quadruped": {},
    "aerial": {},
}
