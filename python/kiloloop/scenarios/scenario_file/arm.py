"""A scenario file on an arm: the reference's waypoints (joint, or tool poses solved by the IK)
become one quintic joint trajectory that the robot file's computed-torque (or PD + gravity)
controller tracks in the native loop; an estop event puts the C++ ArmSupervisor between the
controller and the motors. The plant starts at rest at the first waypoint."""
from __future__ import annotations

import numpy as np

import kiloloop as kl

from ...errors import InputError
from ...sil import native
from ...sil import events as sil_events
from ...sil.arm_adapters import JointTracking, Supervised
from ...sil.rig import Rig
from ...sil.signals import Signals
from ..arm_controllers import controller
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
    chain = Signals(q_sigma=float(settings["q_sigma"]), qd_sigma=float(settings["qd_sigma"]),
                    encoder_resolution=float(settings["encoder_resolution"]),
                    measurement_delay=float(settings["measurement_delay"]),
                    motor_delay=float(settings["motor_delay"]),
                    motor_time_constant=float(settings["motor_time_constant"]))
    rig = Rig(robot, chain, seed=seed, video=video, physics_dt=settings["physics_dt"],
              **plant_only)
    plant, model = rig.plant, rig.model
    points = waypoints(scenario.reference, model, rig)
    plant.q0 = points[0]
    plant.reset()
    trajectory = kl.QuinticTrajectory(points, np.asarray(scenario.reference.t, float))
    ctrl = controller(robot, model, settings["controller"], points[0],
                      measurement_delay=common.ticks(settings["measurement_delay"]) * common.CONTROL_DT)
    estops = [e for e in scenario.events if isinstance(e, Estop)]
    if estops:
        config = kl.ArmSupervisorConfig()
        config.stop_deceleration = np.array([float(settings["stop_deceleration"])])
        reference = Supervised(ctrl, kl.ArmSupervisor(model, config), trajectory,
                               min(e.t for e in estops))
    else:
        reference = JointTracking(ctrl, trajectory)
    tip = int(plant.model.site_bodyid[plant.model.site(plant.ee_site).id])
    events, payloads = [], []
    for i, e in enumerate(scenario.events):
        if isinstance(e, (Push, Payload)):
            body = tip if e.body is None else common.body_id(plant.model, e.body,
                                                             f"events[{i}].body")
            if isinstance(e, Push):
                events.append((e.t, sil_events.Push(e.force, e.duration, body=body)))
            else:
                payloads.append((common.ticks(e.t), body, e))
    stages = common.dropout_stages(scenario.events, {"joints": (0, 2 * model.nq)})
    log = rig.run(duration, reference, events, observe=native.Observe("q_true", "qd_true", "ee"),
                  stages=stages, hooks=common.payload_hooks(payloads))
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
