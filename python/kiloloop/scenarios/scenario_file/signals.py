"""The signals a scenario file's criteria, baselines and plots read, per family, with units.

Each is computed from a finished run's log (ground truth from the simulator where it says so,
never what the controller estimated) and stored back into the log under its name, so `--log`
files carry them. `kiloloop signals ROBOT` prints the table of a robot's family with the
component names of its vector signals.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Signal:
    unit: str
    description: str
    vector: bool = False   # one column per component (joints, axes, rotors)
    frame: str | None = None  # the frame it is expressed in ("world", "heading"), where one is


ARM = {
    "q": Signal("rad", "joint positions (simulator)", True),
    "q_ref": Signal("rad", "joint position reference", True),
    "qd": Signal("rad/s", "joint velocities (simulator)", True),
    "joint_error": Signal("rad", "largest |q_ref - q| over the joints"),
    "ee": Signal("m", "tool position in the world (simulator)", True, "world"),
    "ee_ref": Signal("m", "tool position reference in the world", True, "world"),
    "ee_error": Signal("m", "distance from the tool to its reference"),
    "tau": Signal("N m", "joint torque commands", True),
    "status": Signal("-", "the controller's Status code (negative: failure)"),
    "estop_mode": Signal("-", "supervisor mode: 0 normal, 1 stopping, 2 holding (with an estop event)"),
}
QUADRUPED = {
    "roll": Signal("deg", "trunk roll (simulator)"),
    "pitch": Signal("deg", "trunk pitch (simulator)"),
    "yaw": Signal("deg", "trunk yaw, unwrapped (simulator)"),
    "height": Signal("m", "trunk origin above the world's z = 0 (simulator)", frame="world"),
    "vx": Signal("m/s", "forward trunk velocity, heading frame (simulator)", frame="heading"),
    "vy": Signal("m/s", "leftward trunk velocity, heading frame (simulator)", frame="heading"),
    "yaw_rate": Signal("rad/s", "trunk yaw rate (simulator)"),
    "vx_ref": Signal("m/s", "commanded forward velocity", frame="heading"),
    "vy_ref": Signal("m/s", "commanded leftward velocity", frame="heading"),
    "yaw_rate_ref": Signal("rad/s", "commanded yaw rate"),
    "velocity_error": Signal("m/s", "|(vx, vy) - (vx_ref, vy_ref)|"),
    "fell": Signal("0/1", "1 from the tick the trunk fell (below half its standing height or "
                          "tilted past 45 deg) on"),
    "tau": Signal("N m", "joint torque commands", True),
    "status": Signal("-", "the controller's Status code (negative: failure)"),
}
AERIAL = {
    "position": Signal("m", "body position in the world (simulator)", True, "world"),
    "position_ref": Signal("m", "body position reference", True, "world"),
    "position_error": Signal("m", "|position_ref - position|"),
    "attitude_error": Signal("deg", "rotation from the commanded attitude to the body's"),
    "tilt": Signal("deg", "angle of the body's z axis from vertical (simulator)"),
    "thrust": Signal("N", "rotor thrusts (simulator)", True),
    "diverged": Signal("0/1", "1 from the tick the flight diverged (non-finite state, safe "
                              "stop, tilt past 60 deg) on"),
    "q": Signal("rad", "arm joint positions (simulator; empty without an arm)", True),
    "tau": Signal("N m", "arm joint torque commands", True),
    "status": Signal("-", "the controller's Status code (negative: failure)"),
}
BY_FAMILY = {"arm": ARM, "quadruped": QUADRUPED, "aerial": AERIAL}
# Every signal is logged against "t" [s], the controller's time of the tick.


def table(family: str, components: dict | None = None) -> str:
    """The signal table as text (`kiloloop signals`): name, unit, description, components."""
    rows = []
    for name, s in BY_FAMILY[family].items():
        comp = (components or {}).get(name)
        rows.append(f"  {name:<16} [{s.unit}]{' ' * max(1, 8 - len(s.unit))}{s.description}"
                    + (f"\n  {'':<16} components: {', '.join(comp)}" if comp else ""))
    return "\n".join(rows)


def components_of(robot) -> dict:
    """The component names of a robot's vector signals (joints in the controller's order, x/y/z,
    rotor0..), from its robot file alone (no plant is built)."""
    xyz = ["x", "y", "z"]
    if robot.kind == "arm":
        joints = list(robot.model().joint_names)
        return {"q": joints, "q_ref": joints, "qd": joints, "tau": joints, "ee": xyz, "ee_ref": xyz}
    if robot.kind == "quadruped":
        import kiloloop as kl

        from ...robot.quadruped import controller_config

        ctrl = kl.QuadrupedController(robot.model(), controller_config(robot))
        return {"tau": list(ctrl.joint_names)}
    from ...robot import aerial

    model = aerial.model(robot)
    joints = list(model.joint_names) if model.nq else []
    rotors = [f"rotor{k}" for k in range(len(robot.data.get("rotors", [])))]
    return {"position": xyz, "position_ref": xyz, "q": joints, "tau": joints, "thrust": rotors}
