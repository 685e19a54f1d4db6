"""The URDF as every model of a robot reads it: the file, parsed, with what kiloloop changes in it
applied and each change named in one line.

The controller's model (Robot.model: the C++ loader), the firmware export and the MuJoCo plants
(sil/) all build from the same UrdfDoc, so that they agree:
- the robot file's `[limits.<joint>]` (robot/joint_limits.py), then
- link inertias MuJoCo refuses (robot/urdf_inertia.py): moved into a fixed parent (exact),
  repaired without asking where the change is negligible, balanced where the robot file's
  `balance_inertia = true` asks (each warned about: UrdfRepairWarning), else refused naming the
  link, the inequality and the fix.
`kiloloop robot check` lists every change and the joints whose limits the URDF leaves infinite.
A file that is not XML is passed on untouched: the C++ loader refuses it with its reason.
"""
from __future__ import annotations

import contextlib
import copy
import tempfile
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..errors import UrdfRepairWarning
from . import joint_limits, urdf_inertia
from .errors import RobotFileError


@dataclass(frozen=True)
class UrdfDoc:
    path: Path                       # the file (meshes resolve against its directory)
    root: ET.Element | None          # parsed and repaired; None: not XML. Copy before changing.
    repairs: tuple[str, ...] = ()    # every change made, one line each
    missing_limits: dict = field(default_factory=dict)  # joint -> what it lacks (after [limits])

    @property
    def changed(self) -> bool:
        return bool(self.repairs)

    def xml(self) -> str:
        return ET.tostring(self.root, encoding="unicode")

    def model_source(self) -> str:
        """What kl.RobotModel.from_urdf takes: the file's path when nothing was changed (its
        errors then name the file), else the changed XML."""
        return self.xml() if self.changed else str(self.path)

    @contextlib.contextmanager
    def as_file(self):
        """A path holding this URDF: the file itself, or a temporary copy of the changed XML
        (for what reads only files: the firmware export's description)."""
        if not self.changed:
            yield self.path
            return
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / self.path.name
            path.write_text(self.xml())
            yield path


def read(path, *, limits: dict | None = None, balance_inertia: bool = False,
         owner: str | None = None, where: Callable[[str], str] | None = None) -> UrdfDoc:
    """The URDF at `path` with a robot file's `[limits]` table and `balance_inertia` applied.
    owner: what a refused inertia's message starts with (the robot file; default the URDF);
    where(dotted key): what a refused limit's names (the file or --set, and the key). Raises
    RobotFileError for either."""
    path = Path(path)
    owner = owner or str(path)
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError):
        return UrdfDoc(path=path, root=None)
    repairs = joint_limits.apply(root, limits or {}, where or (lambda key: f"{owner}: {key}"))
    made, balanced, refused = urdf_inertia.repair(root, balance_inertia)
    if refused:
        raise RobotFileError(f"{owner}: {path.name}: {urdf_inertia.refusal(refused[0])}")
    for line in balanced:
        warnings.warn(f"{path.name}: {line}", UrdfRepairWarning, stacklevel=2)
    return UrdfDoc(path=path, root=root, repairs=tuple(repairs + made),
                   missing_limits=joint_limits.missing(root))


def tree(doc: UrdfDoc) -> ET.Element:
    """A copy of the doc's tree to change (the file parsed again when it is not XML: its error)."""
    return copy.deepcopy(doc.root) if doc.root is not None else ET.parse(doc.path).getroot()

