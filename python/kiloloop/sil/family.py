"""A robot family of the SIL rig (sil/rig.py), as data: the record of functions that turn a
robot file into the native loop's parts, and the two small records they return (what the
controller measures, what the motors do). One module per family fills it in (arm_family.py,
quadruped_family.py, aerial_family.py)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from .timing import CONTROL_DT  # noqa: F401  (the families' control period, 1 kHz)


@dataclass(frozen=True)
class Measurement:
    """What the controller reads and how it is spoiled: y's MuJoCo addresses and their sources
    (0 sensordata, 1 qpos, 2 qvel), white noise and quantization per element (empty: none), and
    the run's own C++ sensor stages (fresh per run: they carry state and a random stream)."""

    addresses: list
    sources: list
    sigma: list
    quantum: list
    stages: list


@dataclass(frozen=True)
class Motor:
    """The C++ motor model of a run: transport delay [ticks], first-order lag [s], saturation
    per actuator (empty: none), and whether the first command is held until the delay has passed
    (a vehicle's ESC) instead of zero torque (a drive with no command)."""

    delay_ticks: int = 0
    time_constant: float = 0.0
    limit: tuple = ()
    hold_first: bool = False


@dataclass(frozen=True)
class Family:
    """One robot family as data. Each function takes the parts `build` returned.

    build(robot, signals, seed, options) -> parts (plant, model, controller, ...; options are the
        family's keywords of Rig: scene, slope_deg, terrain, config...)
    measurement(parts, signals, seed, reference) -> Measurement
    motor(parts, signals) -> Motor
    actuators(parts) -> MuJoCo actuator ids of u, in order
    adapter(parts, reference, controller, ticks) -> the C++ adapter (controller None: the
        parts'; ticks: the run's length, for references sampled into a table)
    reference_events(parts, reference) -> native events the reference schedules
    events(parts, [(t, event)]) -> native events (sil/events.py types)
    probes(parts, observe) -> ground-truth probes (observe: the caller's extra request or None)
    stop(parts, stop) -> the Rollout's stop tuple (probe, element, below) or None
    camera_body(parts) -> the MuJoCo body a video follows
    """

    name: str
    build: Callable
    measurement: Callable
    motor: Callable
    actuators: Callable
    adapter: Callable
    reference_events: Callable
    events: Callable
    probes: Callable
    stop: Callable
    camera_body: Callable
    stop_nonfinite: bool = False   # a diverged physics state ends the run (a flight)
