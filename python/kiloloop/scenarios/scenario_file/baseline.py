"""Baselines: a run's signals saved once (`--save-baseline base.npz`, or any `--log` .npz or
.mcap) and later runs compared with them, signal by signal, as Simulink Test's baseline criteria do.

    [baseline]
    file = "base.npz"                         # relative to the scenario file
    signals = { q = { abs = 1e-6 }, ee_error = { abs = 1e-4, rel = 0.01 }, tau = "exact" }

A sample passes when |run - base| <= abs + rel |base| (both default 0: `"exact"` is the same,
bit for bit, NaN equal to NaN). The two runs must have the same ticks. The report names the
first signal and time outside its tolerance, with both values.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class Tolerance:
    abs: float = 0.0
    rel: float = 0.0

    @property
    def exact(self) -> bool:
        return self.abs == 0.0 and self.rel == 0.0

    def __str__(self) -> str:
        return "bit for bit" if self.exact else f"abs {self.abs:g}, rel {self.rel:g}"


@dataclass(frozen=True)
class BaselineSpec:
    file: Path | None                    # None: given on the command line
    signals: dict                        # name -> Tolerance; empty: every signal, exact


def parse_tolerance(value, what: str) -> Tolerance:
    if value == "exact":
        return Tolerance()
    if isinstance(value, dict) and set(value) <= {"abs", "rel"} and value:
        out = {}
        for k, v in value.items():
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not v >= 0:
                raise ValueError(f"{what}.{k}: expected a number >= 0, got {v!r}")
            out[k] = float(v)
        return Tolerance(**out)
    raise ValueError(f"{what}: expected \"exact\" or {{ abs = ..., rel = ... }}, got {value!r}")


def parse(table, base_dir: Path | None, signals: dict) -> BaselineSpec:
    if not isinstance(table, dict):
        raise ValueError("expected a table with file and signals")
    unknown = set(table) - {"file", "signals"}
    if unknown:
        raise ValueError(f"{sorted(unknown)[0]}: unknown key; known: file, signals")
    file = table.get("file")
    if file is not None and not (isinstance(file, str) and file):
        raise ValueError(f"file: expected a path, got {file!r}")
    path = None if file is None else (Path(file) if base_dir is None else base_dir / file)
    given = table.get("signals", {})
    if not isinstance(given, dict):
        raise ValueError("signals: expected a table { signal = tolerance, ... }")
    tolerances = {}
    for name, tol in given.items():
        if name not in signals and name != "t":
            raise ValueError(f"signals.{name}: unknown signal; this family's: {', '.join(signals)}")
        tolerances[name] = parse_tolerance(tol, f"signals.{name}")
    return BaselineSpec(path, tolerances)


def save(log, path, names) -> Path:
    """Writes the signals `names` (and t) of a run as a baseline (.npz)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(path, **{n: log[n] for n in ["t", *names] if n in log})
    return path


def _outside(a: np.ndarray, b: np.ndarray, tol: Tolerance) -> np.ndarray:
    """Per tick: whether any component of a is outside the tolerance around b."""
    if tol.exact:
        same = (a == b) | (np.isnan(a) & np.isnan(b))
    else:
        with np.errstate(invalid="ignore"):
            same = np.abs(a - b) <= tol.abs + tol.rel * np.abs(b)
    return ~same.reshape(len(a), -1).all(axis=1)


def compare(log, path, spec_signals: dict, components: dict | None = None) -> dict:
    """The baseline's row of the criteria table: passed, and where the first difference is.
    spec_signals: name -> Tolerance (empty: every signal the baseline holds, bit for bit);
    components: signal -> component names, to name the differing one."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"baseline file {path} not found (write it with --save-baseline)")
    from ...sil.log import load_log

    base = load_log(path)   # a --save-baseline file, or any --log (.npz or .mcap)
    names = list(spec_signals) or [n for n in base if n != "t"]
    row = {"op": "within", "threshold": 0.0, "value": 0.0, "passed": True, "file": str(path)}
    t = np.asarray(log["t"])
    if "t" not in base or base["t"].shape != t.shape or not np.array_equal(base["t"], t):
        row.update(passed=False, value=float("nan"),
                   reason=f"the run has {len(t)} ticks to {t[-1] if len(t) else 0:g} s, the "
                          f"baseline {len(base.get('t', []))}: not the same ticks")
        return row
    first = None   # (tick, name)
    for name in names:
        if name not in base:
            row.update(passed=False, reason=f"{name}: not in the baseline {path}")
            return row
        if name not in log:
            row.update(passed=False, reason=f"{name}: not in this run's log")
            return row
        a, b = np.asarray(log[name], float), base[name]
        if a.shape != b.shape:
            row.update(passed=False, reason=f"{name}: shape {a.shape} against the baseline's {b.shape}")
            return row
        bad = np.nonzero(_outside(a, b, spec_signals.get(name, Tolerance())))[0]
        if len(bad) and (first is None or bad[0] < first[0]):
            first = (int(bad[0]), name)
    if first is not None:
        k, name = first
        tol = spec_signals.get(name, Tolerance())
        a = np.atleast_1d(np.asarray(log[name], float)[k]).ravel()
        b = np.atleast_1d(base[name][k]).ravel()
        j = int(np.nonzero(_outside(a[None, :].T, b[None, :].T, tol))[0][0]) if a.size > 1 else 0
        names = (components or {}).get(name)
        label = name if a.size == 1 else f"{name}[{names[j] if names and j < len(names) else j}]"
        row.update(passed=False, value=float(t[k]), signal=name, tick=k,
                   reason=f"first outside tolerance ({tol}): {label} at t = {t[k]:.3f} s: "
                          f"{float(a[j])!r} against the baseline's {float(b[j])!r}")
    return row
