"""Helpers for tests that bring real robots: example-robot-data's URDFs and minimal robot files."""
from __future__ import annotations

import sys
import sysconfig
from pathlib import Path

import pytest


def erd_share() -> Path:
    """The directory that package://example-robot-data/... resolves against: the wheel installs
    its robots under site-packages/cmeel.prefix/share/ (6.x has no Python module to ask)."""
    bases = [Path(sysconfig.get_paths()["purelib"]), *map(Path, sys.path), Path(sys.prefix)]
    for base in bases:
        for share in (base / "cmeel.prefix" / "share", base / "share"):
            if (share / "example-robot-data" / "robots" / "ur_description").is_dir():
                return share
    pytest.skip("example-robot-data (a test dependency) is not installed")


def erd_robots_dir() -> Path:
    return erd_share() / "example-robot-data" / "robots"


def erd_urdf(rel: str) -> Path:
    """A URDF of example-robot-data, e.g. 'ur_description/urdf/ur10_robot.urdf'."""
    return erd_share() / "example-robot-data" / "robots" / rel


def write_robot_file(tmp_path: Path, text: str, name: str = "robot.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def minimal_arm(tmp_path: Path, urdf: Path, root: str, tip: str, name: str = "arm") -> Path:
    """The issue's minimal arm robot file: name, kind, urdf, package_dirs, [chain] only."""
    return write_robot_file(tmp_path, f'''name = "{name}"
kind = "arm"
urdf = "{urdf}"
package_dirs = ["{erd_share()}"]
[chain]
root = "{root}"
tip = "{tip}"
''', f"{name}.toml")
