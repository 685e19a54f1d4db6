"""The multirotor family (with or without an arm) of the SIL rig (sil/rig.py), as data
(sil/family.py): the MuJoCo plant (sil/aerial_plant.py) and the compiled AerialController from the
robot file; the measurement y = [position (3); velocity (3); gyro (3); accel (3); quat (4); q (nq);
qd (nq)] (the body origin's position and velocity from the free joint, a motion-capture stand-in;
the IMU site's sensors; the arm's encoders, plant order); the command u = [thrust (rotors); tau
(nq)]; the adapter on a reference table (cpp/sil/aerial_adapter.hpp); pushes at the vehicle's CoM,
rotor faults as actuator-gain events, the wind a C++ disturbance. No control logic here.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import kiloloop as kl

from ..errors import InputError, configuring
from ..robot import Robot
from ..robot import aerial as aerial_robot
from . import events as ev
from . import native
from .aerial_plant import AerialPlant
from .aerial_signals import reference_table
from .family import CONTROL_DT, Family, Measurement, Motor

DEFAULT_ROBOT = "aerial_manipulator"


def load_robot(robot=None):
    """A loaded kl.Robot: `robot` itself, or a name / file, or kiloloop's aerial manipulator."""
    return robot if isinstance(robot, Robot) else Robot.load(robot or DEFAULT_ROBOT)


def aerial_paths():
    return kl.model_files(DEFAULT_ROBOT)


def rotor_config(robot=None) -> "kl.RotorAllocationConfig":
    """The controller's rotor settings from the robot file's [[rotors]] (where they live)."""
    return aerial_robot.rotor_config(load_robot(robot))


# The attitude-estimate noise's stream is the run seed's plus this (the white noise keeps its own).
ATTITUDE_STREAM = 1_000_003


@dataclass
class AerialParts:
    robot: object
    model: object            # kl.RobotModel of the arm (none: a bare vehicle)
    controller: object       # kl.AerialController
    config: object
    plant: AerialPlant
    n_rotors: int
    to_ctrl: np.ndarray      # controller arm joint j is plant joint to_ctrl[j]
    to_plant: np.ndarray
    hover_pos: np.ndarray    # [m] the body's start position


def build(robot, signals, seed, options) -> AerialParts:
    """options: physics_dt [s]; config (a kl.AerialConfig, default derived from the robot file);
    joint_friction (False: a frictionless arm plant); friction_compensation (the controller knows
    the arm's friction, the robot file's values); lag_compensation (rotor-lag lead); visual."""
    options = dict(options)
    physics_dt = options.pop("physics_dt", 0.001)
    config = options.pop("config", None)
    joint_friction = bool(options.pop("joint_friction", True))
    friction_compensation = bool(options.pop("friction_compensation", True))
    lag_compensation = bool(options.pop("lag_compensation", False))
    visual = bool(options.pop("visual", False))
    if options:
        raise TypeError(f"aerial rig: unknown option(s) {', '.join(sorted(options))}")
    kw = {} if joint_friction else {"damping": 0.0, "frictionloss": 0.0}
    plant = AerialPlant.from_robot(robot, timestep=physics_dt, visual=visual, **kw)
    model = aerial_robot.model(robot)
    config = aerial_robot.config(robot) if config is None else config
    config.dt = CONTROL_DT
    if joint_friction and friction_compensation and plant.nq:
        # The arm's friction as identified: the robot file's values (what the plant simulates).
        joints = robot.sim.get("joints", {})
        for field_name, key in (("arm_viscous", "damping"), ("arm_coulomb", "frictionloss")):
            value = joints.get(key)
            if value is not None:
                setattr(config, field_name, np.atleast_1d(np.asarray(value, dtype=float)))
    rotors = config.rotors
    rotors.lag_compensation = lag_compensation
    config.rotors = rotors
    with configuring(f"{robot.name} aerial controller"):
        controller = kl.AerialController(model, config)
    plant_index = {name: i for i, name in enumerate(plant.joint_names)}
    names = list(model.joint_names) if controller.nq else []
    to_ctrl = np.array([plant_index[n] for n in names], dtype=int)
    return AerialParts(robot=robot, model=model, controller=controller, config=config,
                       plant=plant, n_rotors=controller.n_rotors, to_ctrl=to_ctrl,
                       to_plant=np.argsort(to_ctrl), hover_pos=plant.base_pos0.copy())


def measurement(parts: AerialParts, signals, seed: int, reference) -> Measurement:
    """y, its white noise (motion capture, IMU), encoder quantization and the attitude-estimate
    noise stage (cpp/sil/attitude_noise.hpp) on the quaternion."""
    p, imu, nq = parts.plant, parts.plant._imu_adr, parts.plant.nq
    addresses = (list(range(p._free_q, p._free_q + 3)) + list(range(p._free_d, p._free_d + 3))
                 + list(range(imu["gyro"], imu["gyro"] + 3))
                 + list(range(imu["accel"], imu["accel"] + 3))
                 + list(range(imu["quat"], imu["quat"] + 4))
                 + [int(a) for a in p._pos_sens] + [int(a) for a in p._vel_sens])
    sources = [1] * 3 + [2] * 3 + [0] * (10 + 2 * nq)
    s, size = signals, 16 + 2 * nq
    noise = ([s.position_sigma] * 3 + [s.velocity_sigma] * 3 + [s.gyro_sigma] * 3
             + [s.accel_sigma] * 3 + [0.0] * (4 + 2 * nq))
    sigma = noise if s.enabled and any(x > 0 for x in noise) else []
    quantum = ([0.0] * 16 + [s.encoder_resolution] * nq + [0.0] * nq
               if s.enabled and s.encoder_resolution > 0 and nq else [])
    quat_sigma = s.on("quat_sigma")
    stages = ([native._native.AttitudeNoise(12, quat_sigma, int(seed) + ATTITUDE_STREAM, size)]
              if quat_sigma > 0 else [])
    return Measurement(addresses, sources, sigma, quantum, stages)


def motor(parts, signals) -> Motor:
    # An ESC holds the first command until the delay has passed (no start-up sag).
    return Motor(delay_ticks=signals.ticks("motor_delay", CONTROL_DT), hold_first=True)


def actuators(parts: AerialParts) -> list[int]:
    return [int(a) for a in parts.plant._rotor_act] + [int(a) for a in parts.plant._act]


def adapter(parts: AerialParts, command, controller, ticks: int):
    """command(t, input) sampled into the adapter's reference table (a Hold: one row)."""
    controller = controller or parts.controller
    table = reference_table(controller, command, max(int(ticks), 1))
    return native._native.aerial_adapter(controller, [int(i) for i in parts.to_ctrl], table)


def reference_events(parts, command) -> list:
    return []


def events(parts: AerialParts, timed) -> list:
    """Pushes at the vehicle's CoM (the base's subtree CoM), rotor faults as gain events."""
    p, out = parts.plant, []
    for t, e in timed:
        if isinstance(e, ev.Push):
            if e.body is not None:
                raise InputError("a multirotor's pushes act at the vehicle's CoM (no body)")
            out.append(ev.force_event(t, p._base_id, [*e.force, 0.0, 0.0, 0.0], e.duration,
                                      at_subtree_com=True))
        elif isinstance(e, ev.RotorFault):
            if not 0 <= e.rotor < parts.n_rotors:
                raise InputError(f"rotor: expected 0..{parts.n_rotors - 1}, got {e.rotor}")
            out.append((float(t), ev.GAIN, [float(p._rotor_act[e.rotor]), float(e.efficiency)]))
        else:
            raise InputError(f"a multirotor run takes pushes and rotor faults as events, not "
                             f"{type(e).__name__}")
    return out


def probes(parts: AerialParts, observe) -> list:
    """The vehicle's ground truth, the rotors' thrusts, the arm and its end effector."""
    p = parts.plant
    fq, fd, b = p._free_q, p._free_d, int(p._base_id)
    ee = ([("ee_pos", native._SITE_POS, [int(p._ee_site)]),
           ("ee_rot", native._SITE_MAT, [int(p._ee_site)])] if p._ee_site is not None
          else [("ee_pos", native._BODY_POS, [b]), ("ee_rot", native._BODY_MAT, [b])])
    return [("base_pos", native._QPOS, list(range(fq, fq + 3))),
            ("com", native._SUBTREE_COM, [b]),
            ("base_quat", native._QPOS, list(range(fq + 3, fq + 7))),
            ("base_vel", native._QVEL, list(range(fd, fd + 3))),
            ("base_omega", native._QVEL, list(range(fd + 3, fd + 6))),
            ("thrust", native._ACTUATOR_FORCE, [int(a) for a in p._rotor_act]),
            ("q", native._SENSOR, [int(p._pos_sens[i]) for i in parts.to_ctrl]),
            *ee]


def stop(parts, condition) -> None:
    if condition is not None:
        raise InputError("a multirotor run stops only when its physics diverges")
    return None


def camera_body(parts: AerialParts) -> int:
    return int(parts.plant._base_id)


FAMILY = Family(name="aerial", build=build, measurement=measurement, motor=motor,
                actuators=actuators, adapter=adapter, reference_events=reference_events,
                events=events, probes=probes, stop=stop, camera_body=camera_body,
                stop_nonfinite=True)
