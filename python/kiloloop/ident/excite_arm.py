"""An arm's excitation run: the Fourier trajectory (excitation.py) from the work pose, tracked by
the robot file's computed-torque controller, the actuation delay and lag in the motor model.

The controller compensates the joint friction the plant has (the file's [sim.joints], unless its
[controller] names the friction to compensate): a real arm's drive does as well, and without it
a light wrist behind a strong Coulomb friction does not move at all under gains derived from the
rigid body's inertia (the UR5's wrist 3: 3 N m of friction against 0.2 N m of feedback)."""
from __future__ import annotations

from ..robot.arm import controller_settings as arm_settings
from ..scenarios.arm_controllers import controller
from ..scenarios.arm_targets import PoseProbe, work_pose
from ..sil.arm_adapters import JointTracking
from ..sil.rig import Rig
from ..sil.signals import Signals
from .excitation import design
from .logged import keep

# What a real arm's logger records, with units.
LOGGED = {"t": ("s", "time"), "q": ("rad", "measured joint positions"),
          "qd": ("rad/s", "measured joint velocities"),
          "tau": ("N m", "commanded joint torques"), "q_ref": ("rad", "reference")}


def run(robot, duration: float, seed: int, delay: float, motor_lag: float, noise: dict):
    rig = Rig(robot, Signals(motor_delay=delay, motor_time_constant=motor_lag, **noise),
              seed=seed)
    plant, model = rig.plant, rig.model
    q0 = work_pose(robot, model, plant)
    plant.q0 = q0
    plant.reset()
    exc = design(robot, model, plant, q0, duration, seed, probe=PoseProbe(plant))
    given = robot.section("controller")
    if "viscous_friction" not in given and "coulomb_friction" not in given:
        m, dofs = plant.model, plant.dof_addresses
        robot = robot.with_overrides({
            "controller.viscous_friction": [float(x) for x in m.dof_damping[dofs]],
            "controller.coulomb_friction": [float(x) for x in m.dof_frictionloss[dofs]]})
    if "kp" not in given and "kd" not in given:
        # The file's bandwidth as it is: robot/arm.py raises it on joints whose Coulomb friction
        # dominates (up to 250 rad/s), which rings behind the 10-35 ms actuation delay an
        # excitation is run to find (measured: example-robot-data's Panda, 20 ms, the fit's
        # residual 86 % of the torque); the friction is compensated here instead.
        c = arm_settings(robot)
        w, zeta = float(c["bandwidth"]), float(c["damping_ratio"])
        robot = robot.with_overrides({"controller.kp": w * w, "controller.kd": 2.0 * zeta * w})
    law = controller(robot, model, "computed_torque", q0)
    log = rig.run(duration, JointTracking(law, exc.trajectory()))
    out = keep(log, LOGGED)
    for name in ("q", "qd", "tau", "q_ref"):  # per joint: name the components
        unit, label = LOGGED[name]
        out.describe(name, unit, components=list(model.joint_names), label=label)
    return out
