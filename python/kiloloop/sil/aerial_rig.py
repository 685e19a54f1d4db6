"""SIL rig for multirotors (with or without an arm) from a robot file: MuJoCo plant
(aerial_plant.py) + sensor non-idealities + the compiled AerialController, at 1 kHz. Scenarios (scenarios/aerial_*.py) script the references
and disturbances and judge the log; this file only moves data (no control logic).

What the controller sees: the IMU (gyro with noise, orientation with a small noise standing in for
an attitude estimator), the arm encoders (quantized), and the body position and velocity from a
motion-capture-like source (ground truth plus white noise). Commands travel through a short
transport delay before the plant; the rotors add their own first-order lag.

Two loops, one log: by default the closed loop runs in C++ (sil/native.py, cpp/sil/
aerial_adapter.hpp): the command is sampled into a reference table, pushes and rotor faults are
events, the wind a seeded C++ drag model; with native=False, or an event or disturbance
given as a Python callable, it runs per tick in Python. Both use the same C++ sensor model (one
normal per element of y per tick from the seed's xoshiro stream), attitude noise stage, motor
delay and wind model, so they give the same log (tests/test_native_aerial.py). What both loops
share as data (event actions, wind, signal models, the reference table): sil/aerial_signals.py.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

import kiloloop as kl

from ..robot import Robot
from ..errors import InputError, configuring
from ..robot import aerial as aerial_robot
from . import native as native_loop
from .aerial_plant import AerialPlant
# What both loops share as data (re-exported: scenarios import them from here).
from .aerial_signals import (ARM_REFERENCE_FIELDS, CONTROL_DT, REFERENCE_FIELDS,  # noqa: F401
                             REFERENCE_WIDTH, AerialSignals, Push, RotorFault, Wind,
                             _load_references, _torque_at, reference_row, reference_table)
from .log import SignalLog
from .nonideal import NonIdealities
from .timing import substeps, whole_periods
from .video import maybe_recorder

DEFAULT_ROBOT = "aerial_manipulator"


def load_robot(robot=None):
    """A loaded kl.Robot: `robot` itself, or a name / file, or kiloloop's aerial manipulator."""
    return robot if isinstance(robot, Robot) else Robot.load(robot or DEFAULT_ROBOT)


def aerial_paths():
    return kl.model_files(DEFAULT_ROBOT)


def rotor_config(robot=None) -> "kl.RotorAllocationConfig":
    """The controller's rotor settings from the robot file's [[rotors]] (the one place they live)."""
    return aerial_robot.rotor_config(load_robot(robot))


@dataclass
class AerialRigSettings:
    physics_dt: float = 0.001
    nonideal: NonIdealities = field(default_factory=lambda: NonIdealities(
        quat_sigma=0.002, motor_delay=0.002))
    position_sigma: float = 0.001   # [m] motion-capture position noise per axis
    velocity_sigma: float = 0.005   # [m/s]
    joint_friction: bool = True     # the overlay's arm friction (False: frictionless plant)
    lag_compensation: bool = False  # rotor-lag lead in the controller's allocation
    friction_compensation: bool = True  # the controller knows the arm's joint friction
    config: object = None           # kl.AerialConfig; None = derived from the robot file
    video: str | None = None        # an .mp4 path: record the run
    native: bool = True             # the C++ loop where the run allows it (runs_natively)


# command(t, input): sets the references on the controller input for time t.
CommandFn = Callable[[float, object], None]


class AerialRig:
    def __init__(self, settings: AerialRigSettings, seed: int = 0, robot=None):
        robot = load_robot(robot)
        self.robot = robot
        self.settings = settings
        kw = {} if settings.joint_friction else {"damping": 0.0, "frictionloss": 0.0}
        self.plant = AerialPlant.from_robot(robot, timestep=settings.physics_dt,
                                            visual=bool(settings.video), **kw)
        self.model = aerial_robot.model(robot)
        config = (settings.config if settings.config is not None
                  else aerial_robot.config(robot))
        config.dt = CONTROL_DT
        if settings.joint_friction and settings.friction_compensation and self.plant.nq:
            # The arm's friction as identified: the robot file's values (what the plant simulates).
            joints = robot.sim.get("joints", {})
            for field_name, key in (("arm_viscous", "damping"), ("arm_coulomb", "frictionloss")):
                value = joints.get(key)
                if value is not None:
                    setattr(config, field_name, np.atleast_1d(np.asarray(value, dtype=float)))
        rotors = config.rotors
        rotors.lag_compensation = settings.lag_compensation
        config.rotors = rotors
        self.config = config
        with configuring(f"{robot.name} aerial controller"):
            self.controller = kl.AerialController(self.model, config)
        self.n_rotors = self.controller.n_rotors
        plant_index = {name: i for i, name in enumerate(self.plant.joint_names)}
        names = list(self.model.joint_names) if self.controller.nq else []
        self.to_ctrl = np.array([plant_index[n] for n in names], dtype=int)
        self.to_plant = np.argsort(self.to_ctrl)
        self.signals = AerialSignals(settings, seed, self.n_rotors, self.plant.nq)
        self.substeps = substeps(self.plant.timestep)
        self.input, self.output = self.controller.make_input(), self.controller.make_output()
        self.hover_pos = self.plant.base_pos0.copy()

    # --- the native loop ---------------------------------------------------------------------

    def runs_natively(self, events=(), disturbance=None, native: bool | None = None) -> bool:
        """Whether run() takes the C++ loop: asked for, built in, events Push or RotorFault, the
        disturbance None or a Wind (the command is sampled into a table; a video's frames are
        captured between ticks)."""
        native = self.settings.native if native is None else native
        return (native is not False and native_loop.available()
                and all(isinstance(a, (Push, RotorFault)) for _, a in events)
                and (disturbance is None or isinstance(disturbance, Wind)))

    def measurement(self) -> tuple[list[int], list[int]]:
        """(addresses, sources) of y: the free joint's qpos/qvel (motion capture), the IMU
        sensors, the arm's encoders (native_loop.hpp measurement_source: 0 sensordata, 1 qpos,
        2 qvel)."""
        p, imu = self.plant, self.plant._imu_adr
        addr = (list(range(p._free_q, p._free_q + 3)) + list(range(p._free_d, p._free_d + 3))
                + list(range(imu["gyro"], imu["gyro"] + 3))
                + list(range(imu["accel"], imu["accel"] + 3))
                + list(range(imu["quat"], imu["quat"] + 4))
                + [int(a) for a in p._pos_sens] + [int(a) for a in p._vel_sens])
        source = [1] * 3 + [2] * 3 + [0] * (10 + 2 * p.nq)
        return addr, source

    def native_adapter(self, table: np.ndarray, controller=None):
        return native_loop._native.aerial_adapter(controller or self.controller,
                                                  [int(i) for i in self.to_ctrl], table)

    def native_probes(self) -> list[tuple]:
        """The ground truth AerialRig._record logs, as native probes."""
        p = self.plant
        fq, fd, b = p._free_q, p._free_d, int(p._base_id)
        ee = ([("ee_pos", native_loop._SITE_POS, [int(p._ee_site)]),
               ("ee_rot", native_loop._SITE_MAT, [int(p._ee_site)])] if p._ee_site is not None
              else [("ee_pos", native_loop._BODY_POS, [b]), ("ee_rot", native_loop._BODY_MAT, [b])])
        return [("base_pos", native_loop._QPOS, list(range(fq, fq + 3))),
                ("com", native_loop._SUBTREE_COM, [b]),
                ("base_quat", native_loop._QPOS, list(range(fq + 3, fq + 7))),
                ("base_vel", native_loop._QVEL, list(range(fd, fd + 3))),
                ("base_omega", native_loop._QVEL, list(range(fd + 3, fd + 6))),
                ("thrust", native_loop._ACTUATOR_FORCE, [int(a) for a in p._rotor_act]),
                ("q", native_loop._SENSOR, [int(p._pos_sens[i]) for i in self.to_ctrl]),
                *ee]

    def native_events(self, events=()) -> list[tuple]:
        p, out = self.plant, []
        for t, a in events:
            if isinstance(a, Push):  # at the subtree CoM (the 9th payload entry)
                time, kind, payload = native_loop.force(t, p._base_id, [*a.force, 0.0, 0.0, 0.0],
                                                        a.duration)
                out.append((time, kind, payload + [1.0]))
            else:
                if not 0 <= a.rotor < self.n_rotors:
                    raise InputError(f"rotor: expected 0..{self.n_rotors - 1}, got {a.rotor}")
                out.append((float(t), native_loop.GAIN, [float(p._rotor_act[a.rotor]), float(a.efficiency)]))
        return out

    def native_rollout(self, duration: float, command, events=(), disturbance=None, data=None,
                       adapter=None, seed: int | None = None, table=None, stages=()):
        """A configured native Rollout of this rig (data: another MjData of plant.model for a
        batch, a new one starting at the plant's state (native.start_state); a RotorFault writes
        the model, so a concurrent rollout with one needs its own model and data; adapter: one
        built on another controller; seed: another noise stream than the rig's; stages: more
        C++ measurement stages after the rig's own, a sensor dropout)."""
        native_loop.check()
        p, s = self.plant, self.signals
        ticks = native_loop.ticks_of(duration, CONTROL_DT)
        if adapter is None:
            adapter = self.native_adapter(reference_table(self.controller, command, max(ticks, 1))
                                          if table is None else table)
        if seed is not None:
            s = AerialSignals(self.settings, seed, self.n_rotors, p.nq)
        addr, source = self.measurement()
        return native_loop._native.Rollout(
            p.model, native_loop.start_state(p, data), adapter, ticks=ticks,
            control_dt=CONTROL_DT, measurement=addr, measurement_source=source,
            actuators=[int(a) for a in p._rotor_act] + [int(a) for a in p._act],
            sigma=s.sigma, quantum=s.quantum, seed=s.seed, stages=s.stages() + list(stages),
            motor_delay_ticks=s.motor_delay_ticks, motor_hold_first=True,
            events=self.native_events(events),
            disturbances=[disturbance.model(p)] if disturbance is not None else [],
            probes=self.native_probes(), stop_nonfinite=True)

    # --- run -----------------------------------------------------------------------------------

    def run(self, duration: float, command: CommandFn, events=(),
            log: SignalLog | None = None, disturbance=None, native: bool | None = None) -> SignalLog:
        """The closed loop for `duration` [s]: in C++ when runs_natively() (native None: the
        settings' choice), else per tick in Python; the same log either way. command(t, input)
        sets the references (sampled into a table for both loops); events: (time [s], action)
        pairs, a Push, a RotorFault or any action(plant) (per-tick loop); disturbance: None, a
        Wind, or any disturbance(t, plant, log) called every tick (per-tick loop)."""
        log = SignalLog() if log is None else log
        if self.runs_natively(events, disturbance, native):
            r = self.native_rollout(duration, command, events, disturbance)
            native_loop.drive(r, self.plant.model, self.plant.data, video=self.settings.video,
                              camera_body=self.plant._base_id)
            native_loop.signal_log(r, log)
            if r.diverged:
                log.record("diverged", 1.0)
            return log
        recorder = maybe_recorder(self.settings.video, self.plant.model,
                                  body=self.plant._base_id)
        try:
            return self._run(duration, command, events, log, disturbance, recorder)
        finally:
            if recorder is not None:
                recorder.close()

    def _run(self, duration, command, events, log, disturbance, recorder):
        """The per-tick loop, in the native loop's order and with its C++ sensor, motor and wind
        models (the same log); any Python event action or disturbance runs here."""
        ticks = whole_periods(duration)
        table = reference_table(self.controller, command, max(ticks, 1))
        pending = sorted(events, key=lambda e: e[0])
        inp, out, plant, s = self.input, self.output, self.plant, self.signals
        sensor, stages, motor = s.sensor(), s.stages(), s.motor()
        wind = disturbance.model(plant) if isinstance(disturbance, Wind) else None
        if wind is not None:
            wind.check(plant.model)
        addr, source = self.measurement()
        addr = np.array(addr)
        src = np.array(source)
        n, nq, b = self.n_rotors, plant.nq, plant._base_id
        pushes = []  # [force (3), physics steps left]
        ts = plant.timestep
        for k in range(ticks):
            t = k * CONTROL_DT
            d = plant.data
            y_raw = np.where(src == 0, d.sensordata[np.where(src == 0, addr, 0)],
                             np.where(src == 1, d.qpos[np.where(src == 1, addr, 0)],
                                      d.qvel[np.where(src == 2, addr, 0)]))
            y = sensor.apply(y_raw)
            for stage in stages:
                y = stage.apply(t, y)
            while pending and t >= pending[0][0]:
                action = pending.pop(0)[1]
                if isinstance(action, Push):
                    steps = whole_periods(action.duration, ts)
                    pushes.append([np.asarray(action.force, float), steps])
                else:
                    action(plant)
            if wind is not None:
                wind.apply(t, plant.model, d)
                wrench = d.xfrc_applied[b].copy()
                log.record("wind", wind.wind)
                log.record("wind_force", wind.force)
            elif disturbance is not None:
                disturbance(t, plant, log)
            inp.t = inp.stamp = t
            inp.position[:], inp.velocity[:] = y[0:3], y[3:6]
            inp.gyro[:], inp.accel[:], inp.quat[:] = y[6:9], y[9:12], y[12:16]
            if nq:
                inp.q[:] = y[16:16 + nq][self.to_ctrl]
                inp.qd[:] = y[16 + nq:16 + 2 * nq][self.to_ctrl]
            _load_references(inp, table[min(k, len(table) - 1)], nq)
            status = self.controller.step(inp, out)
            cmd = motor.push(np.concatenate([out.thrust, np.asarray(out.tau)[self.to_plant]]))
            plant.set_thrust(cmd[:n])
            plant.set_torque(cmd[n:])
            self._record(log, t, status)
            for _ in range(self.substeps):
                if pushes or wind is not None:
                    # As the native loop's physics step: zero, the pushes, the wind.
                    f = d.xfrc_applied[b]
                    f[:] = 0.0
                    for push in pushes:
                        if push[1] > 0:
                            f[:3] += push[0]
                            f[3:] += _torque_at(d.subtree_com[b], d.xipos[b], push[0])
                            push[1] -= 1
                    if wind is not None:
                        f[:] += wrench
                plant.step(1)
            if recorder is not None:
                recorder.capture(plant.data)
            if not np.all(np.isfinite(plant.data.qpos)):
                log.record("diverged", 1.0)
                break
        return log

    def _record(self, log, t, status):
        out, inp, p = self.output, self.input, self.plant
        pos, quat = p.base_pose()
        vel, omega = p.base_velocity()
        log.record("t", t)
        log.record("base_pos", pos)
        log.record("com", p.com())
        log.record("base_quat", quat)
        log.record("base_vel", vel)
        log.record("base_omega", omega)
        log.record("thrust", p.rotor_thrust())
        log.record("q", p.q()[self.to_ctrl])
        ee_pos, ee_rot = p.ee_pose()
        log.record("ee_pos", ee_pos)
        log.record("ee_rot", ee_rot)
        log.record("status", int(status))
        log.record("pos_ref", inp.position_ref)
        log.record("quat_des", out.quat_des)
        log.record("tilt", out.tilt)
        log.record("safe_stop", float(out.safe_stop))
        log.record("thrust_cmd", out.thrust)
        log.record("rotors_saturated", float(out.rotors_saturated))
        log.record("tau", out.tau)
        log.record("reaction", out.reaction)
        log.record("q_ref", out.q_ref)


# Settings every aerial scenario accepts (`kiloloop run aerial-... --set key=value`).
COMMON_DEFAULTS = {
    "nonideal": True,          # IMU noise, encoder quantization, command delay on
    "gyro_sigma": 0.02,        # [rad/s]
    "accel_sigma": 0.05,       # [m/s^2]
    "quat_sigma": 0.002,       # [rad] attitude-estimate noise
    "position_sigma": 0.001,   # [m] motion capture
    "velocity_sigma": 0.005,   # [m/s]
    "motor_delay": 0.002,      # [s] command transport (ESC) delay, on top of the rotor lag
    "physics_dt": 0.001,       # [s]
    "law": "quaternion_pd",    # or "geometric_so3"
    "feedforward": True,       # arm reaction feed-forward
    "lag_compensation": False, # rotor-lag lead in the allocation (all thrusts)
    "reaction_lead": None,     # [s] lead on the fed-forward reaction torque; None: derived
                               # (the rotor time constant, robot/aerial.py)
    "hold_com": True,          # the position loop holds the vehicle's CoM (not the body origin)
    # The controller compensates the arm's (identified) joint friction (the overlay's values).
    "friction_compensation": True,
    "att_kp": 0.0,             # 0: the controller's default (roll/pitch) [1/s^2]
    "att_kd": 0.0,             # 0: default [1/s]
    "att_ki": 0.0,             # roll/pitch integral [1/s^3]
    "pos_kp": 0.0,             # 0: default (x, y) [1/s^2]
    "pos_kd": 0.0,             # 0: default [1/s]
    "native": True,            # the C++ loop (sil/native.py); false: per tick in Python, same log
}

LAWS = {"quaternion_pd": "QUATERNION_PD", "geometric_so3": "GEOMETRIC_SO3"}


def config_from_settings(settings: dict, robot=None) -> "kl.AerialConfig":
    """The robot file's derived configuration with the scenario settings on top."""
    config = aerial_robot.config(load_robot(robot))
    if settings["law"] not in LAWS:
        raise InputError(f"law: expected one of {sorted(LAWS)}, got {settings['law']!r}")
    config.attitude.law = getattr(kl.AttitudeLaw, LAWS[settings["law"]])
    config.reaction_feedforward = bool(settings["feedforward"])
    if settings["reaction_lead"] is not None:
        config.reaction_lead = float(settings["reaction_lead"])
    config.hold_com = bool(settings["hold_com"])
    gains = config.attitude.gains
    kp, kd, ki = np.array(gains.kp), np.array(gains.kd), np.array(gains.ki)
    if settings["att_kp"] > 0:
        kp[:2] = settings["att_kp"]
    if settings["att_kd"] > 0:
        kd[:2] = settings["att_kd"]
    ki[:2] = settings["att_ki"]
    gains.kp, gains.kd, gains.ki = kp, kd, ki
    config.attitude.gains = gains
    pos = config.position
    pkp, pkd = np.array(pos.kp), np.array(pos.kd)
    if settings["pos_kp"] > 0:
        pkp[:2] = settings["pos_kp"]
    if settings["pos_kd"] > 0:
        pkd[:2] = settings["pos_kd"]
    pos.kp, pos.kd = pkp, pkd
    config.position = pos
    return config


def rig_from_settings(settings: dict, seed: int, config=None, robot=None) -> AerialRig:
    nonideal = NonIdealities(enabled=settings["nonideal"], gyro_sigma=settings["gyro_sigma"],
                             accel_sigma=settings["accel_sigma"],
                             quat_sigma=settings["quat_sigma"],
                             motor_delay=settings["motor_delay"])
    nonideal.validate()
    robot = load_robot(robot)
    config = config_from_settings(settings, robot) if config is None else config
    rig = AerialRig(AerialRigSettings(physics_dt=settings["physics_dt"], nonideal=nonideal,
                                      position_sigma=settings["position_sigma"],
                                      velocity_sigma=settings["velocity_sigma"],
                                      lag_compensation=bool(settings["lag_compensation"]),
                                      friction_compensation=bool(
                                          settings["friction_compensation"]),
                                      config=config, video=settings.get("video"),
                                      native=bool(settings.get("native", True))),
                    seed=seed, robot=robot)
    return rig
