"""A SIL run that logs every input and output of the family's controller (the b2b log).

The scenario runs unchanged: while it runs, `kiloloop.<Controller>` makes controllers wrapped in
RecordedController, which passes every call through and appends each step's input and output
records (C++ firmware/record.hpp: raw doubles, no printing) to its log. The config and model each
controller was made with are kept for `kiloloop export`.

Log file: header (magic, family, input and output bytes per tick), then per tick input + output.
"""
from __future__ import annotations

import contextlib
import hashlib
import struct
from dataclasses import dataclass
from pathlib import Path

from .families import Family


class RecordedController:
    """A compiled controller whose step() also logs its input and output records."""

    def __init__(self, inner, model, config):
        from .. import _core

        self._inner, self.model, self.config = inner, model, config
        self._record = _core.firmware.record
        self.records: list[bytes] = []
        self.input_bytes = self.output_bytes = 0

    def step(self, inp, out):
        status = self._inner.step(inp, out)
        a, b = self._record(inp), self._record(out)
        self.input_bytes, self.output_bytes = len(a), len(b)
        self.records.append(a + b)
        return status

    def __getattr__(self, name):
        return getattr(self._inner, name)


@contextlib.contextmanager
def recording(family: Family):
    """Within: `kiloloop.<family.controller>(model, config)` makes RecordedControllers, listed
    in the yielded list."""
    import kiloloop as kl

    original = getattr(kl, family.controller)
    made: list[RecordedController] = []

    def make(model, config=None):
        if config is None:
            config = getattr(kl, family.controller.replace("Controller", "Config"))()
        made.append(RecordedController(original(model, config), model, config))
        return made[-1]

    setattr(kl, family.controller, make)
    try:
        yield made
    finally:
        setattr(kl, family.controller, original)


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
    with recording(family) as made:
        result = scenarios.run(module, settings, robot, seed=seed, duration=duration)
    stepped = [c for c in made if c.records]
    if len(stepped) != 1:
        raise RuntimeError(f"{family.scenario}: expected one stepped {family.controller}, "
                           f"found {len(stepped)}")
    return SilRecording(stepped[0], len(stepped[0].records), result.passed)


def write_log(rec: SilRecording, family_code: int, path) -> str:
    """Writes the b2b log; returns its SHA-256."""
    from .. import _core

    c = rec.controller
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    data = struct.pack("<8sqqq", _core.firmware.LOG_MAGIC, family_code, c.input_bytes,
                       c.output_bytes) + b"".join(c.records)
    path.write_bytes(data)
    return hashlib.sha256(data).hexdigest()
