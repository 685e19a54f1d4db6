"""The `[[events]]` of a scenario file: what happens at a time `t` [s] of the run.

    push            impulse = [x, y, z] [N s], world frame, spread over `duration` [s]
                    (default 0.1 s) as a constant force on the base (quadruped, aerial: at the
                    vehicle's CoM) or the chain's tip (arm), or on `body` (a link name)
    rotor_fault     rotor (robot file order, from 0), efficiency (0..1 of thrust and drag torque)
    estop           the e-stop input goes high: an arm's supervisor stops it and holds (arms only)
    sensor_dropout  sensor = "imu" | "joints" | "position" (a multirotor's motion capture),
                    duration [s]: the measurement stays frozen at its last sample (a bus that
                    stops updating; the controller is not told)
    payload         mass [kg], com = [x, y, z] [m] in the body's frame: a point mass rigidly
                    attached to the tip (arm) or the base, or to `body`
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

PUSH_DURATION = 0.1  # [s] a short shove, as the built-in push scenarios use


@dataclass(frozen=True)
class Push:
    t: float
    impulse: tuple          # [N s] world frame
    duration: float = PUSH_DURATION
    body: str | None = None

    @property
    def force(self) -> np.ndarray:
        return np.asarray(self.impulse, float) / self.duration


@dataclass(frozen=True)
class RotorFault:
    t: float
    rotor: int
    efficiency: float


@dataclass(frozen=True)
class Estop:
    t: float


@dataclass(frozen=True)
class SensorDropout:
    t: float
    sensor: str             # imu | joints | position
    duration: float


@dataclass(frozen=True)
class Payload:
    t: float
    mass: float             # [kg]
    com: tuple = (0.0, 0.0, 0.0)   # [m] body frame
    body: str | None = None


# kind -> (class, required keys, optional keys)
KINDS = {
    "push": (Push, {"impulse"}, {"duration", "body"}),
    "rotor_fault": (RotorFault, {"rotor", "efficiency"}, set()),
    "estop": (Estop, set(), set()),
    "sensor_dropout": (SensorDropout, {"sensor", "duration"}, set()),
    "payload": (Payload, {"mass"}, {"com", "body"}),
}
# Which families each kind applies to.
FAMILIES = {"push": {"arm", "quadruped", "aerial"}, "rotor_fault": {"aerial"}, "estop": {"arm"},
            "sensor_dropout": {"arm", "quadruped", "aerial"},
            "payload": {"arm", "quadruped", "aerial"}}
SENSORS = ("imu", "joints", "position")


def _number(value, what: str, lo=-math.inf, hi=math.inf, strict_lo=False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{what}: expected a finite number, got {value!r}")
    if value < lo or value > hi or (strict_lo and value == lo):
        bound = f"> {lo:g}" if strict_lo else f">= {lo:g}"
        raise ValueError(f"{what}: expected {bound}{'' if hi == math.inf else f' and <= {hi:g}'}, "
                         f"got {value!r}")
    return float(value)


def _vector(value, what: str) -> tuple:
    if not isinstance(value, list) or len(value) != 3:
        raise ValueError(f"{what}: expected [x, y, z], got {value!r}")
    return tuple(_number(v, what) for v in value)


def parse(index: int, table, family: str):
    """events[index]; raises ValueError("events[i].key: what")."""
    at = f"events[{index}]"
    if not isinstance(table, dict):
        raise ValueError(f"{at}: expected a table with t and kind")
    kind = table.get("kind")
    if kind not in KINDS:
        raise ValueError(f"{at}.kind: expected one of {', '.join(KINDS)}, got {kind!r}")
    cls, required, optional = KINDS[kind]
    if family not in FAMILIES[kind]:
        raise ValueError(f"{at}.kind: {kind} is not available for the {family} family "
                         f"(only {', '.join(sorted(FAMILIES[kind]))})")
    unknown = set(table) - required - optional - {"t", "kind"}
    if unknown:
        raise ValueError(f"{at}.{sorted(unknown)[0]}: unknown key for {kind}; known: "
                         f"{', '.join(sorted(required | optional | {'t', 'kind'}))}")
    missing = ({"t"} | required) - set(table)
    if missing:
        raise ValueError(f"{at}.{sorted(missing)[0]}: missing")
    t = _number(table["t"], f"{at}.t", 0.0)
    if kind == "push":
        return Push(t, _vector(table["impulse"], f"{at}.impulse"),
                    _number(table.get("duration", PUSH_DURATION), f"{at}.duration", 0.0, strict_lo=True),
                    _name(table.get("body"), f"{at}.body"))
    if kind == "rotor_fault":
        rotor = table["rotor"]
        if isinstance(rotor, bool) or not isinstance(rotor, int) or rotor < 0:
            raise ValueError(f"{at}.rotor: expected a rotor index >= 0, got {rotor!r}")
        return RotorFault(t, rotor, _number(table["efficiency"], f"{at}.efficiency", 0.0, 1.0))
    if kind == "estop":
        return Estop(t)
    if kind == "sensor_dropout":
        if table["sensor"] not in SENSORS:
            raise ValueError(f"{at}.sensor: expected one of {', '.join(SENSORS)}, got "
                             f"{table['sensor']!r}")
        return SensorDropout(t, table["sensor"],
                             _number(table["duration"], f"{at}.duration", 0.0, strict_lo=True))
    return Payload(t, _number(table["mass"], f"{at}.mass", 0.0, strict_lo=True),
                   _vector(table.get("com", [0.0, 0.0, 0.0]), f"{at}.com"),
                   _name(table.get("body"), f"{at}.body"))


def _name(value, what: str) -> str | None:
    if value is not None and not (isinstance(value, str) and value):
        raise ValueError(f"{what}: expected a link name, got {value!r}")
    return value
