"""What the three families' runners share: the run's ticks, the native rollout driven through
its events (payloads change the plant between ticks, video frames are captured between ticks),
the sensor-dropout stages and the payload's rigid-body arithmetic."""
from __future__ import annotations

import numpy as np

from ...errors import InputError
from ...sil import native
from .events import SensorDropout

CONTROL_DT = 0.001  # [s]


def ticks(duration: float) -> int:
    """Control ticks in `duration` [s] (the native loop's rule)."""
    return native.ticks_of(duration, CONTROL_DT)


def body_id(model, name: str, what: str) -> int:
    """A MuJoCo body by its URDF link name; ValueError listing the bodies otherwise."""
    import mujoco

    bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
    if bid < 0:
        names = [model.body(i).name for i in range(1, model.nbody)]
        raise InputError(f"{what}: no body {name!r} in the plant (links merged by fixed joints "
                         f"take their parent's body); bodies: {', '.join(names)}")
    return bid


def dropout_stages(events, layout: dict) -> list:
    """C++ stages freezing a slice of y during each SensorDropout. layout: sensor -> (offset,
    count) in the family's measurement vector; a sensor it lacks is an error."""
    out = []
    for i, e in enumerate(events):
        if not isinstance(e, SensorDropout):
            continue
        if e.sensor not in layout or layout[e.sensor][1] == 0:
            raise InputError(f"events: sensor_dropout at {e.t:g} s: this robot has no "
                             f"{e.sensor!r} sensor; it has {', '.join(k for k, v in layout.items() if v[1])}")
        offset, count = layout[e.sensor]
        out.append(native._native.DropoutStage(int(offset), int(count), float(e.t),
                                               float(e.duration)))
    return out


def attach_payload(model, body: int, mass: float, com) -> None:
    """Adds a point mass `mass` [kg] at `com` (3) [m, the body's frame] to `body` in place: the
    body's mass, CoM and inertia become those of the rigid union (parallel-axis theorem, the
    union's inertia re-diagonalised into body_inertia / body_iquat). MuJoCo reads them at the
    next step (mj_comPos builds the composite inertias from them every step)."""
    import mujoco

    m0, p = float(model.body_mass[body]), np.asarray(com, float)
    c0 = np.array(model.body_ipos[body])
    R0 = np.zeros(9)
    mujoco.mju_quat2Mat(R0, model.body_iquat[body])
    R0 = R0.reshape(3, 3)
    I0 = R0 @ np.diag(model.body_inertia[body]) @ R0.T     # about c0, body frame
    m1 = m0 + mass
    c1 = (m0 * c0 + mass * p) / m1

    def shift(m, r):  # inertia of a point mass m at offset r
        return m * (np.dot(r, r) * np.eye(3) - np.outer(r, r))

    I1 = I0 + shift(m0, c0 - c1) + shift(mass, p - c1)
    w, V = np.linalg.eigh(I1)
    if np.linalg.det(V) < 0:
        V[:, 0] = -V[:, 0]
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, V.reshape(9))
    model.body_mass[body] = m1
    model.body_ipos[body] = c1
    model.body_inertia[body] = np.maximum(w, 1e-12)
    model.body_iquat[body] = q
    mujoco.mj_setConst(model, mujoco.MjData(model))


def payload_hooks(payloads: list) -> list:
    """Rig.run hooks attaching each payload (tick, body id, Payload) once its tick has run."""
    def attach(body, p):
        return lambda model, _data: attach_payload(model, body, p.mass, p.com)

    return [(tick, attach(body, p)) for tick, body, p in payloads]


def cumulative(flags: np.ndarray) -> np.ndarray:
    """1.0 from the first true tick on (a fall, a divergence: it does not un-happen)."""
    return np.maximum.accumulate(np.asarray(flags, dtype=float)) if len(flags) else np.zeros(0)
