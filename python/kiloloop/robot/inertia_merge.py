"""A link fixed to its parent moved into the parent's <inertial>: the same rigid body, exactly.

MuJoCo checks each body's own inertia, but a link on a fixed joint moves only with its parent:
what the dynamics see (MuJoCo's and KDL's alike) is the composite of the two. A sensor frame or a
camera whose own inertia no rigid body has (ANYmal C's cameras and hatch) is therefore repaired
without approximation by giving its parent the composite mass, CoM and inertia and the link none
(robot/urdf_inertia.py decides when).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np

from ..meshes import _origin


def _inertial(link: ET.Element) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass [kg], CoM [m] (3,), inertia about the CoM [kg m^2] (3, 3)) in the link frame;
    zero without an <inertial>."""
    inertial = link.find("inertial")
    if inertial is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    T = _origin(inertial.find("origin"))
    mass = float(inertial.find("mass").get("value"))
    i = {k: float(inertial.find("inertia").get(k)) for k in
         ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
    tensor = np.array([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]],
                       [i["ixz"], i["iyz"], i["izz"]]])
    R = T[:3, :3]
    return mass, T[:3, 3], R @ tensor @ R.T


def _about(mass: float, com: np.ndarray, point: np.ndarray) -> np.ndarray:
    """(3, 3) [kg m^2] what a point mass at `com` adds about `point` (parallel axis)."""
    d = com - point
    return mass * (float(d @ d) * np.eye(3) - np.outer(d, d))


def merge_into_parent(child: ET.Element, joint: ET.Element, parent: ET.Element) -> float:
    """Moves `child`'s <inertial> into `parent`'s (`joint`: the fixed joint between them): the
    parent gets the composite (CoM origin, axes of the parent's frame), the child none. Returns
    the mass moved [kg]."""
    m_c, c_c, I_c = _inertial(child)
    T = _origin(joint.find("origin"))
    R = T[:3, :3]
    c_c, I_c = T[:3, 3] + R @ c_c, R @ I_c @ R.T  # in the parent's frame
    m_p, c_p, I_p = _inertial(parent)
    m = m_p + m_c
    com = (m_p * c_p + m_c * c_c) / m
    tensor = I_p + _about(m_p, c_p, com) + I_c + _about(m_c, c_c, com)
    for old in parent.findall("inertial"):
        parent.remove(old)
    inertial = ET.SubElement(parent, "inertial")
    ET.SubElement(inertial, "origin", xyz=" ".join(repr(float(x)) for x in com), rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=repr(float(m)))
    ET.SubElement(inertial, "inertia", **{
        k: repr(float(tensor[i, j])) for k, (i, j) in
        zip(("ixx", "iyy", "izz", "ixy", "ixz", "iyz"),
            ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))})
    child.remove(child.find("inertial"))
    return m_c
