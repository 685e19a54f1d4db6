"""Criteria of a scenario file: `"function(signal[, t0[, t1]])" = "op threshold"`.

A criterion reduces one signal over a time window [t0, t1] (seconds of simulated time, both
ends included; t1 defaults to the end of the run) to one number and compares it with a
threshold. Functions: max, min, max_abs, rms, mean, final (the last sample of the window). A
vector signal (q, tau, thrust) is reduced over all of its components, or over one named
`signal[component]` (a joint name, x/y/z, a rotor index; `kiloloop signals ROBOT` lists them).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

FUNCTIONS = {
    "max": np.max,
    "min": np.min,
    "max_abs": lambda x: np.max(np.abs(x)),
    "rms": lambda x: np.sqrt(np.mean(np.square(x))),
    "mean": np.mean,
}
OPS = {"<": lambda a, b: a < b, "<=": lambda a, b: a <= b, ">": lambda a, b: a > b,
       ">=": lambda a, b: a >= b, "==": lambda a, b: a == b}

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_KEY = re.compile(rf"^\s*(?P<fn>[a-z_]+)\s*\(\s*(?P<signal>[A-Za-z_][A-Za-z0-9_]*)"
                  rf"(?:\[\s*(?P<component>[^\]]+?)\s*\])?"
                  rf"(?:\s*,\s*(?P<t0>{_NUMBER}))?(?:\s*,\s*(?P<t1>{_NUMBER}))?\s*\)\s*$")
_CONDITION = re.compile(rf"^\s*(?P<op><=|>=|==|<|>)\s*(?P<value>{_NUMBER}|inf|-inf)\s*$")


@dataclass(frozen=True)
class Criterion:
    key: str               # as written in the file, the criteria table's row name
    function: str
    signal: str
    component: str | None  # a component name or index, as written
    t0: float              # [s]
    t1: float | None       # [s]; None: the end of the run
    op: str
    threshold: float

    @property
    def condition(self) -> str:
        return f"{self.op} {self.threshold:g}"


def parse(key: str, condition, signals: dict) -> Criterion:
    """One criterion; raises ValueError naming what is wrong (the caller adds file and key)."""
    m = _KEY.match(key)
    if not m:
        raise ValueError("expected \"function(signal[, t0[, t1]])\", e.g. \"max(ee_error, 1.0)\"")
    fn = m["fn"]
    if fn not in (*FUNCTIONS, "final"):
        raise ValueError(f"unknown function {fn!r}; known: {', '.join([*FUNCTIONS, 'final'])}")
    if m["signal"] not in signals:
        raise ValueError(f"unknown signal {m['signal']!r}; this family's: {', '.join(signals)}")
    if isinstance(condition, bool) or not isinstance(condition, (str, int, float)):
        raise ValueError(f"expected a condition string such as \"< 0.002\", got {condition!r}")
    c = _CONDITION.match(str(condition)) if isinstance(condition, str) else None
    if c is None:
        raise ValueError(f"expected \"op threshold\" with op one of < <= > >= ==, got "
                         f"{condition!r}")
    t0 = float(m["t0"]) if m["t0"] is not None else 0.0
    t1 = float(m["t1"]) if m["t1"] is not None else None
    if t0 < 0 or (t1 is not None and t1 < t0):
        raise ValueError(f"time window [{t0:g}, {t1:g}] s is empty or negative")
    threshold = float(c["value"])
    return Criterion(key, fn, m["signal"], m["component"], t0, t1, c["op"], threshold)


def window(criterion: Criterion, t: np.ndarray) -> np.ndarray:
    """Boolean mask of the ticks in the criterion's window."""
    end = np.inf if criterion.t1 is None else criterion.t1 + 1e-9
    return (t >= criterion.t0 - 1e-9) & (t <= end)


def select(criterion: Criterion, series: np.ndarray, components: list[str] | None) -> np.ndarray:
    """The series, or its named component (by name or index); raises ValueError otherwise."""
    if criterion.component is None:
        return series
    if series.ndim == 1:
        raise ValueError(f"{criterion.signal} is a scalar signal: it has no components")
    name = criterion.component
    names = components or [str(i) for i in range(series.shape[1])]
    if name in names:
        return series[:, names.index(name)]
    if name.lstrip("-").isdigit() and -series.shape[1] <= int(name) < series.shape[1]:
        return series[:, int(name)]
    raise ValueError(f"{criterion.signal} has no component {name!r}; its components: "
                     f"{', '.join(names)}")


def reduce(criterion: Criterion, t: np.ndarray, series: np.ndarray, components=None) -> float:
    """The criterion's value over its window; raises ValueError when the window holds no
    sample (the run is shorter than the window: the message says how long it lasted)."""
    x = select(criterion, series, components)
    mask = window(criterion, t)
    if not mask.any():
        end = f"{t[-1]:g} s" if len(t) else "no tick"
        raise ValueError(f"its window starts at {criterion.t0:g} s but the run ended at {end}: "
                         f"give a duration of at least {criterion.t0:g} s")
    x = x[mask]
    if criterion.function == "final":
        return float(np.max(x[-1])) if np.ndim(x[-1]) else float(x[-1])
    return float(FUNCTIONS[criterion.function](x))


def evaluate(criteria: list[Criterion], t, signals: dict, components: dict) -> dict[str, dict]:
    """The criteria table: row -> {value, op, threshold, passed} (the format every scenario's
    result carries); a NaN value fails, a window the run never reached fails with its reason."""
    out = {}
    for c in criteria:
        row = {"op": c.op, "threshold": c.threshold, "signal": c.signal}
        try:
            value = reduce(c, t, signals[c.signal], components.get(c.signal))
            row.update(value=value, passed=bool(not math.isnan(value)
                                                and OPS[c.op](value, c.threshold)))
        except ValueError as e:
            row.update(value=float("nan"), passed=False, reason=str(e))
        out[c.key] = row
    return out


def min_duration(criteria: list[Criterion]) -> float:
    """[s] the shortest run every criterion's window reaches into."""
    return max([c.t0 for c in criteria] + [c.t1 for c in criteria if c.t1 is not None], default=0.0)
