"""What happens during a run, as data: events at a time, stop conditions. A rig's family turns
them into the native loop's events (cpp/sil/events.hpp): nothing runs in Python per tick.

    rig.run(4.0, reference, events=[(1.0, Push([0, 40, 0], 0.1)), (2.0, EStop())])

Times in [s]; forces world frame [N]; quaternions w, x, y, z.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Event kinds of cpp/sil/events.hpp.
ESTOP, REFERENCE, FORCE, GAIN = 0, 1, 2, 3


@dataclass
class Push:
    """A constant world-frame force [N] for `duration` [s] (whole physics steps, half up), on the
    family's base (a trunk's CoM, a vehicle's CoM, an arm's tip) or on `body` (a MuJoCo body
    name or id)."""

    force: np.ndarray
    duration: float
    body: str | int | None = None

    def __post_init__(self):
        self.force = np.asarray(self.force, dtype=float)
        if self.force.shape != (3,):
            raise ValueError(f"Push.force: expected 3 values, got {self.force.shape}")


@dataclass
class RotorFault:
    """Rotor `rotor` (robot file order) at `efficiency` (thrust and drag torque, 0..1) from then
    on; it writes the rollout's mjModel (a batch gives such a run its own model)."""

    rotor: int
    efficiency: float


@dataclass
class EStop:
    """The e-stop input pressed (or released) from then on (an arm with a supervisor)."""

    pressed: bool = True


@dataclass
class ReferenceOffset:
    """From then on the reference is shifted by `offset` (joint references: (nq) [rad];
    Cartesian: (3) [m])."""

    offset: np.ndarray


@dataclass
class FellBelow:
    """Stop condition: the run ends after the first tick whose trunk height is below `height` [m]
    (a fall ends a legged run)."""

    height: float


def force_event(time: float, body: int, wrench, duration: float,
                at_subtree_com: bool = False) -> tuple:
    """A native force event: wrench (fx, fy, fz, tx, ty, tz) [N, N m], world frame, on MuJoCo
    body `body` for `duration` [s] from `time` [s]; at_subtree_com: at the body's subtree CoM
    (a vehicle's) instead of its own."""
    w = [float(x) for x in wrench]
    if len(w) != 6:
        raise ValueError(f"wrench: expected 6 values, got {len(w)}")
    at_com = [1.0] if at_subtree_com else []
    return (float(time), FORCE, [float(body)] + w + [float(duration)] + at_com)
