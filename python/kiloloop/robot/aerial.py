"""What an aerial robot file does not say, derived from its URDF and its rotors (never tuned for one
vehicle).

The file gives the geometry: `[vehicle] base` (and `ee` when it carries an arm) and one `[[rotors]]`
table per rotor (position, axis, spin, thrust_max, torque_coefficient, time_constant). From them and
the URDF's masses:
- hover thrust and thrust/weight: the rotors' pseudo-inverse allocation about the body CoM;
- roll/pitch authority: the angular acceleration the rotors' margin at hover gives the rigid
  vehicle (roll_pitch_authority);
- attitude gains: bandwidth 0.6 / tau_m (the slowest rotor's time constant: the same phase margin
  through the rotor lag for any vehicle; tau_m = 30 ms gives 20 rad/s: kp 400, kd 40), capped at
  40 rad/s and at 2 sqrt(authority / tilt limit) (bandwidths()), critically damped (yaw at half
  the bandwidth);
- position gains: a fifth of the attitude bandwidth horizontally, a quarter vertically, critically
  damped, integral w^3 / 16 (so the loops stay separated by the same ratio);
- arm gains: the attitude bandwidth (the arm's motion is what the attitude loop has to absorb);
- reaction lead: the rotor time constant (the fed-forward reaction torque is led by tau_m to cancel
  the rotors' first-order lag to first order; measured in aerial-arm-sweep, CoM held: the
  feed-forward's reduction of the attitude error went from 53/74/82 % to 91/92/92 % at 2/3/4 s);
- per-rotor efficiency for the plant ([sim.rotors] efficiency), 1 by default.
`[controller]` may set any of these explicitly (`attitude_bandwidth`, `position_bandwidth`,
`arm_bandwidth`, `arm_kp`, `arm_kd`, ...; see CONTROLLER_KEYS).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .errors import RobotFileError

if TYPE_CHECKING:  # annotations only: kiloloop._core is imported where it is used
    from .._core import AerialConfig, RobotModel

# [s] a rotor's time constant where its table gives none (10-inch props): the plant's motor lag
# and the gains' design both take it, so that they agree (a plant without lag under gains and a
# reaction lead designed for 30 ms diverged: hextilt, whose source gives none).
DEFAULT_TIME_CONSTANT = 0.03
# Rotor table keys: None = required.
ROTOR_KEYS = {"position": None, "axis": [0.0, 0.0, 1.0], "spin": None, "thrust_max": None,
              "torque_coefficient": None, "time_constant": DEFAULT_TIME_CONSTANT,
              "thrust_min": 0.0}
MAX_ATTITUDE_BANDWIDTH = 40.0  # [rad/s]: beyond, the 1 kHz loop's delay and IMU noise dominate

# [controller] keys: bandwidths [rad/s] that the gains come from, and kl.AerialConfig fields.
CONTROLLER_KEYS = {
    "attitude_bandwidth": None, "position_bandwidth": None, "arm_bandwidth": None,
    "arm_kp": None, "arm_kd": None, "arm_q_nominal": None, "reaction_feedforward": None,
    "hold_com": None, "reaction_lead": None, "measured_acceleration": None, "max_tilt": None,
    "max_measurement_age": None, "failsafe_thrust_fraction": None, "ik_damping": None,
    "ik_iterations": None, "tilt_limit": None, "lag_compensation": None,
}


def _err(robot, msg):
    return RobotFileError(f"{robot.path}: {msg}")


def rotors(robot) -> list[dict]:
    """The checked [[rotors]] tables with their defaults: position (3,) [m], axis (3,) unit,
    spin +-1, thrust_max [N], torque_coefficient [m], time_constant [s], thrust_min [N]."""
    tables = robot.data.get("rotors")
    if not isinstance(tables, list) or len(tables) < 4:
        raise _err(robot, "rotors: expected at least 4 [[rotors]] tables "
                          f"(got {0 if not isinstance(tables, list) else len(tables)})")
    out = []
    for i, t in enumerate(tables):
        if not isinstance(t, dict):
            raise _err(robot, f"rotors[{i}]: expected a table")
        for key in t:
            if key not in ROTOR_KEYS:
                raise _err(robot, f"unknown key 'rotors[{i}].{key}'")
        r = {}
        for key, default in ROTOR_KEYS.items():
            if key not in t and default is None:
                raise _err(robot, f"missing key 'rotors[{i}].{key}'")
            r[key] = t.get(key, default)
        for key in ("position", "axis"):
            v = np.asarray(r[key], dtype=float)
            if v.shape != (3,) or not np.all(np.isfinite(v)):
                raise _err(robot, f"rotors[{i}].{key}: expected 3 finite numbers")
            r[key] = v
        if np.linalg.norm(r["axis"]) < 1e-9:
            raise _err(robot, f"rotors[{i}].axis: must not be zero")
        r["axis"] = r["axis"] / np.linalg.norm(r["axis"])
        if r["spin"] not in (1, -1):
            raise _err(robot, f"rotors[{i}].spin: expected 1 (counter-clockwise about the axis) "
                              f"or -1, got {r['spin']!r}")
        for key in ("thrust_max", "torque_coefficient", "time_constant", "thrust_min"):
            v = float(r[key])
            if not math.isfinite(v) or v < 0:
                raise _err(robot, f"rotors[{i}].{key}: expected a finite number >= 0")
            r[key] = v
        if r["thrust_max"] <= r["thrust_min"]:
            raise _err(robot, f"rotors[{i}]: thrust_max must exceed thrust_min")
        out.append(r)
    if len({r["thrust_min"] for r in out}) > 1:
        raise _err(robot, "rotors: thrust_min must be the same for every rotor")
    return out


def time_constant(robot) -> float:
    """[s] the slowest rotor's lag (DEFAULT_TIME_CONSTANT when no rotor gives one)."""
    tau = max(r["time_constant"] for r in rotors(robot))
    return tau if tau > 0 else DEFAULT_TIME_CONSTANT


# What each [controller] key takes (schema.bad_values templates): true/false, a number, or (arm
# gains and pose) one number or one per arm joint.
_BOOLEAN = ("reaction_feedforward", "hold_com", "measured_acceleration", "lag_compensation")
_PER_JOINT = ("arm_kp", "arm_kd", "arm_q_nominal")


def _controller_template() -> dict:
    from .schema import NUMBERS

    return {k: True if k in _BOOLEAN else NUMBERS if k in _PER_JOINT else 0.0
            for k in CONTROLLER_KEYS}


def controller_settings(robot) -> dict:
    from .errors import RobotFileError
    from .schema import bad_values

    c = robot.section("controller")
    for key in c:
        if key not in CONTROLLER_KEYS:
            raise _err(robot, f"unknown key 'controller.{key}'; known: "
                              f"{', '.join(sorted(CONTROLLER_KEYS))}")
    bad = bad_values(c, _controller_template(), "controller.")
    if bad:
        key = bad[0].split(":", 1)[0]
        raise RobotFileError(f"{robot.where(key)}:{bad[0].split(':', 1)[1]}")
    return c


def tilt_limit(robot) -> float:
    """[rad] the largest tilt the position loop commands ([controller] tilt_limit, else the
    controller's default)."""
    import kiloloop as kl

    c = controller_settings(robot)
    return float(c["tilt_limit"]) if "tilt_limit" in c else kl.PositionControlConfig().max_tilt


def roll_pitch_authority(robot) -> float:
    """[rad/s^2] the smallest roll or pitch angular acceleration the rotors can give the vehicle
    (arm frozen at nominal: the rigid inertia about the body CoM) in either direction while they
    hold its weight: each rotor's room between its hover share and thrust_min / thrust_max,
    through the allocation's pseudo-inverse. The thrust margin as the attitude loop sees it."""
    rows, f0, lo, hi, ctrl = _allocation_rows(robot)
    P = np.linalg.pinv(rows)
    torque_col = 3 if rows.shape[0] == 6 else 1
    J = np.asarray(ctrl.rigid_inertia)
    out = math.inf
    for axis in (0, 1):
        p = P[:, torque_col + axis]
        for d in (p, -p):
            up = np.where(d > 1e-12, (hi - f0) / np.where(d > 1e-12, d, 1.0), math.inf)
            down = np.where(d < -1e-12, (lo - f0) / np.where(d < -1e-12, d, -1.0), math.inf)
            torque = float(min(up.min(), down.min()))  # [N m] before a rotor leaves its range
            out = min(out, max(torque, 0.0) / J[axis, axis])
    return out


def _allocation_rows(robot):
    """The rotors as the allocation sees them, about the body CoM: (rows, f0, lo, hi, ctrl) with
    rows the (4, n) mixer [T; tau] or, for tilted rotors, the (6, n) effectiveness [F; tau]; f0
    the hover thrusts (n,) [N] with zero torque; [lo, hi] each rotor's range [N]; ctrl a
    kl.AerialController with the derived rotors (gains do not matter here)."""
    import kiloloop as kl

    from ..errors import configuring

    cfg = kl.AerialConfig()
    cfg.rotors = rotor_config(robot)
    # The module's own class, not the package name `kl.AerialController`: a b2b recording
    # (firmware/recording.py) takes the one made under that name as the run's controller.
    from .. import _core

    with configuring(f"{robot.name} aerial controller"):  # e.g. rotors that cannot lift it
        ctrl = _core.AerialController(model(robot), cfg)
    alloc = ctrl.allocation
    rows = np.asarray(alloc.effectiveness if alloc.uses_lateral_rows else alloc.mixer)
    f0 = np.asarray(alloc.collective_share) * ctrl.hover_thrust
    hi = np.broadcast_to(np.asarray(cfg.rotors.thrust_max, dtype=float), f0.shape).copy()
    return rows, f0, float(cfg.rotors.thrust_min), hi, ctrl


def hover_weight_with(robot, efficiency) -> tuple[float, float]:
    """([N] the largest weight the rotors can hold level with no torque left over, yaw included,
    when rotor k gives efficiency[k] of its thrust and drag torque; [N] the vehicle's weight).
    The arm at nominal: its moment about the body CoM is part of the torque to cancel."""
    import kiloloop as kl

    rows, _, lo, hi, ctrl = _allocation_rows(robot)
    n = rows.shape[1]
    A = rows * np.asarray(efficiency, dtype=float)[None, :]
    weight = ctrl.hover_thrust
    # Torque the rotors must give about the body CoM: gravity acts at the vehicle's CoM.
    tau = np.cross(np.asarray(ctrl.vehicle_com) - np.asarray(ctrl.body_com), [0.0, 0.0, weight])
    lateral = rows.shape[0] == 6
    C, d = np.vstack([np.eye(n), -np.eye(n)]), np.concatenate([hi, -np.full(n, lo)])

    def holds(scale: float) -> bool:
        t = scale * tau
        w = np.array([0.0, 0.0, scale * weight, *t]) if lateral else np.array([scale * weight, *t])
        return kl.qp.solve(np.eye(n), np.zeros(n), A_eq=A, b_eq=w, C=C,
                           d=d).status == kl.qp.QpStatus.OPTIMAL

    low, high = 0.0, 16.0  # [weights]: a thrust/weight beyond 16 is reported as 16
    if holds(high):
        return high * weight, weight
    for _ in range(40):  # bisection on the weight held (the feasible set is convex in it)
        mid = 0.5 * (low + high)
        low, high = (mid, high) if holds(mid) else (low, mid)
    return low * weight, weight


def bandwidths(robot) -> dict:
    """[rad/s] attitude, position (horizontal), arm: derived unless [controller] sets them.
    Attitude: 0.6 / tau_m, at most MAX_ATTITUDE_BANDWIDTH and at most 2 sqrt(alpha / theta), the
    loop whose step response settles (91 %, 4 / w) no sooner than the rotors' margin alpha
    (roll_pitch_authority) can turn the vehicle bang-bang (2 sqrt(theta / alpha)) through the
    largest tilt step theta the position loop commands (tilt_limit, 0.6 rad): a faster loop asks
    for torque the rotors do not have on every large step (a push) and rings in saturation."""
    c = controller_settings(robot)
    att = c.get("attitude_bandwidth")
    if not att:
        att = min(0.6 / time_constant(robot), MAX_ATTITUDE_BANDWIDTH,
                  2.0 * math.sqrt(roll_pitch_authority(robot) / tilt_limit(robot)))
    att = float(att)
    pos = float(c.get("position_bandwidth") or att / 5.0)
    arm = float(c.get("arm_bandwidth") or att)
    return {"attitude": att, "position": pos, "arm": arm}


def model(robot: Any) -> RobotModel:  # robot: a robot_file.Robot (it imports this module)
    """The controller's model: the arm's chain base -> ee, or the whole tree (no arm)."""
    import kiloloop as kl

    v = robot.section("vehicle")
    urdf = robot.urdf_doc.model_source()  # the URDF as the plant reads it too
    try:
        if v.get("ee"):
            return kl.RobotModel.from_urdf(urdf, root=v.get("base") or None, tip=v["ee"])
        return kl.RobotModel.from_urdf(urdf)
    except (ValueError, RuntimeError) as e:
        raise RobotFileError(f"{robot.path}: {e}") from None


def rotor_config(robot, lag_compensation: bool = False):
    """kl.RotorAllocationConfig from the [[rotors]] tables (base link frame)."""
    import kiloloop as kl

    rs = rotors(robot)
    c = kl.RotorAllocationConfig()
    c.positions = np.array([r["position"] for r in rs]).T.copy()
    c.axes = np.array([r["axis"] for r in rs]).T.copy()
    c.spin = np.array([float(r["spin"]) for r in rs])
    c.torque_coefficient = np.array([r["torque_coefficient"] for r in rs])
    c.thrust_max = np.array([r["thrust_max"] for r in rs])
    c.thrust_min = rs[0]["thrust_min"]
    c.time_constant = time_constant(robot)
    c.lag_compensation = bool(lag_compensation)
    return c


def config(robot: Any, config: AerialConfig | None = None) -> AerialConfig:
    """kl.AerialConfig with the rotors and the derived gains (explicit [controller] keys win)."""
    import kiloloop as kl

    cfg = kl.AerialConfig() if config is None else config
    c = controller_settings(robot)
    bw = bandwidths(robot)
    cfg.rotors = rotor_config(robot, bool(c.get("lag_compensation", False)))
    w = bw["attitude"]
    gains = cfg.attitude.gains
    gains.kp = np.array([w * w, w * w, (w / 2) ** 2])
    gains.kd = np.array([2 * w, 2 * w, w])
    cfg.attitude.gains = gains
    p = bw["position"]
    pz = 1.25 * p
    pos = cfg.position
    pos.kp = np.array([p * p, p * p, pz * pz])
    pos.kd = np.array([2 * p, 2 * p, 2 * pz])
    pos.ki = np.array([p ** 3, p ** 3, pz ** 3]) / 16.0
    cfg.position = pos
    a = bw["arm"]
    cfg.arm_kp = np.atleast_1d(np.asarray(c.get("arm_kp", a * a), dtype=float))
    cfg.arm_kd = np.atleast_1d(np.asarray(c.get("arm_kd", 2 * a), dtype=float))
    for key in ("reaction_feedforward", "hold_com", "measured_acceleration"):
        if key in c:
            setattr(cfg, key, bool(c[key]))
    cfg.reaction_lead = time_constant(robot)
    for key in ("reaction_lead", "max_tilt", "max_measurement_age", "failsafe_thrust_fraction",
                "ik_damping"):
        if key in c:
            setattr(cfg, key, float(c[key]))
    if "ik_iterations" in c:
        cfg.ik_iterations = int(c["ik_iterations"])
    if "arm_q_nominal" in c:
        cfg.arm_q_nominal = np.asarray(c["arm_q_nominal"], dtype=float)
    if "tilt_limit" in c:
        pos = cfg.position
        pos.max_tilt = float(c["tilt_limit"])
        cfg.position = pos
    return cfg
