"""arm-rrt: an arm moves between two configurations around a box that blocks the straight path.

Planning (C++): the links as capsules bounding the URDF collision geometry (primitives, or
capsules fitted to the collision meshes, or the robot file's [collision] capsules), the box and the floor
as obstacles, RRT-Connect in joint space (seeded, bounded), random shortcutting, then the
synchronized trapezoid within joint velocity/acceleration limits. Execution: computed torque tracks
the trajectory at 1 kHz on the MuJoCo plant, which has the same box; MuJoCo's own collision
detection must report no contact with it. `--set planner=straight` skips planning and runs the
straight joint-space trapezoid instead, which hits the box (the pytest checks that it does).
The loop runs in C++ (sil/rig.py): the box contacts and distance are native probes.
Any arm: from the work pose, the first joint turns by ROTATION (or back when its limits say so);
the box stands on the floor under the tool's mid-path position, as high as the tool is there, and
is shrunk until start and goal clear it by the margin (scenarios/arm_targets.py, this file's
derive()).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..errors import InputError, ScenarioRefused
from ..sil import arm_scene, native
from ..sil.arm_adapters import JointTracking
from ..sil.rig import Rig
from .arm_controllers import controller
from .arm_targets import link_capsules, reach, work_pose
from ..sil.log import SignalLog
from . import ScenarioResult, evaluate
from .plots import ARM_RRT_PLOT

NAME = "arm-rrt"
DESCRIPTION = "arm moves around a box: RRT-Connect + shortcut + trapezoid, no contact in MuJoCo"
HOLD = 0.5  # [s] simulated after the trajectory ends
DEFAULTS = {
    "planner": "rrt",               # or "straight" (no planning: goes through the box)
    # Empty: derived from the robot (see the module doc).
    "q_start": [],                  # [rad]
    "q_goal": [],                   # [rad]
    "box_center": [],               # [m] chain root frame (the plant's world when the root is)
    "box_half_extents": [],         # [m]
    "margin": 0.02,                 # [m] planning clearance to the box and the floor
    # [m] the planner's floor; None: 0, lowered just enough for links whose height no joint can
    # change (a shoulder turning about a vertical first joint) whose capsules reach below it.
    "floor_z": None,
    "max_iterations": 20000,        # RRT-Connect cap
    "shortcut_iterations": 300,
    "velocity_scale": 0.5,          # fraction of the URDF velocity limits
    "acceleration": 3.0,            # [rad/s^2] per joint
}
# Robot-file tables it reads (scenarios/__init__.py): the chain, the plant, the joint controller
# and the link capsules the planner checks.
ROBOT_KEYS = ("chain", "sim", "controller", "collision")
SIZES = {"q_start": "nq", "q_goal": "nq", "box_center": 3, "box_half_extents": 3}
# Settings' valid ranges (scenarios/__init__.py): a zero time or scale means nothing.
LIMITS = {"velocity_scale": (">", 0.0), "acceleration": (">", 0.0), "margin": (">=", 0.0),
          "max_iterations": (">", 0), "shortcut_iterations": (">=", 0)}
ROTATION = 2.0      # [rad] of the first joint between start and goal
BOX_WIDTH = 0.08    # of the reach: the box's half extent in x and y
CRITERIA = {
    "planned": (">=", 1),
    "box_contact_ticks": ("<", 1),          # MuJoCo: no contact with the box, ever
    "min_box_distance_m": (">", 0.0),       # MuJoCo's distance from any link to the box
    "final_joint_error_rad": ("<", 1e-3),   # reached the goal
}


def _floor_slab(top: float = 0.0):
    # The floor as a thick box under z = top for the planner (MuJoCo has its own plane at 0).
    return kl.OrientedBox(center=[0.0, 0.0, top - 0.5], half_extents=[5.0, 5.0, 0.5])


def make_checker(model, capsules, settings):
    """Link capsules (the fixed base left out: it cannot move), box + floor."""
    capsules = [c for c in capsules if c.link != model.root_name]
    box = kl.OrientedBox(center=settings["box_center"], half_extents=settings["box_half_extents"])
    floor = _floor_slab(float(settings.get("floor_z") or 0.0))
    return kl.ArmCollisionChecker(model, capsules, [box, floor], margin=settings["margin"])


def derive_targets(robot, model, capsules, plant, settings) -> dict:
    """Start, goal and box for a robot (what the settings leave empty). A derived start is the
    work pose (clear of the floor); when no box fits between it and its goal, the seeded poses
    near it that reach further out (START_CANDIDATES, the tool's distance from the first joint's
    axis first: the arc the arm sweeps, which the box must block, is longer there)."""
    s = dict(settings)
    if s["floor_z"] in (None, "", "none"):
        s["floor_z"] = _floor_below_fixed_links(plant, capsules, float(s["margin"]))
    given = bool(len(s["q_start"]))
    q_work = np.asarray(s["q_start"], float) if given else _planner_clear(
        model, capsules, work_pose(robot, model, plant), s)
    starts = [q_work]
    if not given and not len(s["q_goal"]):
        starts += _further_out(model, capsules, plant, q_work, s)
    for k, q_start in enumerate(starts):
        try:
            q_goal = _goal(robot, model, q_start) if not len(s["q_goal"]) else np.asarray(
                s["q_goal"], float)
        except ScenarioRefused:
            if k == 0:
                raise
            continue  # a candidate start whose first joint cannot turn: the next one
        out = dict(s, q_start=q_start.tolist(), q_goal=q_goal.tolist())
        if len(s["box_center"]) and len(s["box_half_extents"]):
            return out
        if _fit_box(model, capsules, plant, out, q_start, q_goal):
            return out
    raise ScenarioRefused(
        f"{robot.name}: no box fits between start and goal: {NAME} finds none that the links "
        f"clear by the {s['margin']} m margin (link capsules up to "
        f"{max(c.radius for c in capsules):.3f} m, reach {reach(plant):.3f} m; {len(starts)} "
        f"start poses tried)")


START_CANDIDATES = 200  # seeded poses near the work pose tried when it leaves no room for a box


def _further_out(model, capsules, plant, q_work, settings) -> list:
    """Seeded planner-clear poses near q_work (offsets within the limits, at most 1 rad per
    joint), those whose tool lies further from the first joint's axis than q_work's first."""
    from ..robot import arm as arm_defaults

    dyn = kl.Dynamics(model)
    far = dict(settings, box_center=[1e3, 1e3, 1e3], box_half_extents=[0.1, 0.1, 0.1])
    checker = make_checker(model, capsules, far)

    def radius(q):
        p = dyn.forward_kinematics(q)[:3, 3]
        return float(np.hypot(p[0], p[1]))

    down, up = arm_defaults.joint_range(model, q_work)
    rng = np.random.default_rng(11)
    scored = []
    for _ in range(START_CANDIDATES):
        q = q_work + rng.uniform(-down, up)
        if checker.clearance(q) > 0 and radius(q) > radius(q_work):
            scored.append((radius(q), q))
    return [q for _, q in sorted(scored, key=lambda rq: -rq[0])][:20]


def _goal(robot, model, q_start) -> np.ndarray:
    q_goal = q_start.copy()
    lo, up = np.asarray(model.lower)[0], np.asarray(model.upper)[0]
    q_goal[0] = q_start[0] + ROTATION if q_start[0] + ROTATION <= up else q_start[0] - ROTATION
    if q_goal[0] < lo:
        raise ScenarioRefused(f"{robot.name}: {NAME} turns the first joint by {ROTATION} rad; its "
                              f"range is {up - lo:.3f} rad")
    return q_goal


def _fit_box(model, capsules, plant, s, q_start, q_goal) -> bool:
    """Sets s's box: standing on the floor under the tool's mid-path position, as high as the
    tool, BOX_WIDTH of the reach wide, shrunk until start and goal clear it; False if none."""
    dyn = kl.Dynamics(model)
    tool = dyn.forward_kinematics(0.5 * (q_start + q_goal))[:3, 3]
    half = BOX_WIDTH * reach(plant)
    for _ in range(8):
        height = max(float(tool[2]), 2 * half)
        s["box_center"] = [float(tool[0]), float(tool[1]), height / 2.0]
        s["box_half_extents"] = [half, half, height / 2.0]
        checker = make_checker(model, capsules, s)
        if checker.clearance(q_start) > 0 and checker.clearance(q_goal) > 0:
            return True
        half *= 0.7
        tool = tool.copy()
        tool[2] *= 0.8
    return False


def _floor_below_fixed_links(plant, capsules, margin: float) -> float:
    """[m] 0, or lower: just below the capsules of links that only a vertical first joint moves
    (their height is no choice of the planner; a conservative capsule may reach the floor)."""
    from .arm_targets import PoseProbe

    m, d = plant.model, plant.data
    fixed = {m.body(b).name for b in PoseProbe.height_fixed_bodies(plant)}
    lowest = 0.0
    for c in capsules:
        if c.link not in fixed:
            continue
        b = m.body(c.link).id
        R, p = d.xmat[b].reshape(3, 3), d.xpos[b]
        z = min((R @ np.asarray(end, float) + p)[2] for end in (c.a, c.b)) - c.radius
        lowest = min(lowest, z - margin - 1e-3)
    return float(lowest)


def _planner_clear(model, capsules, q_near, settings, candidates: int = 400) -> np.ndarray:
    """q_near if the planner's capsules clear the floor there by the margin; else the seeded pose
    near it (offsets within the limits, at most 0.5 rad per joint) that clears it the most."""
    far = dict(settings, box_center=[1e3, 1e3, 1e3], box_half_extents=[0.1, 0.1, 0.1])
    checker = make_checker(model, capsules, far)
    if checker.clearance(q_near) > 0:
        return q_near
    rng = np.random.default_rng(7)
    lo, up = np.asarray(model.lower), np.asarray(model.upper)
    best, best_clear = q_near, checker.clearance(q_near)
    for _ in range(candidates):
        q = np.clip(q_near + rng.uniform(-0.5, 0.5, model.nq), lo, up)
        c = checker.clearance(q)
        if c > best_clear:
            best, best_clear = q, c
    return best


def plan(model, capsules, settings, seed: int):
    """(trajectory or None, PlanResult or None, checker) for the scenario's settings."""
    checker = make_checker(model, capsules, settings)
    q_start, q_goal = (np.asarray(settings[k], dtype=float) for k in ("q_start", "q_goal"))
    v_max = np.asarray(model.velocity_limit) * settings["velocity_scale"]
    a_max = np.full(model.nq, float(settings["acceleration"]))
    if settings["planner"] == "straight":
        return kl.TrapezoidTrajectory(np.vstack([q_start, q_goal]), v_max, a_max), None, checker
    if settings["planner"] != "rrt":
        raise InputError(f"planner: expected 'rrt' or 'straight', got {settings['planner']!r}")
    config = kl.RrtConfig()
    config.seed = seed
    config.max_iterations = int(settings["max_iterations"])
    config.shortcut_iterations = int(settings["shortcut_iterations"])
    # Joint space to search: the limits, at most +-pi (continuous joints).
    config.lower = np.maximum(np.asarray(model.lower), -np.pi)
    config.upper = np.minimum(np.asarray(model.upper), np.pi)
    result = kl.plan_trajectory(checker, config, q_start, q_goal, v_max, a_max)
    return result.trajectory, result, checker


def run(settings: dict, seed: int = 0, duration: float | None = None,
        robot=None) -> ScenarioResult:
    robot = robot or kl.Robot.load("ur5")
    probe = Rig(robot)  # no obstacle yet: derives the targets on the bare arm
    model = probe.model
    if not arm_scene.robot_geoms(probe.plant):
        raise ScenarioRefused(f"{robot.name}: {NAME} checks the links against the box in MuJoCo, "
                              f"and {robot.urdf.name} gives them no <collision> geometry")
    capsules = link_capsules(robot, model)
    settings = derive_targets(robot, model, capsules, probe.plant, settings)
    trajectory, result, checker = plan(model, capsules, settings, seed + 1)
    metrics = {"planned": int(trajectory is not None)}
    if result is not None:
        s = result.stats
        metrics.update({"plan_status": result.status.name, "plan_iterations": s.iterations,
                        "tree_nodes": s.tree_nodes, "raw_waypoints": s.raw_waypoints,
                        "waypoints": s.waypoints, "raw_path_length_rad": s.raw_length,
                        "path_length_rad": s.length, "collision_checks": s.collision_checks})
    if trajectory is None:
        return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), SignalLog(), dict(settings))

    T = probe.T_world_root()

    def scene(spec):
        center = T[:3, :3] @ np.asarray(settings["box_center"], float) + T[:3, 3]
        arm_scene.add_box(spec, "obstacle", center, settings["box_half_extents"])

    rig = Rig(robot, scene=scene, video=settings.get("video"))
    plant = rig.plant
    q_start = np.asarray(settings["q_start"], dtype=float)
    plant.q0 = q_start
    plant.reset()
    box = plant.model.geom("obstacle").id
    links = arm_scene.robot_geoms(plant)
    reference = JointTracking(controller(robot, model, "computed_torque", q_start), trajectory)

    total = trajectory.end_time + HOLD if duration is None else duration
    # Ground truth per tick, in C++: joint positions, MuJoCo's contacts with the box and the
    # smallest link-box distance (arm_scene.contacts_with, min_distance).
    probes = [native.contact_count("box_contacts", [box]),
              native.geom_distance("box_distance", box, links)]
    log = rig.run(total, reference, observe=native.Observe("q_true"), probes=probes)
    # What the planner's model says about the executed reference (capsules: conservative).
    planned_clearance = min(checker.clearance(q) for q in log["q_ref"][::10]) + settings["margin"]
    q_goal = np.asarray(settings["q_goal"], dtype=float)
    metrics.update({
        "trajectory_duration_s": trajectory.end_time,
        "box_contact_ticks": int(np.sum(log["box_contacts"] > 0)),
        "min_box_distance_m": float(np.min(log["box_distance"])),
        "min_planned_clearance_m": float(planned_clearance),
        "max_tracking_error_rad": float(np.abs(log["q_ref"] - log["q_true"]).max()),
        "final_joint_error_rad": float(np.abs(log["q_true"][-1] - q_goal).max()),
        "failed_ticks": int(np.sum(log["status"] < 0)),
        "ticks": int(len(log["t"])),
    })
    return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), log, dict(settings))


def plot_signals():
    """What `--plot` draws for this scenario (scenarios/plots.py)."""
    return ARM_RRT_PLOT
