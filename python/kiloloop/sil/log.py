"""Named-signal logging for SIL runs: time series in a dict of numpy arrays, saved as .npz."""
from __future__ import annotations

from pathlib import Path

import numpy as np


class SignalLog:
    """Appends one sample per tick for each named signal (scalars or fixed-shape arrays).

    `log.record("q", q)` copies the value, so callers may reuse their buffers. `log["q"]` is
    the stacked array (ticks, ...) of everything recorded under that name.
    """

    def __init__(self):
        self._series: dict[str, list] = {}
        # Whole series handed over at once (the native loop's preallocated arrays): kept stacked.
        self._stacked: dict[str, np.ndarray] = {}

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
        np.savez_compressed(path, **self.as_dict())
        return path


def load_log(path) -> dict[str, np.ndarray]:
    with np.load(path) as data:
        return {k: data[k] for k in data.files}
