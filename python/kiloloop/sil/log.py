"""Named-signal logging for SIL runs: time series in a dict of numpy arrays, saved as .npz or
as MCAP (.mcap: Foxglove, PlotJuggler and ROS 2 tools open it; the layout: log_mcap.py).

A signal may be described (unit, names of its components, a label, a frame); a log may carry what
run made it (`info`: scenario, robot, settings, criteria; scenarios/run_info.py fills it). In the
.npz both travel as extra entries holding JSON, META_KEY and RUN_KEY, which load_log leaves out.
Both formats read back into the same SignalLog, every value bit for bit.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

META_KEY = "__meta__"  # the .npz entry holding the descriptions (a JSON string)
RUN_KEY = "__run__"    # the .npz entry holding `info`, what run made the log (a JSON string)
RESERVED = (META_KEY, RUN_KEY)
MCAP_MAGIC = b"\x89MCAP0\r\n"  # the first bytes of every MCAP file (a .npz is a zip: b"PK")


class SignalLog:
    """Appends one sample per tick for each named signal (scalars or fixed-shape arrays).

    `log.record("q", q)` copies the value, so callers may reuse their buffers. `log["q"]` is
    the stacked array (ticks, ...) of everything recorded under that name.
    """

    def __init__(self):
        self._series: dict[str, list] = {}
        # Whole series handed over at once (the native loop's preallocated arrays): kept stacked.
        self._stacked: dict[str, np.ndarray] = {}
        # name -> {"unit": str, "components": list[str] | None, "label": str | None,
        #          "frame": str | None}
        self._meta: dict[str, dict] = {}
        # What run made the log: section -> {key: JSON value} ("scenario", "robot", "run",
        # "settings", "criteria", "metrics"; scenarios/run_info.py). Empty for a bare log.
        self.info: dict[str, dict] = {}

    def describe(self, name: str, unit: str, components=None, label: str | None = None,
                 frame: str | None = None) -> None:
        """Says what a signal is: its unit ("m", "rad", "N m"; "" for none), the names of its
        components along the first axis after time (joint names, ["x", "y", "z"], foot names),
        a label for people and the frame its vectors are expressed in ("world", "trunk",
        "heading"; None where it has none or it is not a spatial quantity). A signal may be
        described before or after it is recorded."""
        names = None if components is None else [str(c) for c in components]
        self._meta[name] = {"unit": str(unit), "components": names,
                            "label": None if label is None else str(label),
                            "frame": None if frame is None else str(frame)}

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

    def frame(self, name: str) -> str:
        """The frame the signal is expressed in, "" when it has none or is not described."""
        return self._meta.get(name, {}).get("frame") or ""

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

    def descriptions_json(self) -> str:
        """The descriptions as one JSON text (what the .npz's META_KEY entry holds)."""
        return json.dumps(self._meta, sort_keys=True)

    def describe_from_json(self, text: str) -> None:
        """Describes the signals from descriptions_json()'s text (older files lack "frame")."""
        for name, m in json.loads(text).items():
            self.describe(name, m.get("unit", ""), m.get("components"), m.get("label"),
                          m.get("frame"))

    def save(self, path) -> Path:
        """Writes the log: MCAP for a `.mcap` path (log_mcap.py), a compressed .npz for `.npz`;
        any other suffix is a ValueError (numpy would append .npz behind the caller's back)."""
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in (".npz", ".mcap"):
            raise ValueError(f"{path}: a log is saved as .npz or .mcap, not {path.suffix!r}")
        for key in RESERVED:
            if key in self._series:
                raise ValueError(f"a signal may not be named {key!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        if suffix == ".mcap":
            from .log_mcap import write

            return write(self, path)
        arrays = self.as_dict()
        # 0-d unicode arrays: np.load reads them back without pickle. `info` keeps its key order
        # (the criteria table's rows), so no sort_keys.
        arrays[META_KEY] = np.array(self.descriptions_json())
        if self.info:
            arrays[RUN_KEY] = np.array(json.dumps(self.info))
        np.savez_compressed(path, **arrays)
        return path

    @classmethod
    def load(cls, path) -> "SignalLog":
        """A log saved by save(), .npz or MCAP (told apart by the file's first bytes), with its
        descriptions and info (a .npz without them loads undescribed)."""
        if is_mcap(path):
            from .log_mcap import read

            return read(path, cls())
        log = cls()
        with np.load(path) as data:
            for key in data.files:
                if key == META_KEY:
                    log.describe_from_json(str(data[key]))
                elif key == RUN_KEY:
                    log.info = json.loads(str(data[key]))
                else:
                    log.put_array(key, data[key])
        return log


def is_mcap(path) -> bool:
    """Whether the file at `path` is MCAP (its magic bytes), not .npz."""
    with open(path, "rb") as f:
        return f.read(len(MCAP_MAGIC)) == MCAP_MAGIC


def load_log(path) -> dict[str, np.ndarray]:
    """The signal arrays of a saved log (.npz or .mcap), by name, each with the dtype it was
    saved with (descriptions and info left out: SignalLog.load)."""
    if is_mcap(path):
        from .log_mcap import read_arrays

        return read_arrays(path)
    with np.load(path) as data:
        return {k: data[k] for k in data.files if k not in RESERVED}
