"""URIs in URDFs: package://NAME/rest, file://path and plain paths, resolved to files.

The ROS/Pinocchio rule: package://NAME/rest is DIR/NAME/rest for the first DIR in package_dirs
that has it. Relative paths are relative to the URDF's directory.
"""
from __future__ import annotations

from pathlib import Path


class PackageNotFound(ValueError):
    """A package:// URI that no package directory resolves."""


def resolve_uri(uri: str, urdf_dir: Path, package_dirs) -> Path:
    """The file a mesh (or any) URI in a URDF names; PackageNotFound when a package is missing."""
    if uri.startswith("package://"):
        rest = uri[len("package://"):]
        package, _, tail = rest.partition("/")
        for d in package_dirs:
            candidate = Path(d) / package
            if candidate.is_dir():
                return candidate / tail
        searched = ", ".join(str(d) for d in package_dirs) or "(none given: set package_dirs)"
        raise PackageNotFound(f"package '{package}' (in {uri}) not found in package_dirs: "
                              f"{searched}")
    if uri.startswith("file://"):
        return Path(uri[len("file://"):])
    path = Path(uri)
    return path if path.is_absolute() else Path(urdf_dir) / path


def resolve_urdf_text(text: str, urdf_dir: Path, package_dirs) -> str:
    """The URDF text with every mesh filename made an absolute path (what MuJoCo needs)."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(text)
    changed = False
    for mesh in root.iter("mesh"):
        name = mesh.get("filename")
        if name is None:
            continue
        mesh.set("filename", str(resolve_uri(name, urdf_dir, package_dirs)))
        changed = True
    return ET.tostring(root, encoding="unicode") if changed else text
