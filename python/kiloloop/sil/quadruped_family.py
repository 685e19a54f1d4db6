"""The quadruped family of the SIL rig (sil/rig.py), as data (sil/family.py): the floating-base MuJoCo
plant and the compiled QuadrupedController from the robot file, the measurement y = [q (12); qd
(12); gyro (3); accel (3); quat (4)] (plant joint order, the IMU site's sensors; with ground_truth,
the trunk's position (3), quaternion (4) and velocity (3) follow), the command u = tau (12) (plant
order), the adapter on a CommandSchedule (cpp/sil/quadruped_adapter.hpp), pushes on the trunk, the
fall as a stop probe. No control logic here.
"""
from __future__ import annotations

import bisect
from dataclasses import dataclass

import numpy as np

import kiloloop as kl

from ..errors import InputError, configuring
from ..robot.quadruped import controller_config, plant_overlay
from . import events as ev
from . import native
from .floating_plant import FloatingBasePlant
from .legged_sensors import stages as legged_stages
from .family import CONTROL_DT, Family, Measurement, Motor

JOINTS = 12
IMU = 10  # gyro (3), accel (3), quat (4)


class CommandSchedule:
    """A piecewise-constant command as data: segments (start [s], gait 0/1, (vx, vy, yaw rate)),
    the first at 0; command(t) is the last segment with start <= t. The native loop gets the
    first at construction and the others as reference events."""

    def __init__(self, segments):
        self.segments = [(float(t), int(g), np.array(v, dtype=float)) for t, g, v in segments]
        if not self.segments or self.segments[0][0] != 0.0:
            raise ValueError("CommandSchedule: the first segment must start at 0")
        if any(b[0] < a[0] for a, b in zip(self.segments, self.segments[1:])):
            raise ValueError("CommandSchedule: segments must be in time order")
        self._starts = [t for t, _, _ in self.segments]

    def __call__(self, t: float) -> tuple[int, np.ndarray]:
        # The last segment with start <= t (a bisection: a sampled ramp has a segment a tick).
        k = bisect.bisect_right(self._starts, t) - 1
        current = self.segments[max(k, 0)]
        return current[1], current[2]

    def reference_events(self) -> list[tuple]:
        return [(t, ev.REFERENCE, [float(g), *map(float, v)]) for t, g, v in self.segments[1:]]


def stand_command() -> CommandSchedule:
    return CommandSchedule([(0.0, 0, np.zeros(3))])


@dataclass
class QuadrupedParts:
    robot: object
    model: object            # kl.RobotModel
    controller: object       # kl.QuadrupedController
    config: object           # its configuration, everything derived filled in
    plant: FloatingBasePlant
    to_ctrl: np.ndarray      # controller joint j is plant joint to_ctrl[j] (by name)
    to_plant: np.ndarray
    effort: np.ndarray       # [N m] plant order
    fall_height: float       # [m] below this trunk height the robot has fallen
    ground_truth: bool       # the controller reads the simulator's trunk state (debugging)

    def measurement_addresses(self) -> list[int]:
        p, imu = self.plant, self.plant._imu_adr
        return ([int(a) for a in p._pos_sens] + [int(a) for a in p._vel_sens]
                + list(range(imu["gyro"], imu["gyro"] + 3))
                + list(range(imu["accel"], imu["accel"] + 3))
                + list(range(imu["quat"], imu["quat"] + 4)))


def build(robot, signals, seed, options) -> QuadrupedParts:
    """options: slope_deg [deg] (a tilted ground), physics_dt [s], config (a kl.QuadrupedConfig;
    default from the robot file, designed for `design_delay` [s], default the signals'
    motor delay), terrain (callable(resolved config) -> a sil/terrain.py ground), ground_truth."""
    options = dict(options)
    slope_deg = float(options.pop("slope_deg", 0.0))
    physics_dt = options.pop("physics_dt", 0.001)
    config = options.pop("config", None)
    terrain = options.pop("terrain", None)
    ground_truth = bool(options.pop("ground_truth", False))
    design_delay = options.pop("design_delay", None)
    options.pop("visual", None)
    if options:
        raise TypeError(f"quadruped rig: unknown option(s) {', '.join(sorted(options))}")
    if signals.enabled and signals.quat_sigma > 0:
        raise InputError("quadruped rig: quat_sigma is not modelled; the realistic IMU "
                         "(Signals.legged_sensors) is the default")
    if config is None:
        delay = signals.on("motor_delay") if design_delay is None else float(design_delay)
        config = controller_config(robot, actuation_delay=delay)
    config.dt = CONTROL_DT
    # Realistic sensors: no orientation from the plant, the controller's attitude filter
    # estimates it from gyro + accelerometer. Ideal: the plant's as an exact external AHRS.
    estimator = config.estimator
    estimator.external_attitude = not signals.realistic_legged
    config.estimator = estimator
    # The safe-stop tilt is measured from vertical; on a slope the trunk starts tilted by it
    # (15 deg would trip the default 15 deg at once; measured: with it raised by the slope
    # both robots stand on 15 deg).
    config.max_tilt = config.max_tilt + float(np.deg2rad(abs(slope_deg)))
    model = robot.model()
    with configuring(f"{robot.name} quadruped controller"):
        controller = kl.QuadrupedController(model, config)
    config = controller.config
    plant = FloatingBasePlant(robot.urdf_doc, plant_overlay(robot, controller), timestep=physics_dt,
                              slope_deg=slope_deg, package_dirs=robot.package_dirs,
                              terrain=None if terrain is None else terrain(config))
    if plant.nq != JOINTS:
        raise InputError(f"quadruped rig: expected {JOINTS} joints, the plant has {plant.nq}")
    plant_index = {name: i for i, name in enumerate(plant.joint_names)}
    to_ctrl = np.array([plant_index[n] for n in controller.joint_names])
    to_plant = np.argsort(to_ctrl)
    return QuadrupedParts(robot=robot, model=model, controller=controller, config=config,
                          plant=plant, to_ctrl=to_ctrl, to_plant=to_plant,
                          effort=np.asarray(controller.effort_limit)[to_plant],
                          fall_height=0.5 * config.body_height, ground_truth=ground_truth)


def measurement(parts: QuadrupedParts, signals, seed: int, reference) -> Measurement:
    """y and its models: the realistic legged stages (encoder, MEMS IMU) or white IMU noise and
    encoder quantization from the sensor model; the ground truth appended untouched."""
    p = parts.plant
    addresses = parts.measurement_addresses()
    sources = [0] * len(addresses)
    if parts.ground_truth:
        addresses += (list(range(p._free_q, p._free_q + 7)) + list(range(p._free_d, p._free_d + 3)))
        sources += [1] * 7 + [2] * 3
    on, realistic = signals.enabled, signals.realistic_legged
    white = on and not realistic and (signals.gyro_sigma > 0 or signals.accel_sigma > 0)
    # The arrays cover the 34 sensor entries only: the ground truth passes untouched and draws
    # no noise (the stream is the same with and without it).
    sigma = ([0.0] * 2 * JOINTS + [signals.gyro_sigma] * 3 + [signals.accel_sigma] * 3
             + [0.0] * 4) if white else []
    quantum = ([signals.encoder_resolution] * JOINTS + [0.0] * (JOINTS + IMU)
               if on and not realistic and signals.encoder_resolution > 0 else [])
    stages = (legged_stages(signals.legged_sensors, joints=JOINTS, imu_offset=2 * JOINTS,
                            encoder_resolution=signals.encoder_resolution, seed=seed,
                            control_dt=CONTROL_DT) if realistic else [])
    return Measurement(addresses, sources, sigma, quantum, stages)


def motor(parts: QuadrupedParts, signals) -> Motor:
    limit = tuple(signals.torque_limit_scale * parts.effort) if signals.enabled else ()
    return Motor(delay_ticks=signals.ticks("motor_delay", CONTROL_DT), limit=limit)


def actuators(parts: QuadrupedParts) -> list[int]:
    return [int(a) for a in parts.plant._act]


def adapter(parts: QuadrupedParts, command: CommandSchedule, controller, ticks: int):
    gait, v = command.segments[0][1], command.segments[0][2]
    kwargs = {"ground_truth": True} if parts.ground_truth else {}
    return native._native.quadruped_adapter(controller or parts.controller,
                                            [int(i) for i in parts.to_ctrl], gait, v, **kwargs)


def reference_events(parts, command: CommandSchedule) -> list:
    return command.reference_events()


def events(parts: QuadrupedParts, timed) -> list:
    """Pushes on the trunk's CoM (whole physics steps, as FloatingBasePlant.apply_push)."""
    out = []
    for t, e in timed:
        if not isinstance(e, ev.Push):
            raise InputError(f"a quadruped run takes pushes as events, not {type(e).__name__}")
        body = parts.plant._base_id if e.body is None else _body(parts.plant, e.body)
        out.append(ev.force_event(t, body, [*e.force, 0.0, 0.0, 0.0], e.duration))
    return out


def _body(plant, body) -> int:
    return int(body) if isinstance(body, (int, np.integer)) else int(plant.model.body(body).id)


def probes(parts: QuadrupedParts, observe) -> list:
    """The trunk's ground truth, the feet's contact forces and positions."""
    p = parts.plant
    fq, fd = p._free_q, p._free_d
    return [("base_pos", native._QPOS, list(range(fq, fq + 3))),
            ("base_quat", native._QPOS, list(range(fq + 3, fq + 7))),
            ("base_vel", native._QVEL, list(range(fd, fd + 3))),
            ("base_omega", native._QVEL, list(range(fd + 3, fd + 6))),
            ("foot_force", native._CONTACT_FORCE, [int(i) for i in p._foot_ids]),
            ("foot_pos", native._SITES_POS, [int(i) for i in p._foot_sites])]


def stop(parts, condition) -> tuple | None:
    """A FellBelow as the stop probe: base_pos (probe 0), z (element 2)."""
    if condition is None:
        return None
    if not isinstance(condition, ev.FellBelow):
        raise InputError(f"a quadruped run stops on a FellBelow, not {type(condition).__name__}")
    return (0, 2, float(condition.height))


def camera_body(parts: QuadrupedParts) -> int:
    return int(parts.plant.model.body(parts.plant.base_body).id)


FAMILY = Family(name="quadruped", build=build, measurement=measurement, motor=motor,
                actuators=actuators, adapter=adapter, reference_events=reference_events,
                events=events, probes=probes, stop=stop, camera_body=camera_body)
