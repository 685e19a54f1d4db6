"""A scenario file on an arm: the reference's waypoints (joint, or tool poses solved by the IK)
become one quintic joint trajectory that the robot file's computed-torque (or PD + gravity)
controller tracks in the native loop; an estop event puts the C++ ArmSupervisor between the
controller and the motors. The plant starts at rest at the first waypoint."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ...errors import InputError
from ...sil import native
from ...sil.arm_adapters import JointTrackingTick, SupervisedTick
from ...sil.arm_rig import ArmRig, controller
from ..arm_targets import work_pose
from ...sil.urdf_import import rpy_matrix
from . import common
from .events import Estop, Payload, Push

# Settings a scenario file's [settings] (and --set) may give for an arm.
DEFAULTS = {
    "controller": "computed_torque",  # or "pd_gravity"
    "physics_dt": 0.001,        # [s] MuJoCo timestep (divides the 1 ms control period)
    "measurement_delay": 0.0,   # [s] joint measurements reach the controller this late
    "motor_delay": 0.0,         # [s] torque commands reach the motors this late
    "motor_time_constant": 0.0,  # [s] first-order lag of the produced torque
    "q_sigma": 0.0,             # [rad] encoder white noise
    "qd_sigma": 0.0,            # [rad/s] velocity white noise
    "encoder_resolution": 0.0,  # [rad] quantization of q (0: none)
    # Plant-only joint damping [N m s/rad], Coulomb friction [N m], rotor inertia [kg m^2] the
    # controller does not know of; None: the robot file's own (which the controller compensates).
    "damping": None,
    "frictionloss": None,
    "armature": None,
    "stop_deceleration": 5.0,   # [rad/s^2] the supervisor's stopping ramp (estop events)
    "native": True,             # false: the per-tick Python loop (the same log, slower)
}
LAWS = ("computed_torque", "pd_gravity")


def waypoints(reference, model, rig) -> np.ndarray:
    """(k, nq) [rad] joint waypoints: the file's, or the IK's for the tool poses (each solved
    from the previous solution, the first from `q0` or the robot's work pose)."""
    names = list(model.joint_names)
    lo, hi = np.asarray(model.lower, float), np.asarray(model.upper, float)
    if reference.kind == "joint":
        q = reference.values["q"]
        if q.shape[1] != model.nq:
            raise InputError(f"reference.joint.q: rows of {q.shape[1]} values for an arm of "
                             f"{model.nq} joints ({', '.join(names)})")
        points = q
    else:
        seed = reference.values.get("q0")
        if seed is not None and len(seed) != model.nq:
            raise InputError(f"reference.cartesian.q0: {len(seed)} values for {model.nq} joints")
        seed = work_pose(rig.robot, model, rig.plant) if seed is None else seed
        dyn, ik = kl.Dynamics(model), kl.ArmIk(model)
        R_start = dyn.forward_kinematics(seed)[:3, :3]
        points = []
        for i, (xyz, rpy) in enumerate(zip(reference.values["xyz"], reference.values["rpy"])):
            T = np.eye(4)
            T[:3, :3] = R_start if np.isnan(rpy).any() else rpy_matrix(rpy)
            T[:3, 3] = xyz
            q, status = ik.solve(T, seed)
            if int(status) < 0:
                raise InputError(f"reference.cartesian.xyz[{i}]: the IK finds no joint "
                                 f"configuration within the limits for this pose ({status.name})")
            points.append(np.asarray(q, float))
            seed = points[-1]
        points = np.vstack(points)
    for i, row in enumerate(points):
        out = np.nonzero((row < lo - 1e-9) | (row > hi + 1e-9))[0]
        if len(out):
            j = out[0]
            key = "joint.q" if reference.kind == "joint" else "cartesian.xyz"
            raise InputError(f"reference.{key}[{i}]: {names[j]} at {row[j]:.4g} rad is outside its "
                             f"limits [{lo[j]:.4g}, {hi[j]:.4g}]")
    return points


def run(scenario, robot, settings: dict, seed: int, duration: float, video: str | None):
    """The run's log (family signals added) and the vector signals' component names."""
    if settings["controller"] not in LAWS:
        raise InputError(f"settings.controller: expected one of {', '.join(LAWS)}, got "
                         f"{settings['controller']!r}")
    plant_only = {k: None if settings[k] in (None, "", "none") else float(settings[k])
                  for k in ("damping", "frictionloss", "armature")}
    rig = ArmRig(robot, video=video, timestep=settings["physics_dt"], **plant_only)
    plant, model = rig.plant, rig.model
    points = waypoints(scenario.reference, model, rig)
    plant.q0 = points[0]
    plant.reset()
    trajectory = kl.QuinticTrajectory(points, np.asarray(scenario.reference.t, float))
    delay_ticks = common.ticks(settings["measurement_delay"])
    ctrl = controller(robot, model, settings["controller"], points[0], delay_ticks=delay_ticks)
    estops = [e for e in scenario.events if isinstance(e, Estop)]
    if estops:
        config = kl.ArmSupervisorConfig()
        config.stop_deceleration = np.array([float(settings["stop_deceleration"])])
        tick = SupervisedTick(ctrl, kl.ArmSupervisor(model, config), trajectory,
                              min(e.t for e in estops))
    else:
        tick = JointTrackingTick(ctrl, trajectory)
    nonideal = native.NonIdeal(q_sigma=float(settings["q_sigma"]),
                               qd_sigma=float(settings["qd_sigma"]),
                               encoder_resolution=float(settings["encoder_resolution"]),
                               motor_delay_ticks=common.ticks(settings["motor_delay"]),
                               motor_time_constant=float(settings["motor_time_constant"]),
                               seed=seed)
    tip = int(plant.model.site_bodyid[plant.model.site(plant.ee_site).id])
    forces, payloads = [], []
    for i, e in enumerate(scenario.events):
        if isinstance(e, (Push, Payload)):
            body = tip if e.body is None else common.body_id(plant.model, e.body,
                                                             f"events[{i}].body")
            if isinstance(e, Push):
                forces.append(native.force(e.t, body, [*e.force, 0.0, 0.0, 0.0], e.duration))
            else:
                payloads.append((common.ticks(e.t), body, e))
    stages = common.dropout_stages(scenario.events, {"joints": (0, 2 * model.nq)})
    observe = native.Observe("q_true", "qd_true", "ee")
    if not settings["native"]:
        if forces or payloads or stages:
            raise InputError("settings.native = false (the per-tick Python loop) runs "
                             "no push, payload or sensor_dropout events on an arm")
        log = rig.run(tick, duration, delay_ticks=delay_ticks, observe=observe, native=False,
                      nonideal=nonideal)
    else:
        r = native.rollout(plant, tick.native_adapter(), duration, delay_ticks=delay_ticks,
                           nonideal=nonideal, events=tick.native_events() + forces,
                           observe=observe, stages=stages)
        common.drive(r, plant.model, plant.data, payloads, video,
                     plant.model.body(model.root_name).id if model.root_name else 1)
        log = native.signal_log(r)
    return signals(log, rig, model), components(model)


def signals(log, rig, model):
    """The arm's signals (signals.ARM) into the log."""
    dyn, T = kl.Dynamics(model), rig.T_world_root()
    log.put_array("q_measured", log["q"])
    log.put_array("q", log["q_true"])
    log.put_array("qd_measured", log["qd"])
    log.put_array("qd", log["qd_true"])
    ee_ref = np.array([(T @ dyn.forward_kinematics(q))[:3, 3] for q in log["q_ref"]])
    log.put_array("ee_ref", ee_ref)
    log.put_array("joint_error", np.abs(log["q_ref"] - log["q"]).max(axis=1))
    log.put_array("ee_error", np.linalg.norm(log["ee"] - ee_ref, axis=1))
    if "mode" in log:
        log.put_array("estop_mode", log["mode"])
    return log


def components(model) -> dict:
    joints = list(model.joint_names)
    xyz = ["x", "y", "z"]
    return {"q": joints, "q_ref": joints, "qd": joints, "tau": joints, "ee": xyz, "ee_ref": xyz}
