"""Meshes of real robot descriptions: where a URDF's mesh URI points, reading the mesh, and the
conservative primitives that stand in for it where a mesh cannot be used (the planner's link
capsules; MuJoCo, which cannot read COLLADA).

    path = resolve_uri("package://ur_description/meshes/ur10/collision/base.stl", urdf_dir, package_dirs)
    mesh = load_mesh(path, scale=1.0)            # any format trimesh reads: .stl .obj .dae .ply ...
    p0, p1, radius = fit_capsule(mesh)           # every vertex inside, in the mesh frame [m]
    center, half_extents = fit_box(mesh)         # axis-aligned in the mesh frame [m]
    caps = capsules_for_urdf(urdf_path, package_dirs)   # {link: [(a, b, radius)]} in link frames
    kl.capsules_from_urdf(urdf_path, model, mesh_capsules=caps)

URIs follow the ROS / Pinocchio rule: ``package://NAME/rest`` is ``DIR/NAME/rest`` for the first DIR
in ``package_dirs`` that has it; ``file://`` and plain paths are relative to the URDF's directory
unless absolute.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Iterable, Sequence
from urllib.parse import unquote

import numpy as np

from .errors import InputError

__all__ = ["resolve_uri", "load_mesh", "fit_capsule", "fit_box", "capsules_for_urdf", "mesh_collisions"]


def resolve_uri(uri: str, urdf_dir: str | Path | None = None, package_dirs: Iterable[str | Path] = ()) -> Path:
    """The file a URDF mesh URI names. ValueError naming the package and the directories searched
    when a ``package://`` URI is found in none of them, or naming the path for a missing file."""
    uri = uri.strip()
    base = Path(urdf_dir) if urdf_dir is not None else Path.cwd()
    if uri.startswith("package://"):
        rest = uri[len("package://"):]
        name, _, sub = rest.partition("/")
        if not name or not sub:
            raise InputError(f"mesh URI '{uri}': expected package://NAME/path")
        dirs = [Path(d) for d in package_dirs]
        for d in dirs:
            candidate = d / name / sub
            if candidate.is_file():
                return candidate
        searched = ", ".join(f"'{d}'" for d in dirs) if dirs else "none (package_dirs is empty)"
        raise InputError(f"mesh URI '{uri}': package '{name}' not found (no {name}/{sub} in package_dirs: "
                         f"{searched})")
    if uri.startswith("file://"):
        path = Path(unquote(uri[len("file://"):]))
    else:
        path = Path(uri)
    if not path.is_absolute():
        path = base / path
    if not path.is_file():
        raise InputError(f"mesh URI '{uri}': file '{path}' not found")
    return path


def load_mesh(path: str | Path, scale: float | Sequence[float] = 1.0):
    """One triangle mesh (trimesh.Trimesh) in the file's frame, scaled per axis, from any format
    trimesh reads (COLLADA through pycollada; a scene's parts are placed and merged). A COLLADA
    file's <unit meter> is applied, as ROS and MuJoCo's converters do."""
    import trimesh

    path = Path(path)
    loaded = trimesh.load(str(path), force="mesh", process=False)
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.vertices) == 0:
        raise InputError(f"mesh '{path}': no triangles could be read")
    mesh = loaded.copy()
    factor = np.ones(3) * _collada_unit(path)
    factor = factor * np.broadcast_to(np.asarray(scale, dtype=float), (3,))
    if not np.all(factor == 1.0):
        mesh.apply_transform(np.diag([*factor, 1.0]))
    return mesh


def _collada_unit(path: Path) -> float:
    """Metres per unit of a .dae file's <asset><unit meter=...> (1 for other formats). trimesh
    reads COLLADA geometry in file units and only records the unit in its metadata. (<up_axis> is
    left alone, as ROS does.)"""
    if path.suffix.lower() != ".dae":
        return 1.0
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError:
        return 1.0
    for asset in root:
        if not asset.tag.endswith("asset"):
            continue
        for el in asset:
            if el.tag.endswith("unit") and "meter" in el.attrib:
                return float(el.attrib["meter"])
    return 1.0


def _vertices(points_or_mesh) -> np.ndarray:
    v = getattr(points_or_mesh, "vertices", points_or_mesh)
    v = np.asarray(v, dtype=float).reshape(-1, 3)
    if len(v) == 0 or not np.all(np.isfinite(v)):
        raise ValueError("fit: expected a non-empty set of finite 3-D points")
    return v


def _capsule_about(v: np.ndarray, axis: np.ndarray, center: np.ndarray):
    """The thinnest capsule with this axis line (through `center`) holding every point: radius the
    largest distance from the line, ends as close together as the caps allow."""
    d = v - center
    t = d @ axis
    rho2 = np.maximum(np.einsum("ij,ij->i", d, d) - t * t, 0.0)
    r = math.sqrt(float(rho2.max()))
    s = np.sqrt(np.maximum(r * r - rho2, 0.0))
    t_hi = float(np.max(t - s))  # each end reaches far enough that every point is in its cap
    t_lo = float(np.min(t + s))
    if t_lo > t_hi:  # short: a sphere between them holds everything
        t_lo = t_hi = 0.5 * (t_lo + t_hi)
    # The extreme points lie exactly on the surface: a hair of slack [m] keeps the bound true
    # through floating-point rounding.
    return center + t_lo * axis, center + t_hi * axis, r * (1.0 + 1e-9) + 1e-12


def fit_capsule(points_or_mesh):
    """(p0, p1, radius): a capsule (segment p0-p1 swept by a sphere of that radius) holding every
    vertex, in the mesh frame [m]. The axis is the points' principal direction (the other two
    principal directions are tried as well; the smallest volume wins)."""
    v = _vertices(points_or_mesh)
    mean = v.mean(axis=0)
    _, vecs = np.linalg.eigh(np.cov((v - mean).T) if len(v) > 1 else np.eye(3))
    best = None
    for k in (2, 1, 0):
        axis = vecs[:, k] / np.linalg.norm(vecs[:, k])
        # The line through the middle of the points' extent across the axis, or their mean.
        e1, e2 = vecs[:, (k + 1) % 3], vecs[:, (k + 2) % 3]
        u1, u2 = (v - mean) @ e1, (v - mean) @ e2
        mid = mean + 0.5 * (u1.max() + u1.min()) * e1 + 0.5 * (u2.max() + u2.min()) * e2
        for center in (mid, mean):
            p0, p1, r = _capsule_about(v, axis, center)
            volume = math.pi * r * r * float(np.linalg.norm(p1 - p0)) + 4.0 / 3.0 * math.pi * r ** 3
            if best is None or volume < best[0]:
                best = (volume, p0, p1, r)
    _, p0, p1, r = best
    return np.asarray(p0), np.asarray(p1), float(r)


def fit_box(points_or_mesh):
    """(center, half_extents): the axis-aligned box of the vertices in the mesh frame [m]."""
    v = _vertices(points_or_mesh)
    lo, hi = v.min(axis=0), v.max(axis=0)
    return 0.5 * (lo + hi), 0.5 * (hi - lo)


def _origin(el) -> np.ndarray:
    """4x4 transform of a URDF <origin> (xyz, rpy = fixed-axis roll-pitch-yaw)."""
    T = np.eye(4)
    if el is None:
        return T
    xyz = [float(x) for x in el.get("xyz", "0 0 0").split()]
    r, p, y = [float(x) for x in el.get("rpy", "0 0 0").split()]
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    T[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]]
    T[:3, 3] = xyz
    return T


def _read_urdf(urdf_path_or_xml, urdf_dir):
    text = str(urdf_path_or_xml)
    if text.lstrip().startswith("<"):
        return ET.fromstring(text), Path(urdf_dir) if urdf_dir is not None else Path.cwd()
    path = Path(text)
    if not path.is_file():
        raise InputError(f"URDF file '{path}' not found")
    return ET.parse(path).getroot(), Path(urdf_dir) if urdf_dir is not None else path.parent


def mesh_collisions(urdf_path_or_xml, package_dirs: Iterable[str | Path] = (), urdf_dir=None):
    """[(link, T_link_mesh (4, 4), mesh path, scale (3,))] for every <collision> that is a mesh."""
    root, base = _read_urdf(urdf_path_or_xml, urdf_dir)
    package_dirs = list(package_dirs)
    out = []
    for link in root.findall("link"):
        for col in link.findall("collision"):
            mesh = col.find("geometry/mesh")
            if mesh is None:
                continue
            scale = np.array([float(x) for x in mesh.get("scale", "1 1 1").split()])
            path = resolve_uri(mesh.get("filename", ""), base, package_dirs)
            out.append((link.get("name"), _origin(col.find("origin")), path, scale))
    return out


def capsules_for_urdf(urdf_path_or_xml, package_dirs: Iterable[str | Path] = (), urdf_dir=None):
    """{link: [(a, b, radius)]}: one capsule per mesh <collision>, fitted to the mesh's vertices
    (scale and <origin> applied), in the link frame [m]. For kl.capsules_from_urdf(...,
    mesh_capsules=...). Links whose collisions are primitives are not listed (C++ bounds those)."""
    caps: dict[str, list] = {}
    cache: dict[tuple, tuple] = {}
    for link, T, path, scale in mesh_collisions(urdf_path_or_xml, package_dirs, urdf_dir):
        key = (str(path), tuple(scale))
        if key not in cache:
            cache[key] = fit_capsule(load_mesh(path, scale))
        p0, p1, r = cache[key]
        a = T[:3, :3] @ p0 + T[:3, 3]
        b = T[:3, :3] @ p1 + T[:3, 3]
        caps.setdefault(link, []).append((a, b, r))
    return caps
