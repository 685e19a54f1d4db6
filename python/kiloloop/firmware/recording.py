"""A SIL run that logs every input and output of the family's controller (the b2b log).

The scenario runs unchanged, in the native loop: while it runs, `kiloloop.<Controller>` notes
each controller made of the family's class with the model and config it was made with (for
`kiloloop export`), and every native Rollout made keeps its adapter's controller input and output
records, written in C++ each tick (cpp/sil/io_record.hpp: the firmware/record.hpp bytes the
replay reads). Nothing runs in Python per tick.

Log file: header (magic, family, input and output bytes per tick), then per tick input + output.
"""
from __future__ import annotations

import contextlib
import hashlib
import struct
from dataclasses import dataclass
from pathlib import Path

from .families import Family


@dataclass
class RecordedController:
    """A controller of the family made during the run, and what it stepped."""

    controller: object
    model: object
    config: object
    records: bytes = b""          # per tick: input record, then output record
    input_bytes: int = 0
    output_bytes: int = 0


@contextlib.contextmanager
def recording(family: Family):
    """Within: `kiloloop.<family.controller>(model, config)` is noted in the yielded list of
    RecordedController, and every native Rollout keeps its I/O records (the yielded list of
    (rollout, how many controllers had been made when it was))."""
    import kiloloop as kl

    from ..sil import native

    original = getattr(kl, family.controller)
    made: list[RecordedController] = []
    rollouts: list = []

    def make(model, config=None):
        if config is None:
            config = getattr(kl, family.controller.replace("Controller", "Config"))()
        made.append(RecordedController(original(model, config), model, config))
        return made[-1].controller

    rollout_class = native._native.Rollout

    def make_rollout(*args, **kwargs):
        r = rollout_class(*args, **kwargs)
        try:
            r.record_io()
            rollouts.append((r, len(made)))   # its controller is one made before it
        except ValueError:
            pass   # an adapter whose controller has no firmware family: not a b2b run
        return r

    setattr(kl, family.controller, make)
    native._native.Rollout = make_rollout
    try:
        yield made, rollouts
    finally:
        setattr(kl, family.controller, original)
        native._native.Rollout = rollout_class


@dataclass
class SilRecording:
    controller: RecordedController   # the one that stepped (config, model, records)
    ticks: int
    passed: bool                     # the scenario's own criteria (informative here)


def record_sil_run(robot, family: Family, *, duration: float | None, seed: int | None = 0,
                   sets: dict | None = None, scenario: str | None = None) -> SilRecording:
    """Runs the family's scenario (or the scenario file `scenario`) on `robot` and returns its
    stepped controller's records (duration, seed None: the scenario's own)."""
    from .. import scenarios

    module = scenarios.get(scenario or family.scenario)
    overrides = {**family.settings, **(sets or {})}
    robot, settings = scenarios.prepare(module, robot, overrides)
    with recording(family) as (made, rollouts):
        result = scenarios.run(module, settings, robot, seed=seed, duration=duration)
    stepped = [(r, n) for r, n in rollouts if r.ticks_run > 0]
    name = scenario or family.scenario
    # The run's controller: the one made before its rollout (a scenario may make more afterwards,
    # to name its log's joints); two runs or two candidates are ambiguous.
    if len(stepped) != 1 or stepped[0][1] != 1:
        raise RuntimeError(f"{name}: expected one {family.controller} stepped in one native run, "
                           f"found {len(stepped)} runs and "
                           f"{stepped[0][1] if stepped else len(made)} controllers made before")
    r = stepped[0][0]
    records, input_bytes, output_bytes = r.io_records()
    c = made[0]
    c.records, c.input_bytes, c.output_bytes = records, input_bytes, output_bytes
    return SilRecording(c, r.ticks_run, result.passed)


def write_log(rec: SilRecording, family_code: int, path) -> str:
    """Writes the b2b log; returns its SHA-256."""
    from .. import _core

    c = rec.controller
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    data = struct.pack("<8sqqq", _core.firmware.LOG_MAGIC, family_code, c.input_bytes,
                       c.output_bytes) + c.records
    path.write_bytes(data)
    return hashlib.sha256(data).hexdigest()
