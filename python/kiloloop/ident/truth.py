"""Hidden-parameter robot files: a "true" robot that differs from its nominal file in the ways
identification must find (joint friction and armature scaled, a payload on the arm's last link,
an actuation delay, rotors' thrust scaled). The acceptance bench and the tests excite the true
file and identify against the nominal one, which never sees this module's numbers."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .patch import robot_data, set_delay, set_joints, write

# A UR5 with joints as a real one has (the orders of magnitude its robot file's comment gives for
# harmonic-drive joints): the nominal file of the arm's acceptance, whose friction and armature
# the true plants scale.
UR5_JOINTS = {"sim.joints.damping": [5.0, 5.0, 3.0, 1.0, 1.0, 1.0],
              "sim.joints.frictionloss": [8.0, 8.0, 5.0, 1.5, 1.5, 1.5],
              "sim.joints.armature": [0.4, 0.4, 0.2, 0.05, 0.05, 0.05]}


@dataclass(frozen=True)
class Hidden:
    friction_scale: float = 1.0     # joint damping and frictionloss x
    armature_scale: float = 1.0     # joint armature x
    payload_fraction: float = 0.0   # an arm's last link made heavier by this share (all of its
    #                                 inertia scaled: a payload at the link's own CoM)
    delay: float | None = None      # [s] the actuation delay (None: the nominal file's)
    thrust_scale: float = 1.0       # a multirotor's rotors: thrust per command x ([sim.rotors]
    #                                 efficiency: the plant's, the controller does not read it)


def nominal_joints(robot) -> tuple[np.ndarray, ...]:
    """(damping, frictionloss, armature) per chain joint of the robot's plant."""
    if robot.kind == "arm":
        from ..sil.arm_family import build_plant

        p = build_plant(robot)
        dofs = p.dof_addresses
    else:
        from ..sil.aerial_plant import AerialPlant

        p = AerialPlant.from_robot(robot)
        dofs = p._dadr
    m = p.model
    return m.dof_damping[dofs].copy(), m.dof_frictionloss[dofs].copy(), m.dof_armature[dofs].copy()


def write_true_robot(robot, hidden: Hidden, out_dir) -> Path:
    """The true robot file (and URDF, with a payload) in out_dir; returns the robot file."""
    out_dir = Path(out_dir)
    out = out_dir / "robot.toml"
    data = robot_data(robot, out)
    if hidden.friction_scale != 1.0 or hidden.armature_scale != 1.0:
        damping, friction, armature = nominal_joints(robot)
        set_joints(data, damping * hidden.friction_scale, friction * hidden.friction_scale,
                   armature * hidden.armature_scale)
    if hidden.delay is not None:
        set_delay(data, robot.kind, hidden.delay)
    if hidden.payload_fraction > 0:
        from .payload_urdf import chain_last_link, link_inertial, write_with_payload

        link = chain_last_link(robot.urdf, robot.model().joint_names[-1])
        mass, com, inertia = link_inertial(robot.urdf, link)
        f = hidden.payload_fraction
        write_with_payload(robot.urdf, out_dir / "true.urdf", link, f * mass, com, f * inertia)
        data["urdf"] = "true.urdf"
    if hidden.thrust_scale != 1.0:
        rotors = data.setdefault("sim", {}).setdefault("rotors", {})
        n = len(data["rotors"])
        efficiency = rotors.get("efficiency") or [1.0] * n
        rotors["efficiency"] = [float(e) * hidden.thrust_scale for e in efficiency]
    return write(data, out, [f"A true robot with hidden parameters: {hidden}"])


def true_payload(robot, hidden: Hidden) -> tuple[float, np.ndarray]:
    """(mass [kg], CoM (3) [m] in the last link's frame) of the hidden payload."""
    from .payload_urdf import chain_last_link, link_inertial

    link = chain_last_link(robot.urdf, robot.model().joint_names[-1])
    mass, com, _ = link_inertial(robot.urdf, link)
    return hidden.payload_fraction * mass, com
