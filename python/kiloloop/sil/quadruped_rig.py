"""SIL rig for the quadruped: MuJoCo floating-base plant + non-idealities + the compiled
QuadrupedController, at 1 kHz. Scenarios (python/kiloloop/scenarios/quadruped_*.py) script the
commands and disturbances and judge the log; this file only moves data (no control logic).

Two loops, one log: by default the closed loop runs in C++ (sil/native.py, cpp/sil/
quadruped_adapter.hpp) when the command is a CommandSchedule, the events are Push-es and the stop
condition a FellBelow (all data); otherwise, or with native=False or ground truth, it runs
per tick in Python. Both call the same C++ sensor model (noise, quantization: one normal per
element of y = [q; qd; gyro; accel; quat] per tick from the seed's xoshiro stream), the same C++
measurement stages (realistic sensors, sil/legged_sensors.py: MEMS IMU with bias, encoder-difference
joint velocity) and motor model (transport delay, saturation), so they give the same log
(tests/test_native_quadruped.py).
"""
from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

import kiloloop as kl

from ..robot.quadruped import controller_config, plant_overlay
from ..errors import InputError, configuring
from . import native as native_loop
from .floating_plant import FloatingBasePlant
from .legged_sensors import LeggedSensorSettings, stages as sensor_stages
from .log import SignalLog
from .nonideal import NonIdealities
from .timing import substeps, whole_periods

CONTROL_DT = 0.001  # [s]
JOINTS = 12


@dataclass
class RigSettings:
    slope_deg: float = 0.0
    physics_dt: float = 0.001
    nonideal: NonIdealities = field(default_factory=NonIdealities)
    # Realistic sensors unless sensors.ideal (only with nonideal.enabled; sil/legged_sensors.py).
    sensors: LeggedSensorSettings = field(default_factory=LeggedSensorSettings)
    ground_truth: bool = False     # controller runs on the simulator's state (debugging only)
    config: object = None          # kl.QuadrupedConfig; None = from the robot file
    video: str | None = None       # MP4 path: render the run
    # Ground other than a plane (sil/terrain.py), made from the resolved controller config so
    # that its sizes follow the robot (e.g. stone heights from the swing height).
    terrain: Callable[[object], object] | None = None
    native: bool = True            # the C++ loop where the run allows it (runs_natively)


def quadruped_paths():
    return kl.model_files("quadruped")


def default_robot():
    return kl.Robot.load("quadruped")


# command(t) -> (gait 0/1, velocity command (3,)); events: (time [s], action(plant)) run once.
CommandFn = Callable[[float], tuple[int, np.ndarray]]


class CommandSchedule:
    """A piecewise-constant command as data: segments (start [s], gait 0/1, (vx, vy, yaw rate)),
    the first at 0; command(t) is the last segment with start <= t. Both loops understand it (the
    native one as reference events)."""

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
        return [(t, native_loop.REFERENCE, [float(g), *map(float, v)]) for t, g, v in self.segments[1:]]


def stand_command() -> CommandSchedule:
    return CommandSchedule([(0.0, 0, np.zeros(3))])


@dataclass
class Push:
    """Event action: a constant world-frame force (3,) [N] on the trunk CoM for duration [s]
    (FloatingBasePlant.apply_push); data, so the native loop runs it as a force event."""

    force: np.ndarray
    duration: float

    def __call__(self, plant) -> None:
        plant.apply_push(self.force, self.duration)


def push_event(time: float, force, duration: float) -> tuple:
    return (float(time), Push(np.asarray(force, dtype=float), float(duration)))


@dataclass
class FellBelow:
    """stop_when: the run ends once the logged trunk height drops below `height` [m]."""

    height: float

    def __call__(self, log: SignalLog) -> bool:
        return bool(log.last("base_pos")[2] < self.height)


class QuadrupedSignals:
    """The quadruped's sensor and motor models over the flat signal vectors both loops share:
    y = [q (12); qd (12); gyro (3); accel (3); quat (4)] (plant joint order), u = tau (12)."""

    def __init__(self, nonideal: NonIdealities, seed: int, effort: np.ndarray,
                 sensors: LeggedSensorSettings | None = None):
        nonideal.validate()
        if nonideal.enabled and (nonideal.quat_sigma > 0 or nonideal.velocity_from_encoder_diff):
            raise InputError("quadruped rig: quat_sigma and velocity_from_encoder_diff are not "
                             "modelled; realistic sensors (sil/legged_sensors.py) are the default")
        on = nonideal.enabled
        self.sensors = sensors if sensors is not None else LeggedSensorSettings()
        # Realistic: the stages own the IMU and the encoders (the sensor model stays identity).
        self.realistic = on and not self.sensors.ideal
        self.encoder_resolution = nonideal.encoder_resolution if on else 0.0
        self.seed = int(seed) if seed is not None else 0
        white = on and not self.realistic and (nonideal.gyro_sigma > 0 or nonideal.accel_sigma > 0)
        self.sigma = ([0.0] * 2 * JOINTS + [nonideal.gyro_sigma] * 3 + [nonideal.accel_sigma] * 3
                      + [0.0] * 4) if white else []
        self.quantum = ([nonideal.encoder_resolution] * JOINTS + [0.0] * (JOINTS + 10)
                        if on and not self.realistic and nonideal.encoder_resolution > 0 else [])
        # Whole ticks, half up, as nonideal.MotorDelay.
        self.motor_delay_ticks = (whole_periods(nonideal.motor_delay)
                                  if on else 0)
        self.motor_limit = list(nonideal.torque_limit_scale * np.asarray(effort, float)) if on else []

    def sensor(self):
        return native_loop._native.SensorModel(self.sigma, self.quantum, self.seed, 2 * JOINTS + 10)

    def stages(self, seed: int | None = None) -> list:
        """Fresh measurement stages for one run (each run owns its own: state, random stream)."""
        if not self.realistic:
            return []
        return sensor_stages(self.sensors, joints=JOINTS, imu_offset=2 * JOINTS,
                             encoder_resolution=self.encoder_resolution,
                             seed=self.seed if seed is None else int(seed), control_dt=CONTROL_DT)

    def motor(self):
        return native_loop._native.MotorModel(self.motor_delay_ticks, 0.0, CONTROL_DT, JOINTS,
                                              self.motor_limit)


class QuadrupedRig:
    def __init__(self, settings: RigSettings, seed: int = 0, robot=None):
        self.robot = default_robot() if robot is None else robot
        self.settings = settings
        self.model = self.robot.model()
        delay = settings.nonideal.motor_delay if settings.nonideal.enabled else 0.0
        config = (settings.config if settings.config is not None
                  else controller_config(self.robot, actuation_delay=delay))
        config.dt = CONTROL_DT
        # Realistic sensors: no orientation from the plant, the controller's attitude filter
        # estimates it from gyro + accelerometer. Ideal: the plant's as an exact external AHRS.
        realistic = settings.nonideal.enabled and not settings.sensors.ideal
        estimator = config.estimator
        estimator.external_attitude = not realistic
        config.estimator = estimator
        # The safe-stop tilt is measured from vertical; on a slope the trunk starts tilted by it
        # (15 deg would trip the default 15 deg at once; measured: with it raised by the slope
        # both robots stand on 15 deg).
        config.max_tilt = config.max_tilt + float(np.deg2rad(abs(settings.slope_deg)))
        with configuring(f"{self.robot.name} quadruped controller"):
            self.controller = kl.QuadrupedController(self.model, config)
        self.config = self.controller.config  # everything derived filled in
        # Below this trunk height the robot has fallen (half its standing height).
        self.fall_height = 0.5 * self.config.body_height
        self.plant = FloatingBasePlant(self.robot.urdf, plant_overlay(self.robot, self.controller),
                                       timestep=settings.physics_dt, slope_deg=settings.slope_deg,
                                       package_dirs=self.robot.package_dirs,
                                       terrain=None if settings.terrain is None
                                       else settings.terrain(self.config))
        if self.plant.nq != JOINTS:
            raise InputError(f"quadruped rig: expected {JOINTS} joints, the plant has {self.plant.nq}")
        # Joint order: the controller's (leg-major) vs the plant's (URDF); mapped by name.
        plant_index = {name: i for i, name in enumerate(self.plant.joint_names)}
        self.to_ctrl = np.array([plant_index[n] for n in self.controller.joint_names])
        self.to_plant = np.argsort(self.to_ctrl)
        self.effort = np.asarray(self.controller.effort_limit)[self.to_plant]
        self.signals = QuadrupedSignals(settings.nonideal, seed, self.effort, settings.sensors)
        self.substeps = substeps(self.plant.timestep)
        self.input, self.output = kl.QuadrupedInput(), kl.QuadrupedOutput()

    # --- the native loop ---------------------------------------------------------------------

    def runs_natively(self, command, events=(), stop_when=None, native: bool | None = None) -> bool:
        """Whether run() takes the C++ loop: asked for, built in, no ground truth, and command,
        events and stop condition given as data (a video's frames are captured between ticks)."""
        native = self.settings.native if native is None else native
        return (native is not False and native_loop.available()
                and not self.settings.ground_truth and isinstance(command, CommandSchedule)
                and all(isinstance(action, Push) for _, action in events)
                and (stop_when is None or isinstance(stop_when, FellBelow)))

    def native_adapter(self, command: CommandSchedule, controller=None):
        gait, v = command.segments[0][1], command.segments[0][2]
        return native_loop._native.quadruped_adapter(controller or self.controller,
                                                     [int(i) for i in self.to_ctrl], gait, v)

    def native_probes(self) -> list[tuple]:
        """The ground truth QuadrupedRig._record logs, as native probes."""
        p = self.plant
        fq, fd = p._free_q, p._free_d
        feet = [int(i) for i in p._foot_ids]
        return [("base_pos", native_loop._QPOS, list(range(fq, fq + 3))),
                ("base_quat", native_loop._QPOS, list(range(fq + 3, fq + 7))),
                ("base_vel", native_loop._QVEL, list(range(fd, fd + 3))),
                ("base_omega", native_loop._QVEL, list(range(fd + 3, fd + 6))),
                ("foot_force", native_loop._CONTACT_FORCE, feet),
                ("foot_pos", native_loop._SITES_POS, [int(i) for i in p._foot_sites])]

    def native_rollout(self, duration: float, command: CommandSchedule, events=(), stop_when=None,
                       data=None, adapter=None, seed: int | None = None, stages=()):
        """A configured native Rollout of this rig (data: another MjData of plant.model for a
        batch, a new one starting at the plant's state (native.start_state); adapter: one built
        on another controller; seed: another noise stream than the rig's; stages: more C++
        measurement stages after the rig's own, a sensor dropout)."""
        native_loop.check()
        p, s = self.plant, self.signals
        forces = [native_loop.force(t, p._base_id, [*a.force, 0.0, 0.0, 0.0], a.duration)
                  for t, a in events]
        stop = (0, 2, float(stop_when.height)) if stop_when is not None else None
        return native_loop._native.Rollout(
            p.model, native_loop.start_state(p, data),
            adapter if adapter is not None else self.native_adapter(command),
            ticks=native_loop.ticks_of(duration, CONTROL_DT), control_dt=CONTROL_DT,
            measurement=self.measurement_addresses(), actuators=[int(a) for a in p._act],
            sigma=s.sigma, quantum=s.quantum, seed=s.seed if seed is None else int(seed),
            motor_delay_ticks=s.motor_delay_ticks, motor_limit=s.motor_limit,
            events=command.reference_events() + forces, probes=self.native_probes(), stop=stop,
            stages=s.stages(seed) + list(stages))

    def measurement_addresses(self) -> list[int]:
        p, imu = self.plant, self.plant._imu_adr
        return ([int(a) for a in p._pos_sens] + [int(a) for a in p._vel_sens]
                + list(range(imu["gyro"], imu["gyro"] + 3)) + list(range(imu["accel"], imu["accel"] + 3))
                + list(range(imu["quat"], imu["quat"] + 4)))

    # --- run -----------------------------------------------------------------------------------

    def run(self, duration: float, command: CommandFn, events=(), log: SignalLog | None = None,
            stop_when: Callable[[SignalLog], bool] | None = None,
            native: bool | None = None) -> SignalLog:
        """The closed loop for `duration` [s]: in C++ when runs_natively() (native None: the
        settings' choice), else per tick in Python; the same log either way."""
        log = SignalLog() if log is None else log
        if self.runs_natively(command, events, stop_when, native):
            r = self.native_rollout(duration, command, events, stop_when)
            p = self.plant
            native_loop.drive(r, p.model, p.data, video=self.settings.video,
                              camera_body=p.model.body(p.base_body).id)
            return native_loop.signal_log(r, log)
        from .video import maybe_recorder

        pending = sorted(events, key=lambda e: e[0])
        plant = self.plant
        recorder = maybe_recorder(self.settings.video, plant.model, body=plant.model.body(plant.base_body).id)
        try:
            self._loop(duration, command, pending, log, stop_when, recorder)
        finally:
            if recorder is not None:
                recorder.close()
        return log

    def _loop(self, duration, command, pending, log, stop_when, recorder):
        inp, out, plant = self.input, self.output, self.plant
        sensor, motor, stages = self.signals.sensor(), self.signals.motor(), self.signals.stages()
        for stage in stages:
            stage.configure(2 * JOINTS + 10)
        n = JOINTS
        for k in range(whole_periods(duration)):
            t = k * CONTROL_DT
            while pending and pending[0][0] <= t + 1e-12:
                pending.pop(0)[1](plant)
            imu = plant.imu()
            y = sensor.apply(np.concatenate([plant.joint_q(), plant.joint_qd(), imu["gyro"],
                                             imu["accel"], imu["quat"]]))
            for stage in stages:
                y = stage.apply(t, y)
            inp.t = inp.stamp = t
            inp.q[:], inp.qd[:] = y[:n][self.to_ctrl], y[n:2 * n][self.to_ctrl]
            inp.gyro[:], inp.accel[:], inp.quat[:] = y[2 * n:2 * n + 3], y[2 * n + 3:2 * n + 6], y[2 * n + 6:]
            gait, v_cmd = command(t)
            inp.gait, inp.velocity_command[:] = kl.Gait(int(gait)), v_cmd
            pos, quat = plant.base_pose()
            vel, omega = plant.base_velocity()
            if self.settings.ground_truth:
                inp.use_ground_truth = True
                inp.true_position[:], inp.true_velocity[:], inp.true_quat[:] = pos, vel, quat
            status = self.controller.step(inp, out)
            plant.set_torque(motor.push(np.asarray(out.tau)[self.to_plant]))
            self._record(log, t, status, pos, quat, vel, omega, v_cmd)
            plant.step(self.substeps)
            if recorder is not None:
                recorder.capture(plant.data)
            if stop_when is not None and stop_when(log):
                break

    def _record(self, log, t, status, pos, quat, vel, omega, v_cmd):
        out = self.output
        log.record("t", t)
        log.record("status", int(status))
        log.record("base_pos", pos)
        log.record("base_quat", quat)
        log.record("base_vel", vel)
        log.record("base_omega", omega)
        log.record("est_pos", out.position)
        log.record("est_vel", out.velocity)
        log.record("est_quat", out.quat)
        log.record("tilt", out.tilt)
        log.record("safe_stop", float(out.safe_stop))
        log.record("contact", out.contact)
        log.record("scheduled", out.scheduled)
        log.record("foot_clearance", out.foot_clearance)
        log.record("tau", out.tau)
        log.record("foot_force_cmd", out.foot_force)
        log.record("foot_force", self.plant.foot_contact_forces())
        log.record("foot_pos", self.plant.foot_positions())
        log.record("v_cmd", v_cmd)
        log.record("qp_iterations", out.qp_iterations)


_SENSORS = LeggedSensorSettings()
# Settings every quadruped scenario accepts (`kiloloop run quadruped-... --set key=value`).
COMMON_DEFAULTS = {
    "nonideal": True,          # master switch: sensor models, motor delay, saturation on
    # Sensors (sil/legged_sensors.py), realistic by default: MEMS IMU (Allan parameters below), no
    # orientation handed over, encoder-difference joint velocity; ideal_sensors=true (debugging):
    # the simulator's IMU, orientation and joint state with white noise (gyro_sigma, accel_sigma).
    "ideal_sensors": _SENSORS.ideal,
    "gyro_noise_density": _SENSORS.gyro_noise_density,          # [rad/s/sqrt(Hz)] BMI088
    "gyro_bias_random_walk": _SENSORS.gyro_bias_random_walk,    # [rad/s^2/sqrt(Hz)]
    "gyro_turn_on_bias": _SENSORS.gyro_turn_on_bias,            # [rad/s] 1 sigma
    "accel_noise_density": _SENSORS.accel_noise_density,        # [m/s^2/sqrt(Hz)] BMI088
    "accel_bias_random_walk": _SENSORS.accel_bias_random_walk,  # [m/s^3/sqrt(Hz)]
    "accel_turn_on_bias": _SENSORS.accel_turn_on_bias,          # [m/s^2] 1 sigma
    "velocity_resolution": _SENSORS.velocity_resolution,        # [rad] differentiated encoder
    "gyro_sigma": 0.02,        # [rad/s] ideal_sensors only
    "accel_sigma": 0.05,       # [m/s^2] ideal_sensors only
    "encoder_resolution_deg": 0.1,
    "motor_delay": 0.010,      # [s]
    "physics_dt": 0.001,       # [s]
    "ground_truth": False,     # controller on the simulator's state (debugging only; per-tick loop)
    "native": True,            # the C++ loop (sil/native.py); false: per tick in Python, same log
}


def rig_from_settings(settings: dict, seed: int, slope_deg: float = 0.0, config=None,
                      robot=None, terrain=None) -> QuadrupedRig:
    nonideal = NonIdealities(enabled=settings["nonideal"], gyro_sigma=settings["gyro_sigma"],
                             accel_sigma=settings["accel_sigma"],
                             encoder_resolution=float(np.deg2rad(settings["encoder_resolution_deg"])),
                             motor_delay=settings["motor_delay"])
    nonideal.validate()
    sensors = LeggedSensorSettings(
        ideal=bool(settings["ideal_sensors"]),
        **{k: float(settings[k]) for k in ("gyro_noise_density", "gyro_bias_random_walk",
                                           "gyro_turn_on_bias", "accel_noise_density",
                                           "accel_bias_random_walk", "accel_turn_on_bias",
                                           "velocity_resolution")})
    return QuadrupedRig(RigSettings(slope_deg=slope_deg, physics_dt=settings["physics_dt"],
                                    nonideal=nonideal, sensors=sensors,
                                    ground_truth=settings["ground_truth"],
                                    config=config, video=settings.get("video"), terrain=terrain,
                                    native=bool(settings.get("native", True))),
                        seed=seed, robot=robot)
