"""`kiloloop robot check` on an arm: what robot/arm.py derived, the plant (sil/arm_family.py; work
pose and reach come from its geometry, scenarios/arm_targets.py) and the controllers the
scenarios build."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..robot import arm
from ..sil.arm_family import build_plant
from ..scenarios.arm_targets import reach, work_pose


def summary(robot, model) -> list[str]:
    """Lines for `kiloloop robot check`: derived settings, the plant, the controllers."""
    q0 = arm.start_pose(robot, model)
    plant = build_plant(robot, visual=True)  # visual too: its notes say what a video shows
    qw = work_pose(robot, model, plant)
    kp, kd = arm.joint_gains(robot, model, "computed_torque", q0)
    kp_pd, _ = arm.joint_gains(robot, model, "pd_gravity", q0)
    ik = kl.ArmIk(model)
    solver = ik.solver() if hasattr(ik, "solver") else ("ur_analytic" if ik.has_analytic
                                                       else "numeric")
    why = ik.analytic_reason() if hasattr(ik, "analytic_reason") else ""
    lines = [
        "  derived:",
        f"    start pose q0 [rad]        {_fmt(q0)}",
        f"    work pose [rad]            {_fmt(qw)}",
        f"    reach [m]                  {reach(plant):.4g}",
        (f"    computed torque kp, kd     {kp[0]:.4g}, {kd[0]:.4g} (bandwidth "
         f"{arm.controller_settings(robot)['bandwidth']:.4g} rad/s)" if np.all(kp == kp[0]) else
         f"    computed torque kp         {_fmt(kp)} (bandwidth raised where friction holds "
         f"more than {arm.STICK_BAND:g} rad)"),
        f"    PD + gravity kp            {_fmt(kp_pd)}",
        f"    rotor inertia [kg m^2]     {_fmt(model.armature)}"
        + ("" if robot.section("sim").get("joints", {}).get("armature") is not None
           else " (derived where the URDF declares losses)"),
        f"    friction compensated       viscous {_fmt(arm.joint_friction(robot, model).viscous)}, "
        f"Coulomb {_fmt(arm.joint_friction(robot, model).coulomb)}",
        f"    IK solver                  {solver}" + (f" ({why})" if why else ""),
        f"  plant: {plant.model.nbody - 1} bodies, {plant.nq} actuated joints "
        f"({', '.join(plant.joint_names)}), {plant.welded} welded; mass {plant.total_mass():.4g} kg"
        f" (model {model.total_mass:.4g} kg)",
    ]
    for note in plant.notes:
        lines.append(f"    note: {note}")
    kl.ComputedTorqueController(model)
    return lines


def _fmt(x) -> str:
    return "[" + ", ".join(f"{v:.4g}" for v in np.asarray(x, dtype=float)) + "]"
