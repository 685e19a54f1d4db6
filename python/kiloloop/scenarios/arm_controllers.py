"""The arm scenarios' joint controllers, configured from the robot file (robot/arm.py derives
the gains, the measurement age and the friction to compensate)."""
from __future__ import annotations

import kiloloop as kl

from ..errors import InputError, configuring
from ..robot import arm as arm_defaults


def joint_config(robot, model, q, measurement_delay: float = 0.0, config=None,
                 law: str = "computed_torque"):
    """The joint controller's config from the robot file: gains (bandwidth; on M(q) for
    pd_gravity), measurement age (plus the measurement delay [s]), compensated friction."""
    c = config or (kl.ComputedTorqueConfig() if law == "computed_torque"
                   else kl.JointPdGravityConfig())
    c.kp, c.kd = arm_defaults.joint_gains(robot, model, law, q)
    age = float(arm_defaults.controller_settings(robot)["max_measurement_age"])
    c.max_measurement_age = age + float(measurement_delay)
    c.friction = arm_defaults.joint_friction(robot, model)
    return c


def controller(robot, model, law: str, q, *, measurement_delay: float = 0.0, config=None):
    """A compiled joint controller with gains derived from the robot file (robot/arm.py)."""
    classes = {"computed_torque": kl.ComputedTorqueController,
               "pd_gravity": kl.JointPdGravityController}
    if law not in classes:
        raise InputError(f"controller: expected 'computed_torque' or 'pd_gravity', got {law!r}")
    config = joint_config(robot, model, q, measurement_delay, config, law)
    with configuring(f"{robot.name} {law} controller"):
        return classes[law](model, config)
