"""The native SIL loop: the closed loop of sil/loop.py in C++ (kiloloop._core.native), on the very
mjModel/mjData the Python plant built.

Python sets up (plant, compiled controller, reference: the same objects the per-tick path uses) and
reads results; per tick nothing runs in Python. Sensor and actuator models (noise, quantization,
delays, motor lag), scheduled events and ground-truth probes are data:

    rollout = native.rollout(plant, tick.native_adapter(), duration=4.5, observe=Observe("q_true", "ee"))
    rollout.run()                       # GIL released
    log = native.signal_log(rollout)    # a SignalLog, as run_loop returns

The extension calls the libmujoco the `mujoco` module loaded (checked by `check()`); see
docs/native_sil.md for which scenarios run natively and which still need Python each tick.
"""
from __future__ import annotations

import glob
import os
from dataclasses import dataclass

import mujoco
import numpy as np

from .. import _core
from .log import SignalLog
from .timing import whole_periods

_native = _core.native

# The arm family's native adapters (cpp/sil/arm_adapters.hpp), built on the very controller and
# reference objects the per-tick ticks use (sil/arm_adapters.py):
#   joint_tracking_adapter(controller, trajectory)     ComputedTorque / JointPdGravity on a
#                                                      QuinticTrajectory / TrapezoidTrajectory
#   cartesian_adapter(controller, line)                CartesianTrackingController on a CartesianLine
#   supervised_adapter(controller, supervisor, trajectory)   ... -> ArmSupervisor (e-stop events)
joint_tracking_adapter = _native.joint_tracking_adapter if _native.available else None
cartesian_adapter = _native.cartesian_adapter if _native.available else None
supervised_adapter = _native.supervised_adapter if _native.available else None

# Event kinds (cpp/sil/events.hpp).
ESTOP, REFERENCE, FORCE, GAIN = 0, 1, 2, 3
# Probe sources (cpp/sil/native_loop.hpp).
(_SENSOR, _SITE_POS, _SITE_MAT, _BODY_POS, _BODY_QUAT, _QPOS, _QVEL, _BODIES_POS,
 _CONTACT_FORCE, _SUBTREE_COM, _ACTUATOR_FORCE, _BODY_MAT, _SITES_POS) = range(13)
# Computed each tick, one value: contacts (d->ncon entries) involving any of the geoms; the
# smallest signed distance [m] from a geom to others (mj_geomDistance, capped at 1 m).
_CONTACT_COUNT, _GEOM_DISTANCE = 13, 14
# arm-press's adapter (cpp/sil/press_adapter.hpp): press_adapter(controller, p0, R0, force,
# settle, slide, slide_time), y = [q; qd; f_site (3); site quat (4)] (extra_measurement below).
press_adapter = _native.press_adapter if _native.available else None


def _load_mujoco() -> str:
    """Points the native loop at the libmujoco `import mujoco` loaded (cpp/sil/mujoco_api.hpp);
    returns why it cannot run ("" when it can)."""
    if not _native.available:
        return ("kiloloop was built without the native SIL loop (no mujoco wheel at configure "
                "time)")
    if _native.mujoco_loaded():
        return ""
    why = f"no libmujoco next to {mujoco.__file__}"
    for path in sorted(glob.glob(os.path.join(os.path.dirname(mujoco.__file__), "libmujoco.so*"))):
        try:
            _native.load_mujoco(path)
            return ""
        except ValueError as e:
            why = str(e)
    return why


_UNAVAILABLE = _load_mujoco()


def library() -> str:
    """Path of the libmujoco the native loop calls ("" before it is resolved)."""
    return _native.mujoco_library() if _native.available else ""


def available() -> bool:
    """True when the native loop can step this Python mujoco's models."""
    return not _UNAVAILABLE


# Heightfields named with this prefix get one contact per sphere from their smooth surface
# (cpp/sil/smooth_heightfield.hpp); sil/terrain.py's Rough names its heightfield so.
SMOOTH_HEIGHTFIELD_PREFIX = _native.smooth_heightfield_prefix if _native.available else ""
# The contact it makes, for tests: (dist, pos, normal) of a sphere on a bilinear height grid, or None.
sphere_on_bilinear = _native.sphere_on_bilinear if _native.available else None


def install_smooth_heightfield() -> None:
    """Puts kiloloop's sphere : heightfield collider into this process's libmujoco (once; for
    the Python loop and the native one alike). Raises RuntimeError where the native loop cannot
    run: without it the heightfield would silently collide otherwise."""
    check()
    _native.install_smooth_heightfield()


def check() -> None:
    """Raises RuntimeError (with the reason) unless available()."""
    if _UNAVAILABLE:
        raise RuntimeError(_UNAVAILABLE)


@dataclass
class NonIdeal:
    """Joint sensor and motor models of an arm run (both loops; defaults: ideal).

    q_sigma, qd_sigma: white noise per sample [rad], [rad/s]; encoder_resolution: quantization
    step of q [rad] (0: none); motor_delay_ticks: command transport delay [ticks];
    motor_time_constant: first-order lag of the produced torque [s]; seed: the noise stream."""

    q_sigma: float = 0.0
    qd_sigma: float = 0.0
    encoder_resolution: float = 0.0
    motor_delay_ticks: int = 0
    motor_time_constant: float = 0.0
    seed: int = 0

    def arrays(self, nq: int) -> tuple[list, list]:
        """(sigma, quantum) over y = [q; qd]; empty lists where the effect is off."""
        sigma = ([self.q_sigma] * nq + [self.qd_sigma] * nq
                 if self.q_sigma > 0 or self.qd_sigma > 0 else [])
        quantum = ([self.encoder_resolution] * nq + [0.0] * nq
                   if self.encoder_resolution > 0 else [])
        return sigma, quantum

    def sensor(self, nq: int):
        """The C++ sensor model alone (for the per-tick Python loop)."""
        sigma, quantum = self.arrays(nq)
        return _native.SensorModel(sigma, quantum, int(self.seed), 2 * nq)

    def motor(self, nq: int, control_dt: float = 0.001):
        return _native.MotorModel(int(self.motor_delay_ticks), float(self.motor_time_constant),
                                  control_dt, nq)


class Observe:
    """Ground truth recorded every tick, by name, understood by both loops:
    q_true, qd_true (the plant's joint sensors), ee, ee_rot (end-effector site position (3) [m],
    rotation (3, 3)). Called as observe(plant, log) by the per-tick loop; probes() for native."""

    NAMES = ("q_true", "qd_true", "ee", "ee_rot")

    def __init__(self, *names: str):
        unknown = [n for n in names if n not in self.NAMES]
        if unknown:
            raise ValueError(f"Observe: unknown signal {unknown[0]!r}; known: {', '.join(self.NAMES)}")
        self.names = names

    def __call__(self, plant, log: SignalLog) -> None:
        for name in self.names:
            if name == "q_true":
                log.record(name, plant.q())
            elif name == "qd_true":
                log.record(name, plant.qd())
            elif name == "ee":
                log.record(name, plant.ee_pose()[0])
            else:
                log.record(name, plant.ee_pose()[1])

    def probes(self, plant) -> list[tuple]:
        site = int(plant._site)
        table = {"q_true": (_SENSOR, [int(a) for a in plant._pos_sens]),
                 "qd_true": (_SENSOR, [int(a) for a in plant._vel_sens]),
                 "ee": (_SITE_POS, [site]), "ee_rot": (_SITE_MAT, [site])}
        return [(name, *table[name]) for name in self.names]


def estop(time: float, pressed: bool = True) -> tuple:
    """Event: the e-stop input goes high (or low) at `time` [s]."""
    return (float(time), ESTOP, [1.0 if pressed else 0.0])


def reference_offset(time: float, offset) -> tuple:
    """Event: from `time` [s] the reference is shifted by `offset` (joint adapters: (nq) [rad];
    Cartesian: (3) [m])."""
    return (float(time), REFERENCE, [float(x) for x in offset])


def force(time: float, body: int, wrench, duration: float) -> tuple:
    """Event: wrench (fx, fy, fz, tx, ty, tz) [N, N m], world frame, on `body` (a MuJoCo body id)
    for `duration` [s] from `time` [s]."""
    w = [float(x) for x in wrench]
    if len(w) != 6:
        raise ValueError(f"wrench: expected 6 values, got {len(w)}")
    return (float(time), FORCE, [float(body)] + w + [float(duration)])


def ticks_of(duration: float, control_dt: float = 0.001) -> int:
    """Control ticks in `duration` [s], as run_loop counts them."""
    return whole_periods(duration, control_dt)


def rollout(plant, adapter, duration: float, *, data=None, delay_ticks: int = 0,
            nonideal: NonIdeal | None = None, events=(), observe: Observe | None = None,
            control_dt: float = 0.001, stages=(), extra_measurement=(), probes=()):
    """A configured native Rollout of an arm-shaped plant (sil/plant.py MujocoPlant: y = [q; qd]
    from its joint sensors, u = its motors). data: another MjData of plant.model (a batch gives
    each rollout its own); default the plant's own. A new `mujoco.MjData(plant.model)` starts
    where the plant is (start_state); a data you set up yourself starts from its own state.
    stages: C++ measurement stages after the sensor model (a sensor dropout). extra_measurement:
    sensordata addresses appended to y (arm-press's force sensor; the noise model leaves them
    alone); probes: more (name, source, index) probes after observe's (contact_count,
    geom_distance). Run it with .run() or batch.run()."""
    check()
    nonideal = nonideal or NonIdeal()
    sigma, quantum = nonideal.arrays(plant.nq)
    measurement = ([int(a) for a in plant._pos_sens] + [int(a) for a in plant._vel_sens]
                   + [int(a) for a in extra_measurement])
    return _native.Rollout(
        plant.model, start_state(plant, data), adapter,
        ticks=ticks_of(duration, control_dt), control_dt=control_dt, measurement=measurement,
        actuators=[int(a) for a in plant._act], delay_ticks=int(delay_ticks), sigma=sigma,
        quantum=quantum, seed=int(nonideal.seed), motor_delay_ticks=int(nonideal.motor_delay_ticks),
        motor_time_constant=float(nonideal.motor_time_constant), events=list(events),
        probes=(observe.probes(plant) if observe is not None else []) + list(probes),
        stages=list(stages))


def start_state(plant, data=None):
    """The MjData a rollout of `plant` steps, holding the state it starts from: the plant's own
    data when `data` is None; `data` itself when it holds a state; and a new or reset `data`
    (mujoco.MjData(plant.model), mj_resetData) filled with a copy of the plant's data first.

    A new MjData is at the model's qpos0 with its sensors reading zero: not the plant's start pose
    (an arm's qpos0 is its URDF zero) nor a state the loop can start from (its first tick reads
    the sensors the caller's mj_forward left). It is recognised by its world
    body's orientation, the zero quaternion until a kinematics pass (mj_forward, mj_kinematics,
    a step) writes (1, 0, 0, 0), so a data you set and forwarded yourself is kept as it is."""
    if data is None:
        return plant.data
    if data is not plant.data and data.xquat[0, 0] == 0.0:
        mujoco.mj_copyData(data, plant.model, plant.data)
    return data


def signal_log(r, log: SignalLog | None = None) -> SignalLog:
    """The rollout's channels as a SignalLog (the per-tick loop's result type)."""
    log = SignalLog() if log is None else log
    for name, series in r.log().items():
        log.put_array(name, series)
    return log


def run(plant, adapter, duration: float, log: SignalLog | None = None, *, video=None,
        camera_body: int = 1, **kwargs) -> SignalLog:
    """One native run on the plant's own data; raises RuntimeError if the loop stopped early.
    video: an .mp4 path, its frames captured between ticks (drive)."""
    r = rollout(plant, adapter, duration, **kwargs)
    drive(r, plant.model, plant.data, video=video, camera_body=camera_body)
    return signal_log(r, log)


def drive(r, model, data, *, video=None, camera_body: int = 1, hooks=()) -> None:
    """Runs a rollout on (model, data) to its end in C++, doing Python's work only between ticks
    (Rollout.advance): a video frame every 1/30 s of simulated time (video: an .mp4 path, the
    camera on camera_body) and each hook (tick, fn(model, data)) once that tick has run (a
    payload attached mid-run). Without either it is one advance. RuntimeError if the loop
    stopped with an error."""
    from .video import maybe_recorder

    recorder = maybe_recorder(video, model, body=camera_body) if video else None
    pending = sorted(hooks, key=lambda h: h[0])
    try:
        while not r.finished:
            if recorder is not None:   # the state each tick starts from: T / (1/30 s) frames
                recorder.capture(data)
                r.advance(1)
            else:
                r.advance(pending[0][0] - r.ticks_run if pending else 1 << 30)
            while pending and r.ticks_run >= pending[0][0]:
                pending.pop(0)[1](model, data)
    finally:
        if recorder is not None:
            recorder.close()
    if not r.ok:
        raise RuntimeError(f"native loop stopped at tick {r.ticks_run}: {r.error}")


def noisy_plant(plant, nonideal: NonIdeal):
    """The plant as the per-tick loop's controller sees it through nonideal's sensor model (same
    C++ code and stream as the native loop: [q; qd] sampled once per tick, q first)."""
    return _SensedPlant(plant, nonideal.sensor(plant.nq))


class _SensedPlant:
    def __init__(self, plant, sensor):
        self._plant, self._sensor, self._qd = plant, sensor, None

    def __getattr__(self, name):
        return getattr(self._plant, name)

    def q(self) -> np.ndarray:
        p = self._plant
        y = self._sensor.apply(np.concatenate([p.q(), p.qd()]))
        self._qd = y[p.nq:]
        return y[:p.nq]

    def qd(self) -> np.ndarray:
        return self._qd


def contact_count(name: str, geoms) -> tuple:
    """Probe: per tick the number of active contacts (d.ncon entries) involving any of the geom
    ids (a contact counted once), as a float; read where observe() reads (arm_scene.contacts_with
    for one geom)."""
    return (name, _CONTACT_COUNT, [int(g) for g in geoms])


def geom_distance(name: str, geom: int, others) -> tuple:
    """Probe: per tick the smallest signed distance [m] from geom to any of others, capped at
    1 m (arm_scene.min_distance)."""
    return (name, _GEOM_DISTANCE, [int(geom)] + [int(g) for g in others])
