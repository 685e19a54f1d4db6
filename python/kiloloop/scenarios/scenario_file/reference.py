"""The `[reference]` of a scenario file: exactly one table, which also says the robot's family.

    joint     = { t = [...], q = [[...], ...] }                    arm: joint waypoints [rad]
    cartesian = { t = [...], xyz = [[...]], rpy = [[...]] }        arm: tool poses, chain root frame
    velocity  = { t = [...], vx = [...], vy = [...], yaw_rate = [...] }   quadruped [m/s], [rad/s]
    position  = { t = [...], xyz = [[...]], yaw = [...] }          aerial, world [m], [rad]

Times [s] start at 0 and increase. Between points: arm, a quintic through the points (zero
velocity and acceleration at the ends: `kl.QuinticTrajectory`, the `jtraj` of Corke's toolbox);
quadruped and aerial, piecewise linear (`interpolation = "step"` holds each point until the
next instead); after the last point the reference holds.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

FAMILY_OF = {"joint": "arm", "cartesian": "arm", "velocity": "quadruped", "position": "aerial"}
_KEYS = {"joint": ({"t", "q"}, set()),
         "cartesian": ({"t", "xyz"}, {"rpy", "q0"}),
         "velocity": ({"t", "vx"}, {"vy", "yaw_rate", "gait", "interpolation"}),
         "position": ({"t", "xyz"}, {"yaw", "interpolation"})}


@dataclass(frozen=True)
class Reference:
    kind: str                     # joint | cartesian | velocity | position
    t: np.ndarray                 # (k) [s]
    values: dict = field(default_factory=dict)   # name -> (k, ...) arrays, as in the file
    interpolation: str = "linear"
    gait: tuple | None = None     # quadruped: "stand" / "trot" per point (None: derived)

    @property
    def family(self) -> str:
        return FAMILY_OF[self.kind]

    @property
    def end_time(self) -> float:
        return float(self.t[-1])

    def sample(self, name: str, times: np.ndarray) -> np.ndarray:
        """A piecewise-linear (or step) value at `times` [s], held outside the points."""
        v = self.values[name]
        if self.interpolation == "step":
            k = np.clip(np.searchsorted(self.t, times, side="right") - 1, 0, len(self.t) - 1)
            return v[k]
        if v.ndim == 1:
            return np.interp(times, self.t, v)
        return np.stack([np.interp(times, self.t, v[:, j]) for j in range(v.shape[1])], axis=1)

    def slope(self, name: str, times: np.ndarray) -> np.ndarray:
        """d/dt of sample() (0 for steps and outside the points): a velocity feed-forward."""
        v = self.values[name]
        if self.interpolation == "step" or len(self.t) < 2:
            return np.zeros((len(times),) + v.shape[1:])
        k = np.clip(np.searchsorted(self.t, times, side="right") - 1, 0, len(self.t) - 2)
        rate = (v[1:] - v[:-1]) / np.diff(self.t).reshape((-1,) + (1,) * (v.ndim - 1))
        inside = (times >= self.t[0]) & (times < self.t[-1])
        return np.where(inside.reshape((-1,) + (1,) * (v.ndim - 1)), rate[k], 0.0)


def _array(value, what: str, width: int | None) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{what}: expected numbers, got {value!r}") from None
    if width is None and a.ndim != 1:
        raise ValueError(f"{what}: expected a list of numbers")
    if width is not None and (a.ndim != 2 or (width > 0 and a.shape[1] != width)):
        shape = f"[[{', '.join(['x'] * width)}], ...]" if width > 0 else "[[...], ...]"
        raise ValueError(f"{what}: expected a list of rows {shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{what}: every value must be finite")
    return a


def parse(table) -> Reference:
    """The `[reference]` table; raises ValueError("key: what") naming the offending key."""
    if not isinstance(table, dict) or len(table) != 1:
        raise ValueError(f"expected exactly one of {', '.join(FAMILY_OF)}"
                         + (f", got {', '.join(table)}" if isinstance(table, dict) and table else ""))
    kind, body = next(iter(table.items()))
    if kind not in FAMILY_OF:
        raise ValueError(f"unknown reference {kind!r}; expected one of {', '.join(FAMILY_OF)}")
    if not isinstance(body, dict):
        raise ValueError(f"{kind}: expected a table such as {{ t = [...], ... }}")
    required, optional = _KEYS[kind]
    unknown = set(body) - required - optional
    if unknown:
        raise ValueError(f"{kind}.{sorted(unknown)[0]}: unknown key; known: "
                         f"{', '.join(sorted(required | optional))}")
    missing = required - set(body)
    if missing:
        raise ValueError(f"{kind}.{sorted(missing)[0]}: missing")
    t = _array(body["t"], f"{kind}.t", None)
    if len(t) < 1 or t[0] != 0.0 or np.any(np.diff(t) <= 0):
        raise ValueError(f"{kind}.t: times must start at 0 and increase, got {body['t']!r}")
    values = {}
    widths = {"q": 0, "xyz": 3, "rpy": 3, "vx": None, "vy": None, "yaw_rate": None, "yaw": None}
    for name, width in widths.items():
        if name in body:
            a = _array(body[name], f"{kind}.{name}", width)
            if len(a) != len(t):
                raise ValueError(f"{kind}.{name}: {len(a)} points for {len(t)} times")
            values[name] = a
    if kind == "joint" and len({len(row) for row in values["q"]}) != 1:
        raise ValueError("joint.q: every row needs the same number of joints")
    if kind == "velocity":
        for name in ("vy", "yaw_rate"):
            values.setdefault(name, np.zeros(len(t)))
    if kind == "position":
        values.setdefault("yaw", np.zeros(len(t)))
    if kind == "cartesian":
        values.setdefault("rpy", np.full((len(t), 3), np.nan))  # nan: keep the start orientation
        if "q0" in body:
            values["q0"] = _array(body["q0"], "cartesian.q0", None)
    interpolation = body.get("interpolation", "linear")
    if interpolation not in ("linear", "step"):
        raise ValueError(f"{kind}.interpolation: expected \"linear\" or \"step\", got "
                         f"{interpolation!r}")
    gait = None
    if "gait" in body:
        gait = body["gait"]
        if (not isinstance(gait, list) or len(gait) != len(t)
                or any(g not in ("stand", "trot") for g in gait)):
            raise ValueError(f"velocity.gait: expected one of \"stand\" / \"trot\" per point "
                             f"({len(t)}), got {gait!r}")
        gait = tuple(gait)
    return Reference(kind, t, values, interpolation, gait)
