"""`kiloloop log show FILE`: what a saved log holds, the same text for .npz and .mcap.

    FILE: MCAP log, 22 signals
      scenario  quadruped-trot (built-in), seed 0, PASSED
      robot     go1  sha256 1f0c...
      duration  2.1 s: 2100 ticks of 1 ms, t 0 .. 2.099 s
      signal    unit   frame   samples  shape  label
      ...
      criteria:
        ok   fell = 0  (< 0.5)

An MCAP file is read from its summary and metadata alone (channel metadata: log_mcap.py), so a
long log shows at once; a .npz is loaded whole.
"""
from __future__ import annotations

import math
import zipfile
from pathlib import Path

from ..errors import InputError


def _overview_npz(path) -> dict:
    from .log import SignalLog

    log = SignalLog.load(path)
    signals = []
    for name in log.names():
        series = log[name]
        signals.append({"signal": name, "unit": log.unit(name), "frame": log.frame(name),
                        "label": log.described().get(name, {}).get("label") or "",
                        "samples": len(series), "shape": list(series.shape[1:])})
    t = log["t"] if "t" in log else None
    first = float(t[0]) if t is not None and len(t) else None
    last = float(t[-1]) if t is not None and len(t) else None
    return {"format": "npz", "signals": signals, "info": log.info, "first_s": first,
            "last_s": last}


def _overview_mcap(path) -> dict:
    import json

    from .log_mcap import overview

    o = overview(path)
    signals = [{"signal": m["signal"], "unit": m["unit"], "frame": m["frame"],
                "label": m["label"], "samples": int(m["samples"]),
                "shape": json.loads(m["shape"])} for m in o["signals"]]
    ns = (o["start_ns"], o["end_ns"])
    return {"format": "MCAP", "signals": signals, "info": o["info"],
            "first_s": None if ns[0] is None else ns[0] * 1e-9,
            "last_s": None if ns[1] is None else ns[1] * 1e-9}


def overview(path) -> dict:
    """{"format", "signals": [{signal, unit, frame, label, samples, shape}], "info",
    "first_s", "last_s"} of a saved log; InputError for a file that is not one."""
    from .log import is_mcap

    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    mcap = is_mcap(path)
    if not mcap and not zipfile.is_zipfile(path):   # a .npz is a zip archive
        raise InputError(f"{path}: not a log (neither MCAP nor .npz)")
    try:
        return _overview_mcap(path) if mcap else _overview_npz(path)
    except (ValueError, OSError, zipfile.BadZipFile, KeyError) as e:
        raise InputError(f"{path}: not a kiloloop log: {e}") from None


def _num(v) -> str:
    return f"{v:.4g}" if isinstance(v, float) and not math.isnan(v) else str(v)


def _duration(o: dict) -> str:
    """Run length from the log's time: n ticks of (last - first) / (n - 1)."""
    n = next((s["samples"] for s in o["signals"] if s["signal"] == "t"),
             max((s["samples"] for s in o["signals"]), default=0))
    first, last = o["first_s"], o["last_s"]
    if first is None or n < 2:
        return f"{n} ticks"
    dt = (last - first) / (n - 1)   # [s]
    return (f"{n * dt:.6g} s: {n} ticks of {dt * 1e3:.6g} ms, t {first:.6g} .. {last:.6g} s")


def criteria_table(criteria: dict) -> list[str]:
    """One line per criterion: mark, name, value, condition (and why it could not be
    computed), as `kiloloop run` prints a scenario file's."""
    if not criteria:
        return ["    (no criteria)"]
    width = max(len(k) for k in criteria)
    lines = []
    for key, row in criteria.items():
        mark = "ok  " if row.get("passed") else "FAIL"
        if key == "baseline":
            line = f"    {mark} {key:<{width}}  (baseline)"
        else:
            line = (f"    {mark} {key:<{width}} = {_num(row.get('value'))}  "
                    f"({row.get('op')} {_num(row.get('threshold'))})")
        if row.get("reason"):
            line += f": {row['reason']}"
        lines.append(line)
    return lines


def _head(o: dict) -> list[str]:
    info = o["info"]
    lines = []
    scenario, run, robot = info.get("scenario"), info.get("run", {}), info.get("robot")
    if scenario:
        verdict = {True: ", PASSED", False: ", FAILED"}.get(run.get("passed"), "")
        where = scenario.get("path") or scenario.get("source", "")
        lines.append(f"  scenario  {scenario.get('name')} ({where}), seed {run.get('seed')}"
                     f"{verdict}")
    if robot:
        lines.append(f"  robot     {robot.get('name')}  sha256 {robot.get('digest')}  "
                     f"({robot.get('path')})")
    lines.append(f"  duration  {_duration(o)}")
    return lines


def show(path) -> str:
    """The text `kiloloop log show` prints."""
    o = overview(path)
    rows = [("signal", "unit", "frame", "samples", "shape", "label")]
    for s in o["signals"]:
        shape = "x".join(str(d) for d in s["shape"]) or "-"
        rows.append((s["signal"], s["unit"] or "-", s["frame"] or "-", str(s["samples"]),
                     shape, s["label"]))
    widths = [max(len(r[i]) for r in rows) for i in range(5)]
    table = ["  " + "  ".join(c.ljust(w) for c, w in zip(r, widths)) + "  " + r[5]
             for r in rows]
    out = [f"{path}: {o['format']} log, {len(o['signals'])} signals", *_head(o), *table]
    if "criteria" in o["info"]:
        out += ["  criteria:", *criteria_table(o["info"]["criteria"])]
    return "\n".join(line.rstrip() for line in out)
