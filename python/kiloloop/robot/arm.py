"""What an arm's robot file does not say, derived from its URDF (never tuned for one arm).

- start pose: [sim.joints] q0 or [chain] q0 if given, else zero moved inside the limits;
- work pose: a well-conditioned pose near the start pose (Cartesian scenarios start there);
- rotor inertia (armature): [sim.joints] armature if given, else the geared actuator's reflected
  rotor inertia where the URDF declares the joint's losses (<dynamics> damping or friction), 0
  where it declares none (an ideal torque source: the plant is the URDF's rigid body);
- joint gains: a target bandwidth (rad/s) and damping ratio, scaled by the mass matrix (the
  armature on its diagonal) where the control law needs it (PD + gravity), or exact (computed
  torque, whose model carries the armature too: Robot.model()); the bandwidth raised on joints
  whose Coulomb friction would otherwise hold them off the reference (friction_bandwidth);
- reach (scenarios/arm_targets.py, from the plant's geometry): the scale of every Cartesian
  size a scenario derives.
"""
from __future__ import annotations

import numpy as np

from .schema import FREE, NUMBERS, schema_for

# Fraction of a joint's range kept free at each end when the start pose is moved inside it.
LIMIT_MARGIN = 0.05
# Joint offsets larger than this [rad] are never derived (continuous joints have no range).
MAX_OFFSET = 1.0


def _finite_range(model) -> tuple[np.ndarray, np.ndarray]:
    lo, up = np.asarray(model.lower, float), np.asarray(model.upper, float)
    return lo, up


def clip_inside(model, q: np.ndarray, margin: float = LIMIT_MARGIN) -> np.ndarray:
    """q moved inside [lower, upper] by `margin` of each finite range."""
    lo, up = _finite_range(model)
    span = np.where(np.isfinite(up - lo), up - lo, 0.0)
    return np.clip(q, np.where(np.isfinite(lo), lo + margin * span, -np.inf),
                   np.where(np.isfinite(up), up - margin * span, np.inf))


def start_pose_given(robot) -> bool:
    return (robot.section("sim").get("joints", {}).get("q0") is not None
            or robot.section("chain").get("q0") is not None)


def start_pose(robot, model) -> np.ndarray:
    """[rad] the pose the plant starts in (URDF joint order of the chain)."""
    q0 = robot.section("sim").get("joints", {}).get("q0")
    if q0 is None:
        q0 = robot.section("chain").get("q0")
    if q0 is None:
        return clip_inside(model, np.zeros(model.nq))
    key = "sim.joints.q0" if robot.section("sim").get("joints", {}).get("q0") is not None \
        else "chain.q0"
    return per_joint(robot, key, q0, model.nq, scalar=False)


def per_joint(robot, key: str, value, nq: int, scalar: bool = True) -> np.ndarray:
    """(nq,) floats from a robot-file value given per joint (or, when `scalar`, as one number
    for every joint); any other count is an error naming the key, the expected and the given
    count (the schema has already checked that the values are numbers)."""
    from .errors import RobotFileError

    arr = np.atleast_1d(np.asarray(value, dtype=float))
    if arr.shape == (1,) and scalar:
        return np.full(nq, float(arr[0]))
    if arr.shape != (nq,):
        expected = f"1 or {nq}" if scalar else f"{nq}"
        raise RobotFileError(f"{robot.where(key)}: expected {expected} values (the chain has {nq} "
                             f"joints), got {arr.size}")
    return arr


def joint_range(model, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per joint, how far [rad] q may move down and up inside the limits (capped at MAX_OFFSET)."""
    lo, up = _finite_range(model)
    inner_lo, inner_up = clip_inside(model, np.full(model.nq, -np.inf)), clip_inside(
        model, np.full(model.nq, np.inf))
    down = np.minimum(q - np.where(np.isfinite(lo), inner_lo, -np.inf), MAX_OFFSET)
    up_ = np.minimum(np.where(np.isfinite(up), inner_up, np.inf) - q, MAX_OFFSET)
    return np.maximum(down, 0.0), np.maximum(up_, 0.0)


def controller_settings(robot) -> dict:
    out = {k: v for k, v in schema_for("arm")["controller"].items()
           if v is not FREE and v is not NUMBERS}
    out.update(robot.section("controller"))
    return out


# A geared joint's rotor: the time [s] its motor's peak torque takes to spin the rotor alone from
# rest to top speed, J_m w_m / tau_m. It does not depend on the gear ratio N (the joint sees
# N^2 J_m, N tau_m and w_m / N), so the reflected inertia follows from the joint's own limits:
# armature = effort * ROTOR_ACCELERATION_TIME / velocity. 5 ms: servo motors' datasheets give
# 1-10 ms (e.g. maxon EC 45 flat, 135 g cm^2, 1.5 N m stall, 460 rad/s: 4 ms); UR5's
# harmonic-drive joints (models/ur5/robot.toml: armature 0.4 kg m^2 at 150 N m, 3.15 rad/s) give 8.
ROTOR_ACCELERATION_TIME = 0.005


def armature(robot, model) -> np.ndarray:
    """(nq,) [kg m^2] reflected rotor inertia of each chain joint, which the plant adds to M's
    diagonal and the controllers' gains account for: [sim.joints] armature when the file gives it;
    else, where the URDF declares the joint's losses (<dynamics> damping or friction > 0: a geared
    actuator, whose rotor the rigid-body URDF omits), effort * ROTOR_ACCELERATION_TIME / velocity
    (0 without finite limits); 0 where it declares none (an ideal torque source)."""
    given = robot.section("sim").get("joints", {}).get("armature")
    if given is not None:
        return per_joint(robot, "sim.joints.armature", given, model.nq)
    losses = urdf_dynamics(robot)
    effort, velocity = np.asarray(model.effort_limit, float), np.asarray(model.velocity_limit, float)
    declared = np.array([sum(losses.get(n, (0.0, 0.0))) > 0.0 for n in model.joint_names])
    limited = np.isfinite(effort) & np.isfinite(velocity) & (velocity > 0.0)
    rotor = np.where(limited, effort * ROTOR_ACCELERATION_TIME / np.where(limited, velocity, 1.0),
                     0.0)
    return np.where(declared, rotor, 0.0)


# Where a joint's Coulomb friction dominates its inertia: a stuck joint holds an error up to
# friction / kp, so its bandwidth is raised until that band is at most STICK_BAND [rad], up to
# MAX_BANDWIDTH [rad/s] (a quarter of the 1 kHz control rate: the measurement is a tick old).
STICK_BAND = 2e-4
MAX_BANDWIDTH = 250.0


def friction_bandwidth(w: float, coulomb: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """(nq,) [rad/s] w, raised per joint to sqrt(coulomb / (STICK_BAND inertia)) where that is
    higher (at most MAX_BANDWIDTH); w where the joint has no Coulomb friction."""
    needed = np.sqrt(coulomb / (STICK_BAND * np.maximum(inertia, 1e-12)))
    return np.where(coulomb > 0, np.clip(needed, w, max(w, MAX_BANDWIDTH)), w)


def joint_gains(robot, model, law: str, q: np.ndarray, dynamics=None):
    """(kp, kd) per joint. computed_torque: kp = w^2, kd = 2 zeta w (unit-mass error dynamics);
    pd_gravity: the same bandwidth on the diagonal of M(q), the armature included (the model
    carries it: Robot.model()). w is raised on joints whose compensated Coulomb friction would
    hold more than STICK_BAND (friction_bandwidth). Explicit kp/kd in [controller] win."""
    import kiloloop as kl

    c = controller_settings(robot)
    w, zeta = float(c["bandwidth"]), float(c["damping_ratio"])
    coulomb = np.asarray(joint_friction(robot, model).coulomb, float)
    if law == "computed_torque" and not coulomb.any():
        kp, kd = np.full(model.nq, w * w), np.full(model.nq, 2.0 * zeta * w)
    else:
        dyn = dynamics or kl.Dynamics(model)
        m = np.diag(dyn.mass_matrix(q))
        w = friction_bandwidth(w, coulomb * np.ones(model.nq), m)
        unit = np.ones(model.nq) if law == "computed_torque" else m
        kp, kd = unit * w * w, unit * 2.0 * zeta * w
    if "kp" in c:
        kp = per_joint(robot, "controller.kp", c["kp"], model.nq)
    if "kd" in c:
        kd = per_joint(robot, "controller.kd", c["kd"], model.nq)
    return kp, kd


def urdf_dynamics(robot) -> dict[str, tuple[float, float]]:
    """joint name -> (damping [N m s/rad], friction [N m]) from the URDF's <dynamics> elements."""
    import xml.etree.ElementTree as ET

    out = {}
    for joint in ET.parse(robot.urdf).getroot().findall("joint"):
        dyn = joint.find("dynamics")
        if dyn is not None:
            out[joint.get("name")] = (float(dyn.get("damping", 0.0)), float(dyn.get("friction", 0.0)))
    return out


def joint_friction(robot, model):
    """kl.JointFrictionConfig the arm controllers compensate: [controller] viscous_friction /
    coulomb_friction if given, else the URDF's <dynamics> of the chain joints (0 where none);
    all zero when friction_compensation is false."""
    import kiloloop as kl

    c = controller_settings(robot)
    f = kl.JointFrictionConfig()
    f.smoothing_speed = float(c["friction_smoothing_speed"])
    if not c["friction_compensation"]:
        return f
    urdf = urdf_dynamics(robot)
    viscous = np.array([urdf.get(n, (0.0, 0.0))[0] for n in model.joint_names])
    coulomb = np.array([urdf.get(n, (0.0, 0.0))[1] for n in model.joint_names])
    if "viscous_friction" in c:
        viscous = per_joint(robot, "controller.viscous_friction", c["viscous_friction"], model.nq)
    if "coulomb_friction" in c:
        coulomb = per_joint(robot, "controller.coulomb_friction", c["coulomb_friction"], model.nq)
    f.viscous, f.coulomb = viscous, coulomb
    return f


# [controller] keys given per joint (or one number for every joint).
PER_JOINT_KEYS = ("kp", "kd", "viscous_friction", "coulomb_friction")


def check_sizes(robot, model) -> None:
    """Every per-joint value of the file (the start pose, [controller] gains and friction) has a
    count the chain takes: refused at load, not when (or if) a scenario reads it."""
    start_pose(robot, model)
    c = robot.section("controller")
    for key in PER_JOINT_KEYS:
        if key in c:
            per_joint(robot, f"controller.{key}", c[key], model.nq)
