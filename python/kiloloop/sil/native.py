"""The native SIL loop (kiloloop._core.native, cpp/sil/): the closed loop in C++ on the very
mjModel/mjData the Python plant built. The rig (sil/rig.py) configures a Rollout from a robot
file's family; this module holds what every family shares: loading libmujoco, the probe
sources, ground-truth requests (Observe), where a rollout starts (start_state), running one with
Python's work between ticks (drive) and reading its log (signal_log).

    rollout = rig.rollout(4.5, reference, observe=Observe("q_true", "ee"))
    rollout.run()                       # GIL released
    log = native.signal_log(rollout)    # a SignalLog

The extension calls the libmujoco the `mujoco` module loaded (checked by `check()`).
"""
from __future__ import annotations

import glob
import os

import mujoco

from .. import _core
from .log import SignalLog
from .timing import whole_periods

_native = _core.native

# The arm family's native adapters (cpp/sil/arm_adapters.hpp), built on the controller and
# reference objects of sil/arm_adapters.py:
#   joint_tracking_adapter(controller, trajectory)     ComputedTorque / JointPdGravity on a
#                                                      QuinticTrajectory / TrapezoidTrajectory
#   cartesian_adapter(controller, line)                CartesianTrackingController on a CartesianLine
#   supervised_adapter(controller, supervisor, trajectory)   ... -> ArmSupervisor (e-stop events)
joint_tracking_adapter = _native.joint_tracking_adapter if _native.available else None
cartesian_adapter = _native.cartesian_adapter if _native.available else None
supervised_adapter = _native.supervised_adapter if _native.available else None

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
    the native loop and MuJoCo's own mj_step alike). Raises RuntimeError where the native loop cannot
    run: without it the heightfield would silently collide otherwise."""
    check()
    _native.install_smooth_heightfield()


def check() -> None:
    """Raises RuntimeError (with the reason) unless available()."""
    if _UNAVAILABLE:
        raise RuntimeError(_UNAVAILABLE)


class Observe:
    """Ground truth of an arm recorded every tick, by name: q_true, qd_true (the plant's joint
    sensors), ee, ee_rot (end-effector site position (3) [m], rotation (3, 3)); probes() gives
    them as the native loop's probes."""

    NAMES = ("q_true", "qd_true", "ee", "ee_rot")

    def __init__(self, *names: str):
        unknown = [n for n in names if n not in self.NAMES]
        if unknown:
            raise ValueError(f"Observe: unknown signal {unknown[0]!r}; known: {', '.join(self.NAMES)}")
        self.names = names

    def probes(self, plant) -> list[tuple]:
        site = int(plant._site)
        table = {"q_true": (_SENSOR, [int(a) for a in plant._pos_sens]),
                 "qd_true": (_SENSOR, [int(a) for a in plant._vel_sens]),
                 "ee": (_SITE_POS, [site]), "ee_rot": (_SITE_MAT, [site])}
        return [(name, *table[name]) for name in self.names]


def ticks_of(duration: float, control_dt: float = 0.001) -> int:
    """Control ticks in `duration` [s] (sil/timing.py whole_periods)."""
    return whole_periods(duration, control_dt)


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
    """The rollout's channels as a SignalLog."""
    log = SignalLog() if log is None else log
    for name, series in r.log().items():
        log.put_array(name, series)
    return log


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


def contact_count(name: str, geoms) -> tuple:
    """Probe: per tick the number of active contacts (d.ncon entries) involving any of the geom
    ids (a contact counted once), as a float; read where observe() reads (arm_scene.contacts_with
    for one geom)."""
    return (name, _CONTACT_COUNT, [int(g) for g in geoms])


def geom_distance(name: str, geom: int, others) -> tuple:
    """Probe: per tick the smallest signed distance [m] from geom to any of others, capped at
    1 m (arm_scene.min_distance)."""
    return (name, _GEOM_DISTANCE, [int(geom)] + [int(g) for g in others])
