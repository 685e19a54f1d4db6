"""The actuated joints a URDF declares, in document order (what the plants drive and what a
robot file's per-joint lists, q0 included, are ordered by)."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from .joint_limits import ACTUATED
from .urdf_doc import UrdfDoc, tree


def urdf_joints(urdf: Path | UrdfDoc) -> tuple[list[str], np.ndarray]:
    """Actuated joint names in URDF document order, and their effort limits [N m] (inf if none).
    `urdf`: a path, or a UrdfDoc (its limits: a robot file's [limits.<joint>] applied)."""
    names, effort = [], []
    root = tree(urdf) if isinstance(urdf, UrdfDoc) else ET.parse(urdf).getroot()
    # Direct children only: <transmission> elements also contain <joint> tags.
    for joint in root.findall("joint"):
        if joint.get("type") not in ACTUATED:
            continue
        names.append(joint.get("name"))
        limit = joint.find("limit")
        e = float(limit.get("effort", 0.0)) if limit is not None else 0.0
        effort.append(e if e > 0 else np.inf)
    return names, np.array(effort)
