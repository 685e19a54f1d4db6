"""Where a foot touches the ground, from its link's collision geometry: the quadruped controller
models each foot as a sphere, `foot_radius` about a centre `foot_offset` in the foot link's frame.

Real descriptions place the contact geometry in several ways, all measured here along the trunk's
down direction with every joint at zero (legs hanging, the foot frame as the URDF draws it):
a sphere about the origin (Go1, A1: its radius), a sphere offset up the shank (ANYmal: radius
0.031 m whose centre sits 0.023 m above the origin, 8 mm below it), a mesh (Go2, Solo: its lowest
vertex), a shank cylinder listed on the foot link beside the sphere (ANYmal C: the sphere is what
reaches lowest), boxes and cylinders (their support point).

    depth = foot_depth(urdf_path, "FL_foot", "trunk", package_dirs)   # [m], 0: a point foot
    offset, radius = foot_contact(urdf_path, "FL_foot", "trunk", package_dirs)

foot_contact gives the sphere itself (its centre and radius) when the lowest geometry is a sphere:
the centre moves with the shank, so an offset sphere on a bent leg reaches lower than on a straight
one, which a radius about the origin cannot say. Anything else: offset 0 and radius foot_depth.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Iterable

import numpy as np

from ..meshes import _origin, load_mesh, resolve_uri


def _down_in_link(root, link: str, base: str) -> np.ndarray:
    """The base link's -z axis in `link`'s frame, every joint at zero (the fixed origins only)."""
    parent_of = {}
    for joint in root.findall("joint"):
        child, parent = joint.find("child"), joint.find("parent")
        if child is not None and parent is not None:
            parent_of[child.get("link")] = (parent.get("link"), _origin(joint.find("origin")))
    R = np.eye(3)  # base <- link, composed leaf to root
    name = link
    while name != base:
        if name not in parent_of:  # the base is not above the foot: measure in the foot frame
            return np.array([0.0, 0.0, -1.0])
        name, T = parent_of[name]
        R = T[:3, :3] @ R
    return R.T @ np.array([0.0, 0.0, -1.0])


def _support(geom, R: np.ndarray, d: np.ndarray, urdf_dir: Path, package_dirs) -> float:
    """max over the geometry's points p (geometry frame, rotated by R into the link frame) of
    (R p) . d, or nan for a geometry it cannot read."""
    if geom.tag == "sphere":
        return float(geom.get("radius"))
    if geom.tag == "cylinder":  # axis along the geometry's z
        r, half = float(geom.get("radius")), 0.5 * float(geom.get("length"))
        c = float(np.dot(R[:, 2], d))
        return abs(c) * half + r * math.sqrt(max(0.0, 1.0 - c * c))
    if geom.tag == "box":
        size = [float(v) for v in geom.get("size").split()]
        return sum(abs(float(np.dot(R[:, i], d))) * 0.5 * size[i] for i in range(3))
    if geom.tag == "mesh":
        scale = np.array([float(x) for x in geom.get("scale", "1 1 1").split()])
        mesh = load_mesh(resolve_uri(geom.get("filename", ""), urdf_dir, package_dirs), scale)
        return float(np.max(np.asarray(mesh.vertices) @ (R.T @ d)))
    return float("nan")


def _lowest(urdf_path, foot: str, base: str, package_dirs) -> tuple[float, object, np.ndarray]:
    """The foot link's collision geometry reaching lowest below its origin along the base's down
    at the zero pose: (its reach [m], the geometry element, its origin in the link frame (4x4)),
    or (0, None, None) when none reaches below the origin or the link has none."""
    path = Path(urdf_path)
    root = ET.parse(path).getroot()
    d = _down_in_link(root, foot, base)
    deepest, lowest, origin = 0.0, None, None
    for link in root.findall("link"):
        if link.get("name") != foot:
            continue
        for col in link.findall("collision"):
            geom = col.find("geometry/*")
            if geom is None:
                continue
            T = _origin(col.find("origin"))
            reach = float(np.dot(T[:3, 3], d)) + _support(geom, T[:3, :3], d, path.parent,
                                                          list(package_dirs))
            if math.isfinite(reach) and reach > deepest:
                deepest, lowest, origin = reach, geom, T
    return deepest, lowest, origin


def foot_depth(urdf_path, foot: str, base: str, package_dirs: Iterable[str | Path] = ()) -> float:
    """[m] the lowest reach of the foot link's collision geometry below its origin, along the
    base's down direction at the zero pose; 0 when the link has no collision geometry (a point
    foot) or it lies wholly above the origin."""
    return _lowest(urdf_path, foot, base, package_dirs)[0]


def foot_contact(urdf_path, foot: str, base: str,
                 package_dirs: Iterable[str | Path] = ()) -> tuple[np.ndarray, float]:
    """The foot's contact sphere: (its centre in the foot link's frame [m] (3,), its radius [m]).
    When the geometry reaching lowest (foot_depth's) is a sphere: that sphere (a centre at the
    origin gives exactly (0, 0, 0), its radius foot_depth's); otherwise (mesh, box, cylinder, no
    geometry) a sphere about the origin, radius foot_depth."""
    depth, geom, T = _lowest(urdf_path, foot, base, package_dirs)
    if geom is None or geom.tag != "sphere":
        return np.zeros(3), depth
    centre = np.asarray(T[:3, 3], dtype=float)
    return (np.zeros(3) if not centre.any() else centre.copy()), float(geom.get("radius"))
