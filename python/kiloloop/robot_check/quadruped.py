"""`kiloloop robot check` on a quadruped: what the controller derived at configure (mass, CoM,
inertia, stand height and pose, gains) and the plant built from the robot file."""
from __future__ import annotations

import numpy as np

from .. import _core
from ..robot.quadruped import controller_config, plant_overlay
from ..sil.floating_plant import FloatingBasePlant


def summary(robot, model) -> list[str]:
    """Lines for `kiloloop robot check`: the controller's derived settings and the plant."""
    config = controller_config(robot)
    ctrl = _core.QuadrupedController(model, config)
    d = ctrl.config
    plant = FloatingBasePlant(robot.urdf_doc, plant_overlay(robot, ctrl), package_dirs=robot.package_dirs)
    inertia = np.asarray(ctrl.inertia)
    fmt = lambda v: ", ".join(f"{x:.4g}" for x in np.asarray(v).ravel())  # noqa: E731
    knees = ", ".join(str(k).split(".")[-1].lower() for k in d.knees)
    # Derived (not set by the file): at what extension, moved off the default where the limits forbid it.
    extension = ("" if robot.section("controller").get("body_height") else
                 f" (feet {d.stand_extension:.2f} of the leg below the hips)")
    return [
        f"  plant: {plant.model.nbody - 1} bodies, {plant.nq} actuated joints, "
        f"feet {', '.join(plant.feet)} (order checked against the hips)",
        f"  mass {d.mass:.3f} kg; CoM standing {fmt(ctrl.com)} m (trunk frame)",
        f"  composite inertia about the CoM [kg m^2]: diag {fmt(np.diag(inertia))}",
        f"  stand height {d.body_height:.4f} m{extension}; foot radius {d.foot_radius:.4f} m about "
        f"({fmt(d.foot_offset)}) m in the foot frame; knees {knees}",
        f"  stand pose [rad] {fmt(ctrl.stand_pose)}",
        f"  plant start height {plant.base_pos0[2]:.4f} m",
        f"  swing kp {fmt(d.swing_kp)} N m/rad, kd {fmt(d.swing_kd)} N m s/rad "
        f"(actuation delay {d.actuation_delay * 1e3:.1f} ms)",
        f"  contact on/off {d.contact.force_on:.1f}/{d.contact.force_off:.1f} N; "
        f"fz {d.force.fz_min:.1f}..{d.force.fz_max:.1f} N; swing height {d.swing_height:.3f} m; "
        f"Raibert gain {d.raibert_gain:.3f} s",
    ]
