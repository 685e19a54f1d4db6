"""Link inertias MuJoCo refuses, found and named on the URDF before any model is built from it.

MuJoCo refuses a body whose principal moments A <= B <= C [kg m^2] are not all positive (a rod,
a dummy link: "inertia must have positive eigenvalues") or break A + B >= C, which no rigid body
does ("inertia must satisfy A + B >= C; use 'balanceinertia' to fix"), naming neither the URDF's
link nor what the user can do. Here each link with mass is checked and, where it fails, repaired
in the URDF that both the controller's model and the plant read (robot/urdf_doc.py), so that
the two agree. The repair: moments not positive are raised to those of a 1 mm sphere of the
link's mass (0.4 m r^2), and where A + B < C the three move to the nearest inertia that
satisfies it: A and B up and C down by (C - A - B) / 3 each (the least change in every moment;
MuJoCo's own balanceinertia sets all three to their mean, a larger change). It is made
- without asking where it changes no moment by more than a 1 mm sphere of the whole robot's mass
  would have (0.4 M r^2: rounding in the file's digits, dummy links such as Go1's 1e-6 kg root);
- else, on a link fixed to its parent, not at all: the link gives its mass, CoM and inertia to
  the parent, the same rigid body exactly (robot/inertia_merge.py; ANYmal C's cameras and
  hatch), and the composite is checked in turn;
- else only with the robot file's `balance_inertia = true`; without it the link is refused with
  the inequality, its numbers and the fix.
A negative moment (a tensor that is not positive semi-definite) is one more moment not positive,
under the same three rules: a dummy link's junk (tiago's 1 mg antennas, whose products of inertia
exceed their moments) is repaired without asking; a real link's is refused, or balanced on
request. An all-zero inertia is MuJoCo's "none given" and left alone, except on a link that moves
(a joint of its own): a point mass there is raised like the rest. Links without mass are left
alone too (MuJoCo welds them; sil/mujoco_refusal.py names one that moves), and so are non-finite
numbers and negative masses: the C++ loader refuses those, naming the link
(cpp/urdf/urdf_checks.cpp).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from .inertia_merge import merge_into_parent

# Joint types whose child link moves on its own (MuJoCo gives it a joint).
MOVABLE = ("revolute", "continuous", "prismatic", "floating", "planar")
# [m] the radius of the sphere whose moments bound what is repaired without asking (module doc).
NEGLIGIBLE_RADIUS = 1e-3
# [kg m^2] the smallest principal moment MuJoCo's compiler takes as positive (MuJoCo 4.0,
# measured: 9e-15 refused, 1e-14 taken; robot/ imports no MuJoCo, so it is written here).
MJ_POSITIVE = 1e-14
# A negative moment within this fraction of the largest entry is rounding, as the C++ loader
# tolerates it (urdf_checks.cpp); beyond it the C++ loader refuses the link.
ROUNDING = 1e-9
# The repaired A + B exceed C by three times this fraction of C: MuJoCo recomputes the principal
# moments from the tensor written back, and must not find them a rounding error short of it.
MARGIN = 1e-9
_KEYS = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")


@dataclass(frozen=True)
class InertiaFix:
    """One link's inertia as the file gives it and as repaired (principal moments, ascending)."""
    link: str
    mass: float            # [kg]
    before: np.ndarray     # (3,) [kg m^2]
    after: np.ndarray      # (3,) [kg m^2]
    tensor: np.ndarray     # (3, 3) [kg m^2] the repaired tensor, in the file's inertial frame
    triangle: bool         # A + B < C (after raising moments that were not positive)
    change: float          # [kg m^2] the largest change of a principal moment

    def inequality(self) -> str:
        """The violated inequality with its numbers (the file's moments)."""
        a, b, c = self.before
        out = [f"smallest principal moment {_g(a)} kg m^2 not positive"] if a < MJ_POSITIVE else []
        if self.triangle:
            out.append(f"A + B >= C broken: {_g(a)} + {_g(b)} = {_g(a + b)} < {_g(c)}")
        return ", ".join(out)


def _g(x: float) -> str:
    return f"{x:.4g}"


def _moments(v) -> str:
    return "[" + ", ".join(_g(x) for x in v) + "]"


def _tensor(inertia: ET.Element) -> np.ndarray | None:
    """(3, 3) from <inertia>, None when an entry is missing or not a finite number (the C++
    loader's refusal)."""
    try:
        ixx, iyy, izz, ixy, ixz, iyz = (float(inertia.get(k)) for k in _KEYS)
    except (TypeError, ValueError):
        return None
    t = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    return t if np.all(np.isfinite(t)) else None


def _mass(inertial: ET.Element) -> float | None:
    mass = inertial.find("mass")
    try:
        m = float(mass.get("value")) if mass is not None else None
    except (TypeError, ValueError):
        return None
    return m if m is not None and np.isfinite(m) else None


def total_mass(root: ET.Element) -> float:
    """[kg] the sum of every link's finite, positive <mass>."""
    masses = (_mass(i) for i in root.findall("link/inertial"))
    return float(sum(m for m in masses if m is not None and m > 0))


def needed_fix(link: str, mass: float, tensor: np.ndarray) -> InertiaFix | None:
    """The repair MuJoCo's compiler needs (module doc), None when it takes the tensor as is."""
    w, V = np.linalg.eigh(tensor)
    raised = np.maximum(w, max(0.4 * mass * NEGLIGIBLE_RADIUS ** 2, 10 * MJ_POSITIVE)) \
        if w[0] < MJ_POSITIVE else w.copy()
    triangle = raised[0] + raised[1] < raised[2]
    if not triangle and w[0] >= MJ_POSITIVE:
        return None
    after = raised.copy()
    if triangle:
        t = (raised[2] - raised[0] - raised[1]) / 3.0 + MARGIN * raised[2]
        after += np.array([t, t, -t])
    return InertiaFix(link=link, mass=mass, before=w, after=after,
                      tensor=V @ np.diag(after) @ V.T, triangle=triangle,
                      change=float(np.max(np.abs(after - w))))


def fixes(root: ET.Element, moving: set[str]) -> list[InertiaFix]:
    """Every link's needed repair, document order. `moving`: the links below a movable joint (a
    zero inertia, which MuJoCo reads as "none given", needs one there only)."""
    out = []
    for link in root.findall("link"):
        inertial = link.find("inertial")
        inertia = inertial.find("inertia") if inertial is not None else None
        mass = _mass(inertial) if inertial is not None else None
        tensor = _tensor(inertia) if inertia is not None else None
        if mass is None or mass <= 0 or tensor is None:
            continue
        if not np.any(tensor) and link.get("name") not in moving:
            continue
        fix = needed_fix(link.get("name"), mass, tensor)
        if fix is not None:
            out.append(fix)
    return out


def refusal(fix: InertiaFix) -> str:
    """One line: the link, the violated inequality with its numbers, and the two fixes."""
    return (f"link '{fix.link}': principal moments {_moments(fix.before)} kg m^2: "
            f"{fix.inequality()}; no rigid body has them and MuJoCo refuses them. Correct the "
            f"URDF's <inertia>, or set `balance_inertia = true` in the robot file (moments "
            f"{_moments(fix.after)} kg m^2, each moved by at most {_g(fix.change)} kg m^2, in the plant "
            f"and the controller's model alike)")


def describe(fix: InertiaFix, requested: bool) -> str:
    """One line naming the link, its moments before and after, and why."""
    why = "balance_inertia" if requested else (
        f"without asking: within a {NEGLIGIBLE_RADIUS * 1e3:g} mm sphere of the robot's mass")
    return (f"link '{fix.link}' ({_g(fix.mass)} kg): inertia repaired ({why}): {fix.inequality()}; "
            f"principal moments {_moments(fix.before)} -> {_moments(fix.after)} kg m^2 (largest "
            f"change {_g(fix.change)} kg m^2)")


def write(link: ET.Element, tensor: np.ndarray) -> None:
    """The tensor into the link's <inertia> (repr: exactly the doubles computed)."""
    inertia = link.find("inertial/inertia")
    for key, (i, j) in zip(_KEYS, ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
        inertia.set(key, repr(float(tensor[i, j])))


def repair(root: ET.Element, balance: bool) -> tuple[list[str], list[str], list[InertiaFix]]:
    """Repairs `root` in place (module doc). Returns (every repair made, one line each; those
    made only because `balance` asked; the fixes refused: needed, not negligible, `balance`
    false)."""
    negligible = 0.4 * total_mass(root) * NEGLIGIBLE_RADIUS ** 2
    links = {link.get("name"): link for link in root.findall("link")}
    above = {j.find("child").get("link"): j for j in root.findall("joint")
             if j.find("child") is not None and j.find("parent") is not None}
    moving = {name for name, j in above.items() if j.get("type") in MOVABLE}
    made, requested, refused = [], [], []

    def depth(link: str) -> int:
        n = 0
        while link in above and n <= len(above):  # bounded: a loop is the C++ loader's refusal
            link, n = above[link].find("parent").get("link"), n + 1
        return n

    # Links fixed to a parent: what is more than negligible moves into the parent, exactly; the
    # composite may need the same again one link up.
    for _ in range(len(links)):  # each link moves once at most (in a tree)
        pending = [f for f in fixes(root, moving) if f.change > negligible and f.link in above
                   and above[f.link].get("type") == "fixed"
                   and above[f.link].find("parent").get("link") in links]
        if not pending:
            break
        fix = max(pending, key=lambda f: depth(f.link))  # leaves first: each link moves once
        joint = above[fix.link]
        parent = joint.find("parent").get("link")
        merge_into_parent(links[fix.link], joint, links[parent])
        made.append(f"link '{fix.link}' ({_g(fix.mass)} kg): {fix.inequality()}; its inertial "
                    f"moved into its parent '{parent}' (fixed joint '{joint.get('name')}': the "
                    f"same rigid body, exactly)")
    for fix in fixes(root, moving):
        small = fix.change <= negligible
        if not small and not balance:
            refused.append(fix)
            continue
        write(links[fix.link], fix.tensor)
        made.append(describe(fix, requested=not small))
        if not small:
            requested.append(made[-1])
    return made, requested, refused
