"""Named-signal logging for SIL runs: time series in a dict of numpy arrays, saved as .npz.

A signal may be described (unit, names of its components, a label); the description travels in
the .npz as one extra entry, META_KEY, holding JSON, which load_log leaves out.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

META_KEY = "__meta__"  # the .npz entry holding the descriptions (a JSON string)


class SignalLog:
    """Appends one sample per tick for each named signal (scalars or fixed-shape arrays).

    `log.record("q", q)` copies the value, so callers may reuse their buffers. `log["q"]` is
    the stacked array (ticks, ...) of everything recorded under that name.
    """

    def __init__(self):
        self._series: dict[str, list] = {}
        # Whole series handed over at once (the native loop's preallocated arrays): kept stacked.
        self._stacked: dict[str, np.ndarray] = {}
        # name -> {"unit": str, "components": list[str] | None, "label": str | None}
        self._meta: dict[str, dict] = {}

    def describe(self, name: str, unit: str, components=None, label: str | None = None) -> None:
        """Says what a signal is: its unit ("m", "rad", "N m"; "" for none), the names of its
        components along the first axis after time (joint names, ["x", "y", "z"], foot names),
        and a label for people. A signal may be described before or after it is recorded."""
        names = None if components is None else [str(c) for c in components]
        self._meta[name] = {"unit": str(unit), "components": names,
                            "label": None if label is None else str(label)}

    def unit(self, name: str) -> str:
        """The signal's unit, "" when not described."""
        return self._meta.get(name, {}).get("unit", "")

    def components(self, name: str) -> list[str] | None:
        """Names of the signal's components (first axis after time), None when not described."""
        c = self._meta.get(name, {}).get("components")
        return None if c is None else list(c)

    def label(self, name: str) -> str:
        """The signal's label, or its name when it has none."""
        return self._meta.get(name, {}).get("label") or name

    def described(self) -> dict[str, dict]:
        """Every description, by signal name (a copy)."""
        return {k: dict(v) for k, v in self._meta.items()}

    def record(self, name: str, value) -> None:
        if name in self._stacked:
            self._series[name] = list(self._stacked.pop(name))
        self._series.setdefault(name, []).append(np.array(value, dtype=float, copy=True))

    def put_array(self, name: str, series: np.ndarray) -> None:
        """Stores a stacked series (ticks, ...) as it is (no per-tick copies)."""
        self._series[name] = []
        self._stacked[name] = np.asarray(series, dtype=float)

    def put(self, name: str, series) -> None:
        """Stores a whole series computed after the run (e.g. a reference derived from the log)."""
        self._stacked.pop(name, None)
        self._series[name] = [np.array(v, dtype=float, copy=True) for v in series]

    def last(self, name: str) -> np.ndarray:
        """The most recent sample of a signal (cheap: no stacking)."""
        if name in self._stacked:
            return self._stacked[name][-1]
        return self._series[name][-1]

    def names(self) -> list[str]:
        return list(self._series)

    def __contains__(self, name: str) -> bool:
        return name in self._series

    def __getitem__(self, name: str) -> np.ndarray:
        if name in self._stacked:
            return self._stacked[name]
        return np.stack(self._series[name])

    def as_dict(self) -> dict[str, np.ndarray]:
        return {name: self[name] for name in self._series}

    def save(self, path) -> Path:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        arrays = self.as_dict()
        if META_KEY in arrays:
            raise ValueError(f"a signal may not be named {META_KEY!r}")
        # A 0-d unicode array: np.load reads it back without pickle.
        arrays[META_KEY] = np.array(json.dumps(self._meta, sort_keys=True))
        np.savez_compressed(path, **arrays)
        return path

    @classmethod
    def load(cls, path) -> "SignalLog":
        """A log saved by save(), with its descriptions (a file without them loads undescribed)."""
        log = cls()
        with np.load(path) as data:
            for key in data.files:
                if key == META_KEY:
                    for name, m in json.loads(str(data[key])).items():
                        log.describe(name, m.get("unit", ""), m.get("components"), m.get("label"))
                else:
                    log.put_array(key, data[key])
        return log


def load_log(path) -> dict[str, np.ndarray]:
    """The signal arrays of a saved log, by name (descriptions left out: SignalLog.load)."""
    with np.load(path) as data:
        return {k: data[k] for k in data.files if k != META_KEY}
