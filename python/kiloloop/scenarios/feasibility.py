"""Start checks that hold for every scenario of a family: what the robot's data say no controller
can do, refused before anything runs (errors.ScenarioRefused, one line naming the robot, the
scenario, the limit and the figures). scenarios.prepare() calls `check` for every built-in
scenario; a check here is physical and cheap (no simulation), and it only refuses what is
certainly impossible: each estimate leaves out what would make the need larger.

- quadrupeds: standing. Each joint's static torque with the weight shared by the four feet in the
  derived stand pose (trunk level, vertical foot forces m g / 4, tau = J^T f with the leg's
  Jacobian by central differences of the controller's own leg kinematics) against its effort
  limit. The legs' own weight is left out (it adds to the need). Every quadruped scenario starts
  standing.
- multirotors: hovering. The rotors' largest collective thrust (the allocation's, along the
  body's vertical with zero moments) against the weight: below it nothing flies (the aerial
  controller's own configure check, raised here as the scenario's refusal).
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError, ScenarioRefused

GRAVITY = 9.81        # [m/s^2]
STANCE_FEET = 4       # feet sharing the weight when standing
_FD_STEP = 1e-6       # [rad] central-difference step of the leg Jacobian


def check(scenario: str, robot) -> None:
    """Raises ScenarioRefused when `robot` cannot pass `scenario` for a reason its data decide."""
    if robot.kind == "quadruped":
        _refuse(scenario, robot, quadruped_stand_shortfall(robot))
    elif robot.kind == "aerial":
        _refuse(scenario, robot, aerial_hover_shortfall(robot))


def _refuse(scenario: str, robot, reason: str) -> None:
    if reason:
        raise ScenarioRefused(f"{robot.name}: {scenario} refused at start: {reason}")


def stand_torques(robot) -> tuple[list[str], np.ndarray, np.ndarray, float]:
    """(joint names, [N m] static torque each joint holds standing, [N m] its effort limit,
    [kg] mass) in the controller's joint order (legs FL, FR, RL, RR; 3 joints each)."""
    from .. import _core
    from ..robot import quadruped

    controller = _core.QuadrupedController(robot.model(), quadruped.controller_config(robot))
    stand = np.asarray(controller.stand_pose, dtype=float)
    force = np.array([0.0, 0.0, controller.mass * GRAVITY / STANCE_FEET])  # [N] on each foot
    torques = np.zeros(12)
    for leg in range(4):
        q = stand[3 * leg:3 * leg + 3]
        jacobian = np.zeros((3, 3))
        for j in range(3):
            dq = np.zeros(3)
            dq[j] = _FD_STEP
            jacobian[:, j] = (np.asarray(controller.foot_position(leg, q + dq)) -
                              np.asarray(controller.foot_position(leg, q - dq))) / (2 * _FD_STEP)
        torques[3 * leg:3 * leg + 3] = np.abs(jacobian.T @ force)
    return (list(controller.joint_names), torques,
            np.asarray(controller.effort_limit, dtype=float), float(controller.mass))


def quadruped_stand_shortfall(robot) -> str:
    """"" when every joint can hold its share of the weight standing; otherwise the reason, with
    the joint that falls shortest (needed torque over its effort limit)."""
    names, torques, limits, mass = stand_torques(robot)
    ratio = np.divide(torques, limits, out=np.full_like(torques, np.inf), where=limits > 0)
    worst = int(np.argmax(ratio))
    if ratio[worst] <= 1.0:
        return ""
    return (f"standing needs {torques[worst]:.3g} N m at {names[worst]} ({mass:.3g} kg on "
            f"{STANCE_FEET} feet in the derived stand pose, legs' weight left out), its effort "
            f"limit is {limits[worst]:.3g} N m")


def aerial_hover_shortfall(robot) -> str:
    """"" when the rotors can lift the vehicle; otherwise the reason with both figures. The rule
    lives once, in the aerial controller's configure (C++ validate: the allocation's largest
    collective thrust against m g); this turns its refusal into the scenario's."""
    import kiloloop as kl

    from ..robot import aerial

    try:
        kl.AerialController(aerial.model(robot), aerial.config(robot))
    except ValueError as e:
        # Anything else the configure refuses is the robot file's doing: an InputError.
        reason = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        if "cannot lift" in reason:
            return f"{reason}: it cannot hover"
        raise InputError(f"{robot.name}: {reason}") from e
    return ""
