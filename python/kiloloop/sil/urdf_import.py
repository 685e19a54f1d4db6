"""Real URDFs into MuJoCo: what the plants do before MjSpec sees a user's description.

- mesh URIs (package://, relative, file://) become absolute paths (ROS/Pinocchio package rule);
- meshes MuJoCo cannot read (.dae and other formats) are replaced by a box fitted to the mesh
  (read with trimesh), or dropped with a note naming the link when they cannot be read at all;
- visual geometry is discarded unless a camera will look at it (--video);
- joints that the controller does not drive are welded at the configuration the robot file gives
  (default 0), so the plant carries the same rigid mass as the controller's folded model.
Every change is recorded as a one-line note (`kiloloop robot check` prints them).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

from ..errors import InputError
from ..robot.urdf_doc import UrdfDoc, tree

# Mesh formats MuJoCo's compiler reads itself.
MUJOCO_MESH_FORMATS = (".stl", ".obj", ".msh")
MOVABLE = ("revolute", "continuous", "prismatic")


def _resolve(uri: str, urdf_dir: Path, package_dirs) -> Path | None:
    """The mesh file, or None when the file is missing (a package that no package_dirs entry has
    is an error: the robot file is wrong, not the mesh)."""
    from ..meshes import resolve_uri

    try:
        return resolve_uri(uri, urdf_dir, package_dirs)
    except ValueError as e:
        if "package '" in str(e):
            raise
        return None


def _fit_box(path: Path, scale) -> tuple[np.ndarray, np.ndarray]:
    """(centre, half extents) [m] of the mesh's axis-aligned box in the mesh frame, scaled (the
    mesh read by kiloloop.meshes: trimesh, COLLADA units applied)."""
    from ..meshes import fit_box, load_mesh

    centre, half = fit_box(load_mesh(path, scale))
    return np.asarray(centre, dtype=float), np.maximum(np.asarray(half, dtype=float), 1e-4)


def rpy_matrix(rpy) -> np.ndarray:
    """(3, 3) rotation of URDF roll, pitch, yaw [rad]: about fixed x, then y, then z."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def _floats(text, n, default):
    return np.array([float(v) for v in text.split()]) if text else np.full(n, default)


def prepare_urdf(doc: UrdfDoc, package_dirs=(), *, visual: bool = False) -> tuple[str, list[str]]:
    """The URDF text ready for MjSpec.from_string, and notes on what was changed. `doc`: the URDF
    as every model of the robot reads it (robot/urdf_doc.py: limits and inertias repaired)."""
    urdf_path = doc.path
    root = tree(doc)
    notes: list[str] = []
    for link in root.findall("link"):
        for tag in ("visual", "collision"):
            for elem in link.findall(tag):
                if tag == "visual" and not visual:
                    link.remove(elem)
                    continue
                mesh = elem.find("geometry/mesh")
                if mesh is None or mesh.get("filename") is None:
                    continue
                uri = mesh.get("filename")
                path = _resolve(uri, urdf_path.parent, package_dirs)
                if path is None:
                    link.remove(elem)
                    notes.append(f"link '{link.get('name')}': {tag} mesh {uri} dropped (file not "
                                 f"found)")
                    continue
                if path.suffix.lower() in MUJOCO_MESH_FORMATS:
                    mesh.set("filename", str(path))
                    continue
                scale = _floats(mesh.get("scale"), 3, 1.0)
                try:
                    centre, half = _fit_box(path, scale)
                except Exception as e:  # noqa: BLE001 - any unreadable mesh is dropped, with a note
                    link.remove(elem)
                    notes.append(f"link '{link.get('name')}': {tag} mesh {path.name} dropped "
                                 f"({type(e).__name__}: {str(e)[:80]})")
                    continue
                origin = elem.find("origin")
                if origin is None:
                    origin = ET.SubElement(elem, "origin")
                xyz = _floats(origin.get("xyz"), 3, 0.0)
                rpy = _floats(origin.get("rpy"), 3, 0.0)
                origin.set("xyz", " ".join(repr(float(v)) for v in xyz + rpy_matrix(rpy) @ centre))
                origin.set("rpy", " ".join(repr(float(v)) for v in rpy))
                geometry = elem.find("geometry")
                geometry.remove(mesh)
                ET.SubElement(geometry, "box", size=" ".join(repr(float(2 * h)) for h in half))
                notes.append(f"link '{link.get('name')}': {tag} mesh {path.name} "
                             f"({path.suffix} is not read by MuJoCo) replaced by a fitted box "
                             f"{np.round(2 * half, 3).tolist()} m")
    # Compiler settings MuJoCo reads from the URDF's <mujoco> element.
    for old in root.findall("mujoco"):
        root.remove(old)
    ext = ET.SubElement(root, "mujoco")
    ET.SubElement(ext, "compiler", strippath="false", fusestatic="false",
                  discardvisual="false" if visual else "true")
    return ET.tostring(root, encoding="unicode"), notes


def urdf_joints(urdf_path: Path) -> list[tuple[str, str]]:
    """(name, type) of every joint, document order (direct children: not <transmission>'s)."""
    return [(j.get("name"), j.get("type")) for j in ET.parse(urdf_path).getroot().findall("joint")]


def _axis_angle_quat(axis, angle: float) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.asarray(axis, dtype=float), float(angle))
    return q


def weld_joints(spec, keep, locked: dict | None = None) -> list[str]:
    """Removes every joint of `spec` not named in `keep`, first moving its child body to the
    joint's locked position (revolute: rotation about the axis; prismatic: a slide), and every
    equality constraint (URDF mimic) that refers to a removed joint. Returns the removed names."""
    locked = dict(locked or {})
    keep = set(keep)
    removed = []
    for joint in list(spec.joints):
        if joint.name in keep or joint.type == mujoco.mjtJoint.mjJNT_FREE:
            continue
        body = joint.parent
        value = float(locked.pop(joint.name, 0.0))
        if value != 0.0:
            axis = np.asarray(joint.axis, dtype=float)
            if joint.type == mujoco.mjtJoint.mjJNT_HINGE:
                # The joint's anchor is body-frame joint.pos; rotate about it.
                rot = _axis_angle_quat(axis, value)
                out = np.zeros(4)
                mujoco.mju_mulQuat(out, np.asarray(body.quat, dtype=float), rot)
                anchor = np.asarray(joint.pos, dtype=float)
                R_body = np.zeros(9)
                mujoco.mju_quat2Mat(R_body, np.asarray(body.quat, dtype=float))
                R_rot = np.zeros(9)
                mujoco.mju_quat2Mat(R_rot, rot)
                shift = R_body.reshape(3, 3) @ (anchor - R_rot.reshape(3, 3) @ anchor)
                body.pos = np.asarray(body.pos, dtype=float) + shift
                body.quat = out
            elif joint.type == mujoco.mjtJoint.mjJNT_SLIDE:
                R_body = np.zeros(9)
                mujoco.mju_quat2Mat(R_body, np.asarray(body.quat, dtype=float))
                body.pos = np.asarray(body.pos, dtype=float) + R_body.reshape(3, 3) @ (axis * value)
        removed.append(joint.name)
    if locked:
        raise InputError(f"locked: no joint named {sorted(locked)[0]!r} off the chain")
    gone = set(removed)
    for eq in list(spec.equalities):
        if eq.name1 in gone or eq.name2 in gone:
            spec.delete(eq)
    for name in removed:
        spec.delete(spec.joint(name))
    return removed
