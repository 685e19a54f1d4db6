"""The SIL rig: a robot file's MuJoCo plant, its compiled controller and the signal chain between
them, run by the native loop (the C++ Rollout, sil/native.py). One class for every family:

    rig = Rig(robot, signals=Signals(motor_delay=0.01), seed=0)
    log = rig.run(4.0, reference, events=[(1.0, Push([0, 40, 0], 0.1))], stop=FellBelow(0.15))
    rollout = rig.rollout(4.0, reference, data=mujoco.MjData(rig.plant.model))  # batch.run

A family is data, not a subclass: a Family record (sil/family.py; filled in by arm_family.py,
quadruped_family.py, aerial_family.py) of functions that build the parts from the robot file
(plant, controller), map the measurement (which MuJoCo addresses the controller reads, with which
noise and stages), name the actuators, turn the scenario's reference into the C++ adapter, list
the ground-truth probes and turn events into native events. `run()` is the native loop; video
frames and Python checks happen between ticks (Rollout.advance, native.drive), never inside one.
"""
from __future__ import annotations

from typing import Any

from . import aerial_family, arm_family, native, quadruped_family
from .family import CONTROL_DT, Family
from .log import SignalLog
from .signals import Signals
from .timing import substeps

FAMILIES = {"arm": arm_family.FAMILY, "quadruped": quadruped_family.FAMILY,
            "aerial": aerial_family.FAMILY}


def family_of(name: str) -> Family:
    if name not in FAMILIES:
        raise ValueError(f"no SIL family {name!r}; known: {', '.join(FAMILIES)}")
    return FAMILIES[name]


class Rig:
    """One robot file in the SIL: its parts built once, any number of runs over them.

    robot: a kl.Robot (its `kind` picks the family); signals: the non-idealities (default:
    ideal); seed: their random streams; video: an .mp4 path each run() records; options: the
    family's (Family.build). The family's parts read through the rig: rig.plant, rig.model,
    rig.controller, and e.g. rig.fall_height (a quadruped), rig.n_rotors (a multirotor),
    rig.T_world_root() (an arm)."""

    def __init__(self, robot, signals: Signals | None = None, *, seed: int = 0,
                 video: str | None = None, **options):
        self.robot = robot
        self.family = family_of(robot.kind)
        self.signals = Signals() if signals is None else signals
        self.signals.validate()
        self.seed = int(seed)
        self.video = video
        self.parts = self.family.build(robot, self.signals, self.seed,
                                       dict(options, visual=bool(video)))
        # One substep rule: whole physics steps per control tick, else a clear refusal.
        substeps(self.plant.model.opt.timestep, CONTROL_DT)

    def __getattr__(self, name: str) -> Any:
        # The family's parts (plant, model, controller, config, fall_height, ...).
        if name == "parts":
            raise AttributeError(name)
        try:
            return getattr(self.parts, name)
        except AttributeError:
            raise AttributeError(f"{type(self).__name__} of a {self.family.name} has no "
                                 f"{name!r}") from None

    def adapter(self, reference, controller=None, ticks: int = 1):
        """The C++ adapter of `reference` on the rig's controller (or on `controller`, another
        one of the same configuration: a batch gives each rollout its own); ticks: the run's
        length where the reference is sampled into a table (a multirotor's command)."""
        return self.family.adapter(self.parts, reference, controller, ticks)

    def rollout(self, duration: float, reference, events=(), *, stop=None, observe=None,
                probes=(), stages=(), disturbances=(), data=None, seed: int | None = None,
                adapter=None):
        """A configured native Rollout of `duration` [s] (run it with .run(), batch.run or
        native.drive). events: (time [s], event) pairs of sil/events.py; stop: a FellBelow;
        observe: extra ground truth (family-specific: an arm's native.Observe); probes: more
        (name, source, ids) probes after the family's (native.contact_count, geom_distance);
        stages: more C++ measurement stages after the signal chain's (a sensor dropout);
        disturbances: a Wind (sil/aerial_signals.py) or a C++ disturbance model; data: another
        MjData of plant.model (native.start_state); seed: another noise stream; adapter: one
        built with adapter(reference, controller)."""
        native.check()
        f, p = self.family, self.parts
        seed = self.seed if seed is None else int(seed)
        ticks = native.ticks_of(duration, CONTROL_DT)
        # What the caller asked for is checked before anything is built for the run.
        timed = f.events(p, list(events))
        stop_tuple = f.stop(p, stop)
        m = f.measurement(p, self.signals, seed, reference)
        motor = f.motor(p, self.signals)
        adapter = adapter if adapter is not None else f.adapter(p, reference, None, ticks)
        return native._native.Rollout(
            self.plant.model, native.start_state(self.plant, data), adapter,
            ticks=ticks, control_dt=CONTROL_DT,
            measurement=m.addresses, measurement_source=m.sources, actuators=f.actuators(p),
            delay_ticks=self.signals.ticks("measurement_delay", CONTROL_DT),
            sigma=m.sigma, quantum=m.quantum, seed=seed, stages=m.stages + list(stages),
            motor_delay_ticks=motor.delay_ticks, motor_time_constant=motor.time_constant,
            motor_limit=list(motor.limit), motor_hold_first=motor.hold_first,
            events=f.reference_events(p, reference) + timed,
            probes=f.probes(p, observe) + list(probes), stop=stop_tuple,
            disturbances=[d.model(self.plant) if hasattr(d, "model") else d for d in disturbances],
            stop_nonfinite=f.stop_nonfinite)

    def run(self, duration: float, reference, events=(), *, log: SignalLog | None = None,
            hooks=(), video: str | None = None, **rollout_options) -> SignalLog:
        """The closed loop for `duration` [s] in C++, returned as a SignalLog ("t", the adapter's
        channels, the probes; "diverged" when a flight's physics went non-finite). hooks: (tick,
        fn(model, data)) run once that tick is done (a payload attached mid-run); video: an .mp4
        path (default the rig's), frames captured between ticks. RuntimeError if MuJoCo failed."""
        r = self.rollout(duration, reference, events, **rollout_options)
        native.drive(r, self.plant.model, self.plant.data, video=video or self.video,
                     camera_body=self.family.camera_body(self.parts), hooks=hooks)
        log = native.signal_log(r, log)
        if self.family.stop_nonfinite and r.diverged:
            log.record("diverged", 1.0)
        return log
