"""Helpers for tests that bring real robots: example-robot-data's URDFs and minimal robot files."""
from __future__ import annotations

import sysconfig
from pathlib import Path

import pytest


def erd_share() -> Path:
    """The directory that package://example-robot-data/... resolves against (the wheel's share/)."""
    share = Path(sysconfig.get_paths()["purelib"]) / "cmeel.prefix" / "share"
    if not (share / "example-robot-data" / "robots").is_dir():
        pytest.skip("example-robot-data (a test dependency) is not installed")
    return share


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
