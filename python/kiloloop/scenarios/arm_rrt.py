"""arm-rrt: the UR5 moves between two configurations around a box that blocks the straight path.

Planning (C++): the links as capsules bounding the URDF collision cylinders, the box and the floor
as obstacles, RRT-Connect in joint space (seeded, bounded), random shortcutting, then the
synchronized trapezoid within joint velocity/acceleration limits. Execution: computed torque tracks
the trajectory at 1 kHz on the MuJoCo plant, which has the same box; MuJoCo's own collision
detection must report no contact with it. `--set planner=straight` skips planning and runs the
straight joint-space trapezoid instead, which hits the box (the pytest checks that it does).
"""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ..sil import arm_scene
from ..sil.log import SignalLog
from ..sil.loop import LoopSettings, run_loop
from ..sil.plant import MujocoPlant
from . import ScenarioResult, evaluate
from ..sil.arm_adapters import JointTrackingTick

NAME = "arm-rrt"
DESCRIPTION = "UR5 moves around a box: RRT-Connect + shortcut + trapezoid, no contact in MuJoCo"
HOLD = 0.5  # [s] simulated after the trajectory ends
DEFAULTS = {
    "planner": "rrt",               # or "straight" (no planning: goes through the box)
    "q_start": [-1.0, -1.2, 1.6, -1.97, -1.57, 0.0],   # [rad] tool down, left of the box
    "q_goal": [1.0, -1.2, 1.6, -1.97, -1.57, 0.0],     # [rad] mirrored, right of it
    "box_center": [-0.55, -0.1, 0.2],   # [m] world frame (= UR5 base frame)
    "box_half_extents": [0.1, 0.1, 0.2],  # [m] standing on the floor, 40 cm tall
    "margin": 0.02,                 # [m] planning clearance to the box and the floor
    "max_iterations": 20000,        # RRT-Connect cap
    "shortcut_iterations": 300,
    "velocity_scale": 0.5,          # fraction of the URDF velocity limits
    "acceleration": 3.0,            # [rad/s^2] per joint
}
CRITERIA = {
    "planned": (">=", 1),
    "box_contact_ticks": ("<", 1),          # MuJoCo: no contact with the box, ever
    "min_box_distance_m": (">", 0.0),       # MuJoCo's distance from any link to the box
    "final_joint_error_rad": ("<", 1e-3),   # reached the goal
}


def _floor_slab():
    # The floor as a thick box under z = 0 for the planner (MuJoCo has its own plane).
    return kl.OrientedBox(center=[0.0, 0.0, -0.5], half_extents=[5.0, 5.0, 0.5])


def make_checker(model, urdf, settings):
    """Capsules from the URDF (the fixed base left out: it cannot move), box + floor."""
    capsules = [c for c in kl.capsules_from_urdf(str(urdf), model) if c.link != model.root_name]
    box = kl.OrientedBox(center=settings["box_center"], half_extents=settings["box_half_extents"])
    return kl.ArmCollisionChecker(model, capsules, [box, _floor_slab()], margin=settings["margin"])


def plan(model, urdf, settings, seed: int):
    """(trajectory or None, PlanResult or None, checker) for the scenario's settings."""
    checker = make_checker(model, urdf, settings)
    q_start, q_goal = (np.asarray(settings[k], dtype=float) for k in ("q_start", "q_goal"))
    v_max = np.asarray(model.velocity_limit) * settings["velocity_scale"]
    a_max = np.full(model.nq, float(settings["acceleration"]))
    if settings["planner"] == "straight":
        return kl.TrapezoidTrajectory(np.vstack([q_start, q_goal]), v_max, a_max), None, checker
    if settings["planner"] != "rrt":
        raise ValueError(f"planner: expected 'rrt' or 'straight', got {settings['planner']!r}")
    config = kl.RrtConfig()
    config.seed = seed
    config.max_iterations = int(settings["max_iterations"])
    config.shortcut_iterations = int(settings["shortcut_iterations"])
    config.lower = np.full(model.nq, -np.pi)
    config.upper = np.full(model.nq, np.pi)
    result = kl.plan_trajectory(checker, config, q_start, q_goal, v_max, a_max)
    return result.trajectory, result, checker


def run(settings: dict, seed: int = 0, duration: float | None = None) -> ScenarioResult:
    urdf, overlay = kl.model_files("ur5")
    model = kl.RobotModel.from_urdf(str(urdf))
    trajectory, result, checker = plan(model, urdf, settings, seed + 1)
    metrics = {"planned": int(trajectory is not None)}
    if result is not None:
        s = result.stats
        metrics.update({"plan_status": result.status.name, "plan_iterations": s.iterations,
                        "tree_nodes": s.tree_nodes, "raw_waypoints": s.raw_waypoints,
                        "waypoints": s.waypoints, "raw_path_length_rad": s.raw_length,
                        "path_length_rad": s.length, "collision_checks": s.collision_checks})
    if trajectory is None:
        return ScenarioResult(NAME, metrics, evaluate(CRITERIA, metrics), SignalLog(), dict(settings))

    def scene(spec):
        arm_scene.add_box(spec, "obstacle", settings["box_center"], settings["box_half_extents"])

    plant = MujocoPlant(urdf, overlay, scene=scene)
    q_start = np.asarray(settings["q_start"], dtype=float)
    plant.reset(q_start)
    box = plant.model.geom("obstacle").id
    links = arm_scene.robot_geoms(plant)
    config = kl.ComputedTorqueConfig()
    config.kp, config.kd = np.array([900.0]), np.array([60.0])
    tick = JointTrackingTick(kl.ComputedTorqueController(model, config), trajectory)

    def observe(p: MujocoPlant, log: SignalLog) -> None:
        log.record("q_true", p.q())
        log.record("box_contacts", arm_scene.contacts_with(p, box))
        log.record("box_distance", arm_scene.min_distance(p, box, links))

    total = trajectory.end_time + HOLD if duration is None else duration
    log = run_loop(plant, tick, LoopSettings(duration=total), observe=observe)
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
    return [("joint position", "q_true", "q_ref", "rad"),
            ("distance links-box (MuJoCo)", "box_distance", None, "m"),
            ("joint torque", "tau", None, "N m")]
