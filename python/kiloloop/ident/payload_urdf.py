"""A URDF with a payload rigidly added to one link (the composite mass, CoM and inertia in that
link's <inertial>, robot/inertia_merge.py), and with its relative mesh paths made absolute so the
copy may live anywhere. What `identify` writes for an identified payload; also how a test makes a
"true" robot heavier than its file says."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from ..robot.inertia_merge import _inertial, merge_into_parent


def link_inertial(urdf_path, link: str) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass [kg], CoM (3) [m], inertia about the CoM (3, 3) [kg m^2]) of a URDF link."""
    root = ET.parse(urdf_path).getroot()
    return _inertial(_link(root, link))


def _link(root, name: str):
    for el in root.iter("link"):
        if el.get("name") == name:
            return el
    raise KeyError(f"no link named {name!r}")


def write_with_payload(urdf_path, out_path, link: str, mass: float, com, inertia=None) -> Path:
    """Writes urdf_path with a payload of `mass` [kg] at `com` [m] (link frame), inertia about its
    CoM (3, 3) [kg m^2] (None: a point mass), on `link`, to out_path."""
    src = Path(urdf_path).resolve()
    tree = ET.parse(src)
    root = tree.getroot()
    if mass > 0:
        I = np.zeros((3, 3)) if inertia is None else np.asarray(inertia, float)
        child = ET.Element("link", name="payload")
        inertial = ET.SubElement(child, "inertial")
        ET.SubElement(inertial, "origin", xyz=" ".join(repr(float(x)) for x in com), rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=repr(float(mass)))
        ET.SubElement(inertial, "inertia", ixx=repr(float(I[0, 0])), iyy=repr(float(I[1, 1])), izz=repr(float(I[2, 2])),
                      ixy=repr(float(I[0, 1])), ixz=repr(float(I[0, 2])), iyz=repr(float(I[1, 2])))
        joint = ET.Element("joint")
        ET.SubElement(joint, "origin", xyz="0 0 0", rpy="0 0 0")
        merge_into_parent(child, joint, _link(root, link))
    for mesh in root.iter("mesh"):
        name = mesh.get("filename", "")
        if name and "://" not in name and not Path(name).is_absolute():
            mesh.set("filename", str((src.parent / name).resolve()))
    out = Path(out_path)
    out.parent.mkdir(parents=True, exist_ok=True)
    tree.write(out, encoding="unicode", xml_declaration=False)
    return out


def chain_last_link(urdf_path, joint_name: str) -> str:
    """The child link of a URDF joint (an arm's last joint: the link a payload sits on)."""
    root = ET.parse(urdf_path).getroot()
    for j in root.iter("joint"):
        if j.get("name") == joint_name:
            return j.find("child").get("link")
    raise KeyError(f"no joint named {joint_name!r}")
