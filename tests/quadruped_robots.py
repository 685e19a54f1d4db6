"""Quadruped robot files for the tests: minimal ones (only name, kind, urdf, package_dirs, [legs])
for example-robot-data's Go1, a generated light (~2.5 kg) quadruped whose knees sit off the
hip pitch axis (offsets along it) and bend forward, and a generated 27 kg one whose knees bend
forward with limits [0, pi]."""
from __future__ import annotations

from pathlib import Path

import numpy as np

FEET = ["FL_foot", "FR_foot", "RL_foot", "RR_foot"]


def erd_share() -> Path | None:
    """example-robot-data's share directory (the package:// root), None when not installed."""
    try:
        import example_robot_data  # noqa: F401
    except ImportError:
        pass
    import sys

    for base in map(Path, sys.path):
        p = base / "cmeel.prefix" / "share"
        if (p / "example-robot-data" / "robots").is_dir():
            return p
    return None


def minimal_robot_file(directory: Path, name: str, urdf: Path, package_dirs=(), base="trunk",
                       feet=FEET) -> Path:
    path = Path(directory) / f"{name}.toml"
    dirs = ", ".join(f'"{d}"' for d in package_dirs)
    feet_list = ", ".join(f'"{f}"' for f in feet)
    path.write_text(f'name = "{name}"\nkind = "quadruped"\nurdf = "{urdf}"\npackage_dirs = [{dirs}]\n'
                    f'[legs]\nbase = "{base}"\nfeet = [{feet_list}]\n')
    return path


def go1_robot_file(directory: Path) -> Path | None:
    share = erd_share()
    if share is None:
        return None
    urdf = share / "example-robot-data" / "robots" / "go1_description" / "urdf" / "go1.urdf"
    return minimal_robot_file(directory, "go1", urdf, [share])


def _box(m, x, y, z):
    return (m / 12 * (y * y + z * z), m / 12 * (x * x + z * z), m / 12 * (x * x + y * y))


def _link(name, mass, com, inertia, collision=""):
    ix, iy, iz = inertia
    return (f'  <link name="{name}">\n    <inertial><origin xyz="{com[0]} {com[1]} {com[2]}"/>'
            f'<mass value="{mass}"/><inertia ixx="{ix:.6g}" iyy="{iy:.6g}" izz="{iz:.6g}" '
            f'ixy="0" ixz="0" iyz="0"/></inertial>\n{collision}  </link>\n')


def _joint(name, parent, child, xyz, axis, lower, upper, effort=3.0):
    return (f'  <joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz[0]} {xyz[1]} {xyz[2]}"/><axis xyz="{axis}"/>'
            f'<limit lower="{lower}" upper="{upper}" effort="{effort}" velocity="25"/></joint>\n')


def light_quadruped_urdf(path: Path, knee_offset: float = 0.015, forward_knees=True) -> Path:
    """A 2.5 kg quadruped: 1.6 kg trunk, 0.14 m thigh and shank; each knee joint sits
    `knee_offset` outboard of the thigh along the hip pitch axis; knees bend forward."""
    L = 0.14
    out = ['<?xml version="1.0"?>\n<robot name="light_dog">\n']
    out.append(_link("trunk", 1.6, (0, 0, 0), _box(1.6, 0.30, 0.15, 0.06),
                     '    <collision><geometry><box size="0.30 0.15 0.06"/></geometry></collision>\n'))
    knee_lo, knee_hi = (0.2, 2.6) if forward_knees else (-2.6, -0.2)
    for leg, sx, sy in (("FL", 1, 1), ("FR", 1, -1), ("RL", -1, 1), ("RR", -1, -1)):
        out.append(_joint(f"{leg}_abd", "trunk", f"{leg}_hip", (sx * 0.13, sy * 0.06, 0), "1 0 0",
                          -0.8, 0.8))
        out.append(_link(f"{leg}_hip", 0.06, (0, sy * 0.015, 0), _box(0.06, 0.04, 0.03, 0.04)))
        out.append(_joint(f"{leg}_pitch", f"{leg}_hip", f"{leg}_thigh", (0, sy * 0.03, 0), "0 1 0",
                          -2.5, 2.5))
        out.append(_link(f"{leg}_thigh", 0.12, (0, 0, -L / 2), _box(0.12, 0.02, 0.02, L)))
        out.append(_joint(f"{leg}_knee", f"{leg}_thigh", f"{leg}_shank",
                          (0, sy * knee_offset, -L), "0 1 0", knee_lo, knee_hi))
        out.append(_link(f"{leg}_shank", 0.05, (0, 0, -L / 2), _box(0.05, 0.012, 0.012, L)))
        out.append(f'  <joint name="{leg}_foot_fixed" type="fixed"><parent link="{leg}_shank"/>'
                   f'<child link="{leg}_foot"/><origin xyz="0 0 {-L}"/></joint>\n')
        out.append(_link(f"{leg}_foot", 0.01, (0, 0, 0), (2e-7, 2e-7, 2e-7),
                         '    <collision><geometry><sphere radius="0.012"/></geometry></collision>\n'))
    out.append("</robot>\n")
    Path(path).write_text("".join(out))
    return Path(path)


def forward_knee_quadruped_urdf(path: Path, foot_ahead: float = 0.01, hip_lower: float = -2.5) -> Path:
    """A 27 kg quadruped whose knees bend forward, knee limits [0, pi] as a flipped Unitree-style
    URDF writes them: 13 kg trunk, 0.25 m thigh and shank; each foot sits `foot_ahead` [m] in
    front of its shank's line, so the knee limits also allow a sliver of backward bend (0.04
    rad: too little to stand on); the hip pitch's lower limit is `hip_lower` [rad]."""
    L = 0.25
    out = ['<?xml version="1.0"?>\n<robot name="forward_knee_dog">\n']
    out.append(_link("trunk", 13.0, (0, 0, 0), _box(13.0, 0.60, 0.30, 0.15),
                     '    <collision><geometry><box size="0.60 0.30 0.15"/></geometry></collision>\n'))
    for leg, sx, sy in (("FL", 1, 1), ("FR", 1, -1), ("RL", -1, 1), ("RR", -1, -1)):
        out.append(_joint(f"{leg}_abd", "trunk", f"{leg}_hip", (sx * 0.25, sy * 0.08, 0), "1 0 0",
                          -0.8, 0.8, effort=40.0))
        out.append(_link(f"{leg}_hip", 1.0, (0, sy * 0.04, 0), _box(1.0, 0.08, 0.06, 0.08)))
        out.append(_joint(f"{leg}_pitch", f"{leg}_hip", f"{leg}_thigh", (0, sy * 0.08, 0), "0 1 0",
                          hip_lower, 2.5, effort=60.0))
        out.append(_link(f"{leg}_thigh", 1.9, (0, 0, -L / 2), _box(1.9, 0.04, 0.04, L)))
        out.append(_joint(f"{leg}_knee", f"{leg}_thigh", f"{leg}_shank", (0, 0, -L), "0 1 0",
                          0.0, 3.14159, effort=60.0))
        out.append(_link(f"{leg}_shank", 0.5, (0, 0, -L / 2), _box(0.5, 0.02, 0.02, L)))
        out.append(f'  <joint name="{leg}_foot_fixed" type="fixed"><parent link="{leg}_shank"/>'
                   f'<child link="{leg}_foot"/><origin xyz="{foot_ahead} 0 {-L}"/></joint>\n')
        out.append(_link(f"{leg}_foot", 0.05, (0, 0, 0), (5e-6, 5e-6, 5e-6),
                         '    <collision><geometry><sphere radius="0.02"/></geometry></collision>\n'))
    out.append("</robot>\n")
    Path(path).write_text("".join(out))
    return Path(path)


def pinocchio_com_and_inertia(urdf: Path, q_by_name: dict, base: str):
    """Oracle: the whole robot's CoM and composite inertia about it (base frame) from Pinocchio,
    with the base fixed at the identity and the joints at q_by_name."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(urdf), pin.JointModelFreeFlyer())
    data = model.createData()
    q = pin.neutral(model)  # free flyer at the identity: world = root link
    for name, value in q_by_name.items():
        j = model.getJointId(name)
        q[model.joints[j].idx_q] = value
    pin.forwardKinematics(model, data, q)
    pin.ccrba(model, data, q, np.zeros(model.nv))
    # Composite inertia of the whole robot (everything below the free flyer), root frame.
    Y = data.oYcrb[1]
    com = Y.lever
    I_com = Y.inertia  # about the CoM
    frame = model.getFrameId(base)
    pin.updateFramePlacements(model, data)
    T = data.oMf[frame]
    R = T.rotation
    return R.T @ (com - T.translation), R.T @ I_com @ R, Y.mass
