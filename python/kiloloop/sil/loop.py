"""The 1 kHz SIL loop: read sensors -> controller step -> write torques -> physics substeps.

Everything robot-specific stays outside: the plant (sil/plant.py) and a `tick` callable that maps
the measurement onto a compiled kiloloop controller and returns the torque command.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np

from .log import SignalLog
from .timing import substeps, whole_periods


class Plant(Protocol):
    timestep: float

    def q(self) -> np.ndarray: ...
    def qd(self) -> np.ndarray: ...
    def set_torque(self, tau) -> None: ...
    def step(self, n: int = 1) -> None: ...
    def time(self) -> float: ...


@dataclass(frozen=True)
class Measurement:
    t: float          # [s] controller time of this tick
    stamp: float      # [s] when the measurement was sampled (earlier than t when delayed)
    q: np.ndarray     # (nq) [rad]
    qd: np.ndarray    # (nq) [rad/s]


# tick(measurement, log) -> torque command (nq) [N m]
TickFn = Callable[[Measurement, SignalLog], np.ndarray]
# observe(plant, log): records ground truth from the simulator (never seen by the controller)
ObserveFn = Callable[[Plant, SignalLog], None]


@dataclass(frozen=True)
class LoopSettings:
    duration: float = 1.0        # [s] simulated time
    control_dt: float = 0.001    # [s] controller period (1 kHz)
    delay_ticks: int = 0         # measurement delay in ticks (0 or 1 typically)

    def substeps(self, physics_dt: float) -> int:
        return substeps(physics_dt, self.control_dt)


def run_loop(plant: Plant, tick: TickFn, settings: LoopSettings, log: SignalLog | None = None,
             observe: ObserveFn | None = None) -> SignalLog:
    """Runs the closed loop for settings.duration and returns the log ("t" plus what tick logs)."""
    log = SignalLog() if log is None else log
    substeps = settings.substeps(plant.timestep)
    n_ticks = whole_periods(settings.duration, settings.control_dt)
    # Measurements wait in a FIFO to model a transport delay of whole ticks.
    pending: deque[tuple[float, np.ndarray, np.ndarray]] = deque()
    for k in range(n_ticks):
        t = k * settings.control_dt
        pending.append((t, plant.q(), plant.qd()))
        stamp, q, qd = pending[0] if len(pending) > settings.delay_ticks else pending[-1]
        if len(pending) > settings.delay_ticks:
            pending.popleft()
        log.record("t", t)
        if observe is not None:
            observe(plant, log)
        tau = tick(Measurement(t=t, stamp=stamp, q=q, qd=qd), log)
        plant.set_torque(tau)
        plant.step(substeps)
    return log
