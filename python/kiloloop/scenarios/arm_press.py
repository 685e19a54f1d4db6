"""arm-press: an arm presses on a table with 10 N while sliding along x.

Hybrid force/position control (C++): z is force-controlled (the wrench the tool applies on the
table, from a MuJoCo force sensor between the tool tip and the flange), x, y and the orientation
are motion-controlled (selection matrix diag(1, 1, 0, 1, 1, 1) in the world frame). The tool tip
is a 1 cm sphere 3 cm below the flange (along the tip frame's axis closest to the last joint's:
tool_axis), starting 1 mm above the table; after `settle` seconds the
reference slides along x (10 cm on the UR5; 5 % of the reach unless the robot file says) on a
quintic, with the table's Coulomb friction opposing it. Any arm: the pressing pose is the work
pose turned tool-down by the IK (the UR5's robot file gives its own).
`--set controller=impedance` runs the Cartesian impedance controller instead, with the reference
pushed 10 N / K_z below the surface (no force feedback): for comparison.
The loop runs in C++ (sil/rig.py, cpp/sil/press_adapter.hpp): the force sensor and the tool
site's orientation are part of the measurement, the slide reference is computed in the adapter.
"""
from __future__ import annotations

import mujoco
import numpy as np

import kiloloop as kl

from ..errors import InputError, configuring
from ..robot import arm as arm_defaults
from ..sil import arm_scene, native
from ..sil.arm_adapters import Press
from ..sil.rig import Rig
from .arm_targets import line_feasible, pose_reached, work_pose
from . import JUDGED_WINDOW, ScenarioResult, evaluate
from .plots import ARM_PRESS_PLOT

NAME = "arm-press"
DESCRIPTION = "arm presses a table with 10 N while sliding along x (hybrid force/position)"
DURATION = 3.5  # [s]
DEFAULTS = {
    "controller": "hybrid",         # or "impedance"
    "q0": [],                       # [rad] tool pointing down above the table; empty: derived
    "force": 10.0,                  # [N] pressing force (downwards)
    "slide": 0.0,                   # [m] along +x of the chain root; 0: 5 % of the reach
    "settle": 0.5,                  # [s] before the slide starts (contact is made and settles)
    "slide_time": 2.0,              # [s]
    "gap": 0.001,                   # [m] tip above the table at the start
    "friction": 0.5,                # Coulomb friction tip-table
    # Table contact softness (MuJoCo solref / solimp; [] = MuJoCo's default). The impedance
    # ramps from 0.5 at the surface to 0.95 at 5 mm, so the contact force grows with penetration
    # (about 1 mm at 10 N: a compliant tool tip). With MuJoCo's default solimp the contact holds
    # 10 N at a few micrometres whatever the depth, the sliding tip creeps out of it and the
    # contact drops out for single steps every ~40 ms (0 N, then ~13 N): see bench/RESULTS.md.
    "solref": [],
    "solimp": [0.5, 0.95, 0.005, 0.5, 2.0],
    "noslip_iterations": 0,         # MuJoCo's no-slip post-processing of friction
    "cone": "elliptic",             # MuJoCo friction cone: "elliptic" or "pyramidal"
    "measure_from": 0.4,            # [s] criteria hold from here on ("after settling")
    # Force-loop gains on the force-controlled axis (z); empty: HybridForcePositionConfig's.
    "kf": [],                       # [-]
    "ki": [],                       # [1/s]
    "kv": [],                       # [N s/m]
    "project_motion_wrench": True,  # HybridForcePositionConfig.project_motion_wrench
}
# Robot-file tables it reads (scenarios/__init__.py): the chain and the plant. Its force and
# impedance controllers take their own gains (the settings below), not [controller]'s.
ROBOT_KEYS = ("chain", "sim")
SIZES = {"q0": "nq", "solref": 2, "solimp": 5, "kf": 1, "ki": 1, "kv": 1}
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"settle": (">=", 0.0), "slide_time": (">", 0.0), "gap": (">=", 0.0),
          "friction": (">=", 0.0), "measure_from": (">=", 0.0), "noslip_iterations": (">=", 0)}
CRITERIA = {
    "max_force_error_N": ("<", 0.5),
    "max_x_error_m": ("<", 0.002),
    "slide_fraction": (">", 0.999),  # of the commanded slide
}


_CONES = {"elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC, "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL}


# The slide's motion axes hold the table's friction, friction * force against +x at the tool tip,
# as a static error: Lambda_m K e = wrench on the motion axes m (x, y and the rotations; Lambda_m
# the operational-space inertia there). kp_x is raised where the arm at its pressing pose is too
# light to keep that error within STATIC_ERROR_SHARE of the max_x_error_m criterion (kd_x
# critical, 2 sqrt(kp_x)); a heavier arm keeps the config's gains.
STATIC_ERROR_SHARE = 0.25


def task_inertia(model, q) -> np.ndarray:
    """(6, 6) operational-space inertia (J M^-1 J^T)^-1 [kg; kg m^2] of the chain's tip at q, in
    the chain root frame (a pseudo-inverse: a chain of fewer than 6 joints has no inertia along
    the directions it cannot move)."""
    dyn = kl.Dynamics(model)
    J, M = dyn.jacobian(q), dyn.mass_matrix(q)
    return np.linalg.pinv(J @ np.linalg.solve(M, J.T), rcond=1e-9)


def slide_compliance(model, q0, contact) -> float:
    """[m/s^2 per N] the x error times kp_x that a unit force against +x at `contact` (the tip's
    contact point from the chain tip [m], root frame) leaves: (Lambda_m^-1 w)_x, w the force
    and its moment about the chain tip, on the motion axes only (z is the force loop's)."""
    motion = [0, 1, 3, 4, 5]
    lam = task_inertia(model, q0)[np.ix_(motion, motion)]
    force = np.array([-1.0, 0.0, 0.0])
    w = np.concatenate([force, np.cross(contact, force)])[motion]
    return abs(float(np.linalg.lstsq(lam, w, rcond=1e-9)[0][0]))


def joint_friction_force(model, q0, coulomb) -> float:
    """[N] the largest force along x at the chain tip that the joints' Coulomb friction [N m]
    can hold against the motion (the Cartesian controllers do not compensate it): |J^+T|_x fc."""
    J = kl.Dynamics(model).jacobian(q0)
    return float(np.abs(np.linalg.pinv(J, rcond=1e-6).T[0]) @ coulomb)


def motion_gains(model, q0, settings, config, contact,
                 coulomb=None) -> tuple[np.ndarray, np.ndarray]:
    """(kp, kd) of the config with kp_x raised where the table's friction, and the joints' own
    (coulomb [N m] per joint, the robot's URDF), ask for more."""
    kp, kd = np.array(config.kp, dtype=float), np.array(config.kd, dtype=float)
    friction = float(settings["friction"]) * float(settings["force"])  # [N]
    if coulomb is not None and np.any(coulomb > 0):
        friction += joint_friction_force(model, q0, coulomb)
    allowed = STATIC_ERROR_SHARE * CRITERIA["max_x_error_m"][1]       # [m]
    kp[0] = max(kp[0], friction * slide_compliance(model, q0, contact) / allowed)
    kd[0] = max(kd[0], 2.0 * np.sqrt(kp[0]))
    return kp, kd


def _make_controller(model, settings, q0, contact, coulomb=None):
    if settings["controller"] == "hybrid":
        config = kl.HybridForcePositionConfig()
        config.project_motion_wrench = bool(settings["project_motion_wrench"])
        config.kp, config.kd = motion_gains(model, q0, settings, config, contact, coulomb)
        for key in ("kf", "ki", "kv"):
            if len(settings[key]):
                gains = np.array(getattr(config, key))
                gains[2] = float(settings[key][0])  # the z (force) axis
                setattr(config, key, gains)
        return kl.HybridForcePositionController(model, config)
    if settings["controller"] == "impedance":
        return kl.CartesianImpedanceController(model)
    raise InputError(f"controller: expected 'hybrid' or 'impedance', got {settings['controller']!r}")


SLIDE = 0.05  # of the reach, when the settings give none


def min_duration(settings) -> float:
    """[s] the slide must be over (its fraction is judged at the end), the force judged from
    measure_from on."""
    end = float(settings["settle"]) + float(settings["slide_time"])
    return max(end, float(settings["measure_from"])) + JUDGED_WINDOW


# Pressing positions tried: the tool at these fractions of the reach from the first joint,
# horizontally (at the work pose's azimuth) and at the work pose's height above the floor.
PRESS_RADII = (0.45, 0.55, 0.35, 0.65)
PRESS_HEIGHTS = (1.0, 0.6, 1.4)  # of the work pose's tool height


def tool_axis(model) -> np.ndarray:
    """(3,) the chain tip frame's unit axis the tool points along: the one closest to the last
    joint's axis (a flange turns about its own normal: z for UR's tool0 and Panda's link8, x for
    Z1's link06), signed away from the last joint (+ when the tip sits on it)."""
    dyn = kl.Dynamics(model)
    q = np.clip(np.zeros(model.nq), model.lower, model.upper)
    T, J = dyn.forward_kinematics(q), dyn.jacobian(q)
    last = T[:3, :3].T @ J[3:, -1]
    k = int(np.argmax(np.abs(last)))
    axis = np.zeros(3)
    axis[k] = 1.0
    # The last joint's axis passes through its origin; where the tip lies along it decides.
    return axis if last[k] > 0 else -axis


def _z_to(axis) -> np.ndarray:
    """(3, 3) a rotation taking +z onto the unit vector axis (the identity for +z)."""
    z = np.array([0.0, 0.0, 1.0])
    v, c = np.cross(z, axis), float(z @ axis)
    if np.linalg.norm(v) < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    K = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + K + K @ K / (1.0 + c)


def press_pose(rig, settings) -> tuple[np.ndarray, float]:
    """(q0 [rad], slide [m]): a pose with the tool axis (tool_axis) pointing down, from which the
    IK can follow the slide along +x: of the candidate tool positions (PRESS_RADII x
    PRESS_HEIGHTS, the IK seeded from the work pose), the one whose 6 x n Jacobian is best
    conditioned; when there is none, the tool's yaw in quarter turns and more IK seeds."""
    from .arm_targets import PoseProbe

    model = rig.model
    slide = float(settings["slide"]) or SLIDE * reach_of(rig)
    if len(settings["q0"]):
        return np.asarray(settings["q0"], dtype=float), slide
    q_work = work_pose(rig.robot, model, rig.plant)
    dyn, ik, probe = kl.Dynamics(model), kl.ArmIk(model), PoseProbe(rig.plant)
    T = dyn.forward_kinematics(q_work)
    R_world_root = rig.T_world_root()[:3, :3]
    down = R_world_root.T @ np.array([0.0, 0.0, -1.0])   # world -z in the root frame
    x = T[:3, 0] - down * (T[:3, 0] @ down)
    if np.linalg.norm(x) < 1e-6:
        x = np.cross(down, [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    # The tool axis (tool_axis: the tip frame's z on most arms) pointing down.
    R_down = np.column_stack([x, np.cross(down, x), down]) @ _z_to(tool_axis(model)).T
    # First joint's anchor in the root frame (= the work pose's FK minus the site's lever).
    anchor = R_world_root.T @ (probe.plant.data.xanchor[
        probe.plant.model.joint(probe.plant.joint_names[0]).id] - rig.T_world_root()[:3, 3])
    horizontal = T[:3, 3] - anchor
    horizontal -= down * (horizontal @ down)
    azimuth = horizontal / max(np.linalg.norm(horizontal), 1e-9)
    height = -(T[:3, 3] - anchor) @ down
    # An arm of fewer than 6 joints holds the tool down while it slides only where the slide runs
    # through its first joint (its joints then move in the vertical plane of the slide): the
    # pressing position lies on the x axis through the anchor, in front of or behind it.
    # The tool's yaw about the vertical is then the chain's, not a choice: quarter turns tried.
    x_root = np.array([1.0, 0.0, 0.0]) - down * down[0]
    x_root /= np.linalg.norm(x_root)
    yaws = [np.column_stack([x, np.cross(down, x), down]) @ _z_to(tool_axis(model)).T
            for x in (x_root, np.cross(down, x_root), -x_root, -np.cross(down, x_root))]
    if model.nq >= 6:
        best = _best_press_pose(rig, settings, slide, q_work, [azimuth], [R_down], anchor, height,
                                down, [q_work])
        if best is not None:
            return best, slide
        # Joint limits may forbid the work pose's azimuth or yaw (Z1's work pose reaches back over
        # its shoulder, 175 deg round, its first joint turns 150) or trap the IK seeded there:
        # the opposite azimuth, quarter turns of the yaw, seeds spread over the limits.
        seeds = [q_work] + list(np.random.default_rng(PRESS_SEED).uniform(
            np.maximum(model.lower, -np.pi), np.minimum(model.upper, np.pi),
            (PRESS_SEEDS, model.nq)))
        best = _best_press_pose(rig, settings, slide, q_work, [azimuth, -azimuth], yaws, anchor,
                                height, down, seeds)
    else:
        best = _best_press_pose(rig, settings, slide, q_work, [x_root, -x_root], yaws, anchor,
                                height, down, [q_work])
    if best is None:
        raise InputError(f"{rig.robot.name}: no tool-down pose from which the IK can follow a "
                         f"{slide:.3f} m slide along +x")
    return best, slide


PRESS_SEED, PRESS_SEEDS = 5, 8  # IK seeds beyond the work pose, when it finds no pose


def _best_press_pose(rig, settings, slide, q_work, azimuths, tools, anchor, height, down, seeds):
    """The best-conditioned q0 among the candidate tool positions (PRESS_RADII x PRESS_HEIGHTS at
    each azimuth) and orientations, the IK seeded from each seed, that reaches its pose, follows
    the slide and keeps the links clear of the floor; None when none does."""
    from .arm_targets import PoseProbe

    model = rig.model
    dyn, ik, probe = kl.Dynamics(model), kl.ArmIk(model), PoseProbe(rig.plant)
    best, best_score = None, -np.inf
    for radius, h, az, R_press in ((r, h, a, R) for r in PRESS_RADII for h in PRESS_HEIGHTS
                                   for a in azimuths for R in tools):
        T_press = np.eye(4)
        T_press[:3, :3] = R_press
        T_press[:3, 3] = anchor + az * radius * probe.reach - down * h * height
        for seed in seeds:
            q0, status = ik.solve(T_press, seed)
            if int(status) >= 0 and pose_reached(dyn, q0, T_press):
                break
        else:
            continue
        if not line_feasible(model, q0, [slide, 0.0, 0.0], [0.0, 0.0, 0.0],
                             float(settings["slide_time"]), probe=probe):
            continue
        probe.at(q0)
        if probe.floor_clearance() < 0.02 * probe.reach:
            continue
        score = probe.conditioning()
        if score > best_score:
            best, best_score = q0, score
    return best


def reach_of(rig) -> float:
    from .arm_targets import reach

    return reach(rig.plant)


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    del seed  # deterministic
    robot = robot or kl.Robot.load("ur5")
    axis = tool_axis(robot.model())
    tip = arm_scene.ToolTip(parent=robot.section("chain")["tip"], friction=settings["friction"],
                            offset=tuple(float(v) for v in 0.02 * axis))
    # Where the tip starts decides where the table goes: its top `gap` below the tip sphere.
    probe = Rig(robot, scene=tip)
    model = probe.model
    q0, slide = press_pose(probe, settings)
    settings = dict(settings, q0=q0.tolist(), slide=slide)
    if not np.allclose(probe.T_world_root()[:3, :3], np.eye(3), atol=1e-9):
        # The force axis and the slide are world z and x, the controller's the root's.
        raise InputError(f"arm-press: the chain root of {robot.name} must be level with the world")
    probe = probe.plant
    probe.reset(q0)
    tip_z = probe.data.xpos[probe.model.body(tip.body).id][2] - tip.radius
    top = tip_z - settings["gap"]
    p_ee0 = probe.ee_pose()[0]

    def scene(spec):
        spec.option.cone = _CONES[settings["cone"]]
        spec.option.noslip_iterations = int(settings["noslip_iterations"])
        tip(spec)
        arm_scene.add_table(spec, "table", [p_ee0[0], p_ee0[1], top], [0.4, 0.4],
                            friction=settings["friction"],
                            solref=settings["solref"] or None, solimp=settings["solimp"] or None)

    rig = Rig(robot, scene=scene, video=settings.get("video"))
    plant = rig.plant
    plant.q0 = q0
    plant.reset()
    with configuring(f"{NAME} controller"):
        # The tip's lowest point, where the table pushes, from the chain tip (root frame).
        R_tip = kl.Dynamics(model).forward_kinematics(q0)[:3, :3]
        contact = R_tip @ (np.asarray(tip.offset, float) + tip.radius * axis)
        coulomb = np.asarray(arm_defaults.joint_friction(robot, model).coulomb, float)
        controller = _make_controller(model, settings, q0, contact, coulomb)
    # Chain root frame = world orientation (checked above): the task axes are the root's.
    T0 = kl.Dynamics(model).forward_kinematics(q0)
    p0, R0 = T0[:3, 3].copy(), T0[:3, :3].copy()
    if settings["controller"] == "impedance":
        # No force loop: the spring alone presses, its set point F / K_z below the surface.
        k_z = kl.CartesianImpedanceConfig().stiffness[2]
        p0 = p0 - np.array([0.0, 0.0, settings["gap"] + settings["force"] / k_z])
    reference = Press(controller, tip, p0, R0, settings["force"], settings["settle"],
                      settings["slide"], settings["slide_time"])
    log = rig.run(DURATION if duration is None else duration, reference,
                  observe=native.Observe("ee"))
    t = log["t"]
    after = t >= settings["measure_from"]
    fz = -log["force"][:, 2]  # pressing force, positive down
    x_err = log["x_ref"] - log["ee"][:, 0]
    metrics = {
        "max_force_error_N": float(np.abs(fz[after] - settings["force"]).max()),
        "rms_force_error_N": float(np.sqrt(np.mean((fz[after] - settings["force"]) ** 2))),
        "mean_force_N": float(fz[after].mean()),
        "max_x_error_m": float(np.abs(x_err[after]).max()),
        "slide_m": float(log["ee"][-1, 0] - log["ee"][0, 0]),
        "slide_fraction": float((log["ee"][-1, 0] - log["ee"][0, 0]) / slide),
        "max_tangential_force_N": float(np.abs(log["force"][after][:, :2]).max()),
        "failed_ticks": int(np.sum(log["status"] < 0)),
        "saturated_ticks": int(np.sum(log["status"] == int(kl.Status.SATURATED))),
        "ticks": int(len(t)),
    }
    log.put("force_z", fz)
    log.put("x_err_mm", x_err * 1e3)
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    """What `--plot` draws for this scenario (scenarios/plots.py)."""
    return ARM_PRESS_PLOT
