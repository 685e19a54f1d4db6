"""What a scenario file's run shows: the criteria table (text), the plot of the signals its
criteria read (each with its reference where it has one), the log with the signals' units."""
from __future__ import annotations

import math

import numpy as np

from .signals import BY_FAMILY

# A signal's reference, drawn dashed beside it.
REFERENCE_OF = {"q": "q_ref", "ee": "ee_ref", "vx": "vx_ref", "vy": "vy_ref",
                "yaw_rate": "yaw_rate_ref", "position": "position_ref"}


def _value(v) -> str:
    return f"{v:.4g}" if isinstance(v, float) and not math.isnan(v) else str(v)


def criteria_table(result) -> str:
    """One line per criterion: mark, row, value, condition (and why, when it could not be
    computed or the baseline differs)."""
    lines = []
    width = max([len(k) for k in result.criteria] + [8])
    for key, row in result.criteria.items():
        mark = "ok  " if row["passed"] else "FAIL"
        cond = "baseline" if key == "baseline" else f"{row['op']} {row['threshold']:g}"
        value = "" if key == "baseline" else f" = {_value(row['value'])}"
        line = f"  {mark} {key:<{width}}{value}  ({cond})"
        if row.get("reason"):
            line += f": {row['reason']}"
        lines.append(line)
    return "\n".join(lines) if lines else "  (no criteria)"


def summary(result) -> str:
    s = result.settings
    head = (f"scenario {result.scenario}: {'PASSED' if result.passed else 'FAILED'}  "
            f"(robot {s.get('robot')}, {s.get('duration'):g} s, seed {s.get('seed')})")
    return head + "\n  criteria:\n" + criteria_table(result)


def plot_panels(result, family: str) -> list[tuple]:
    """(title, signal, reference or None, unit) per signal the criteria read (their order),
    or the family's main signals when there are no criteria."""
    names = []
    for row in result.criteria.values():
        name = row.get("signal")
        if name and name not in names:
            names.append(name)
    if not names:
        names = {"arm": ["q", "ee_error", "tau"], "quadruped": ["vx", "roll", "pitch", "height"],
                 "aerial": ["position", "position_error", "attitude_error"]}[family]
    table = BY_FAMILY[family]
    return [(n, n, REFERENCE_OF.get(n) if REFERENCE_OF.get(n) in
             result.log else None, table[n].unit) for n in names if n in result.log]


def thresholds(result) -> dict:
    """signal -> [(op, value, label, t0)] (kiloloop.plot's thresholds) of the file's criteria
    on a whole signal: max_abs and rms bounds drawn both ways on a signal that goes negative, as
    a guide (the label names the function), each from its window's start."""
    out = {}
    for c in result.scenario_file.criteria:
        if c.component is not None or not math.isfinite(c.threshold):
            continue
        t0 = c.t0 or None
        lines = out.setdefault(c.signal, [])
        lines.append((c.op, c.threshold, c.key, t0))
        signed = c.signal in result.log and np.nanmin(result.log[c.signal], initial=0.0) < 0
        if (c.function in ("max_abs", "rms") and c.op in ("<", "<=") and c.threshold > 0
                and signed):
            lines.append((">" if c.op == "<" else ">=", -c.threshold, c.key, t0))
    return out


def write_plot(result, path, family: str):
    from ..plots import plot_result

    return plot_result(result, plot_panels(result, family), path,
                       title=f"{result.scenario} ({result.settings.get('robot')})")


def write_log(result, path, family: str):
    """The run's log (.npz) with every signal of the family table and the raw channels."""
    return result.log.save(path)
