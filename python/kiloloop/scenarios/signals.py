"""What a scenario's log holds: unit, component names and label of each signal, per family.

One table per family (arm, quadruped, aerial), the frames of its spatial signals (FRAMES), and one
function, describe(log, kind, robot), that writes them into a finished log (SignalLog.describe),
with the component names taken from
the robot: its controller's joint names for q, q_ref, tau; the quadruped controller's feet for
per-foot signals; rotor0.. for per-rotor ones. scenarios.run calls it on every scenario's log, so
a scenario describes nothing by hand; a signal not in the table stays undescribed (plots then
fall back to name[i]).
"""
from __future__ import annotations

XYZ = ["x", "y", "z"]
QUAT = ["w", "x", "y", "z"]
WRENCH = ["fx", "fy", "fz", "tx", "ty", "tz"]

# Component names resolved per robot by _names(): "joints", "feet", "feet_xyz", "rotors".
# name -> (unit, components (a list, one of those keys, or None for a scalar), label)
COMMON = {
    "t": ("s", None, "time"),
    "status": ("", None, "controller status (0 ok, > 0 degraded, < 0 failed)"),
    "safe_stop": ("", None, "safe stop (0/1)"),
}

ARM = {
    "q": ("rad", "joints", "joint position (measured)"),
    "qd": ("rad/s", "joints", "joint velocity (measured)"),
    "q_true": ("rad", "joints", "joint position (plant)"),
    "q_measured": ("rad", "joints", "joint position (measured)"),
    "qd_measured": ("rad/s", "joints", "joint velocity (measured)"),
    "qd_true": ("rad/s", "joints", "joint velocity (plant)"),
    "q_ref": ("rad", "joints", "joint reference"),
    "q_err": ("rad", "joints", "joint error q_ref - q"),
    "tau": ("N m", "joints", "joint torque command"),
    "ee": ("m", XYZ, "end-effector position (world)"),
    "ee_ref": ("m", XYZ, "end-effector reference (world)"),
    "ee_rot": ("", None, "end-effector rotation matrix (world)"),
    "ee_err_mm": ("mm", None, "end-effector position error"),
    "ee_rot_err_mrad": ("mrad", None, "end-effector orientation error"),
    "pose_ref": ("", None, "tool pose reference (4x4, m)"),
    "ik_error": ("m, rad", ["x", "y", "z", "rx", "ry", "rz"], "IK task error"),
    "mode": ("", None, "supervisor mode (0 normal, 1 stopping, 2 holding)"),
    "manipulability": ("", None, "manipulability"),
    "box_contacts": ("", None, "contacts with the box (MuJoCo)"),
    "box_distance": ("m", None, "distance links-box (MuJoCo)"),
    "x_ref": ("m", None, "tool x reference (world)"),
    "force": ("N", XYZ, "tool force sensor (world)"),
    "force_z": ("N", None, "pressing force"),
    "x_err_mm": ("mm", None, "tool x error"),
}

QUADRUPED = {
    "base_pos": ("m", XYZ, "trunk position (world)"),
    "base_quat": ("", QUAT, "trunk orientation (world)"),
    "base_vel": ("m/s", XYZ, "trunk velocity (world)"),
    "base_omega": ("rad/s", XYZ, "trunk angular velocity (trunk frame)"),
    "est_pos": ("m", XYZ, "estimated trunk position"),
    "est_vel": ("m/s", XYZ, "estimated trunk velocity"),
    "est_quat": ("", QUAT, "estimated trunk orientation"),
    "tilt": ("rad", None, "trunk tilt from vertical (estimated)"),
    "contact": ("", "feet", "contact detected (0/1)"),
    "scheduled": ("", "feet", "scheduled stance (0/1)"),
    "foot_clearance": ("m", "feet", "foot above the estimated ground"),
    "tau": ("N m", "joints", "joint torque command"),
    "foot_force_cmd": ("N", "feet_xyz", "ground reaction commanded (world)"),
    "foot_force": ("N", "feet", "ground reaction (MuJoCo, world, per foot x y z)"),
    "foot_pos": ("m", "feet", "foot position (world, per foot x y z)"),
    "foot_fz": ("N", "feet", "ground reaction, vertical"),
    "v_cmd": ("m/s, rad/s", ["vx", "vy", "yaw_rate"], "velocity command (heading frame)"),
    "qp_iterations": ("", None, "stance-force QP iterations"),
    "roll_pitch_deg": ("deg", ["roll", "pitch"], "roll, pitch"),
}

AERIAL = {
    "base_pos": ("m", XYZ, "body position (world)"),
    "pos_ref": ("m", XYZ, "position reference (world)"),
    "com": ("m", XYZ, "vehicle centre of mass (world)"),
    "base_quat": ("", QUAT, "body orientation (world)"),
    "quat_des": ("", QUAT, "commanded orientation (world)"),
    "base_vel": ("m/s", XYZ, "body velocity (world)"),
    "base_omega": ("rad/s", XYZ, "body angular velocity (body frame)"),
    "tilt": ("rad", None, "body tilt from vertical (estimated)"),
    "thrust": ("N", "rotors", "rotor thrust"),
    "thrust_cmd": ("N", "rotors", "rotor thrust command"),
    "rotors_saturated": ("", None, "rotors saturated (0/1)"),
    "q": ("rad", "joints", "arm joint position"),
    "q_ref": ("rad", "joints", "arm joint reference"),
    "tau": ("N m", "joints", "arm joint torque command"),
    "reaction": ("N, N m", WRENCH, "arm reaction on the body (feed-forward)"),
    "ee_pos": ("m", XYZ, "end effector (world)"),
    "ee_ref": ("m", XYZ, "end-effector reference (world)"),
    "ee_rot": ("", None, "end-effector rotation matrix (world)"),
    "ee_err_mm": ("mm", None, "end-effector error"),
    "att_err_deg": ("deg", XYZ, "attitude error (rotation vector)"),
    "att_level_deg": ("deg", XYZ, "attitude vs level (rotation vector)"),
    "roll_deg": ("deg", None, "roll"),
    "wind": ("m/s", XYZ, "wind (world)"),
    "wind_force": ("N", XYZ, "wind force (world)"),
    "push_force": ("N", XYZ, "push force (world)"),
    "diverged": ("", None, "diverged (0/1)"),
}

TABLES = {"arm": ARM, "quadruped": QUADRUPED, "aerial": AERIAL}

# The frame a signal's vectors (or coordinates) are expressed in, where its label says so: "world"
# (the plant's fixed frame; the controller's estimates are in its idea of it), the trunk's or
# body's own axes, "heading" (world z, x along the trunk's heading). Written into MCAP logs.
FRAMES = {
    "arm": {n: "world" for n in ("ee", "ee_ref", "ee_rot", "pose_ref", "x_ref", "force")},
    "quadruped": {**{n: "world" for n in ("base_pos", "base_quat", "base_vel", "est_pos",
                                           "est_vel", "est_quat", "foot_force_cmd", "foot_force",
                                           "foot_pos")},
                  "base_omega": "trunk", "v_cmd": "heading"},
    "aerial": {**{n: "world" for n in ("base_pos", "pos_ref", "com", "base_quat", "quat_des",
                                        "base_vel", "ee_pos", "ee_ref", "ee_rot", "wind",
                                        "wind_force", "push_force")},
               "base_omega": "body"},
}

# A scenario that runs twice logs the second run under a suffix (aerial-arm-sweep: feed-forward
# off); such a signal is described as its stem, the label saying which run it is.
VARIANTS = {"_no_ff": "feed-forward off"}


def _names(kind: str, robot) -> dict[str, list[str]]:
    """Per-robot component names: the controller's joint order, the feet, the rotors."""
    if robot is None:
        return {}
    if kind == "arm":
        return {"joints": list(robot.model().joint_names)}
    if kind == "quadruped":
        import kiloloop as kl

        from ..robot.quadruped import controller_config

        controller = kl.QuadrupedController(robot.model(), controller_config(robot))
        feet = [str(f) for f in controller.config.feet]
        return {"joints": list(controller.joint_names), "feet": feet,
                "feet_xyz": [f"{f} {a}" for f in feet for a in XYZ]}
    if kind == "aerial":
        from ..robot import aerial

        return {"joints": list(aerial.model(robot).joint_names),
                "rotors": [f"rotor{i}" for i in range(len(aerial.rotors(robot)))]}
    return {}


def describe(log, kind: str, robot=None) -> None:
    """Describes every signal of `log` that the family's table knows (unit, components, label).

    kind: "arm", "quadruped" or "aerial"; robot: the loaded Robot the log was produced with (its
    joint, foot and rotor names); None leaves those components unnamed. A component list whose
    length does not match the logged signal is dropped (the unit and label stay)."""
    table = {**COMMON, **TABLES.get(kind, {})}
    names = _names(kind, robot)
    for name in log.names():
        stem, variant = name, None
        for suffix, what in VARIANTS.items():
            if name.endswith(suffix) and name[:-len(suffix)] in table:
                stem, variant = name[:-len(suffix)], what
        if stem not in table:
            continue
        unit, components, label = table[stem]
        if isinstance(components, str):
            components = names.get(components)
        shape = log[name].shape
        if components is not None and (len(shape) < 2 or shape[1] != len(components)):
            components = None
        log.describe(name, unit, components, f"{label} ({variant})" if variant else label,
                     FRAMES.get(kind, {}).get(stem))
