"""What run made a log: the sections of SignalLog.info, which .npz and .mcap logs carry.

    scenario   name, source ("built-in", "file" or "dict"), description; a file's path and
               text as it is on disk at the end of the run; a dict-built file's table ("dict")
    robot      name, path of its robot file, digest (SHA-256 of robot file + URDF, as a firmware
               export records it), overrides (the --set robot-file keys applied)
    run        seed, duration [s] asked for (null: the scenario's own), passed, kiloloop version
    settings   the scenario's settings, as the run used them
    criteria   name -> {value, op, threshold, passed[, signal, reason]}, the result's table
    metrics    name -> value

Every value is made plain JSON here (numpy numbers and arrays to numbers and lists, paths to
strings, anything else to its repr), so that what a log holds in memory is exactly what either
file reads back.
"""
from __future__ import annotations

import json
from pathlib import Path


def _default(value):
    """json.dumps' fallback for what JSON has no type for."""
    if hasattr(value, "tolist"):          # numpy scalars and arrays
        return value.tolist()
    if isinstance(value, (set, frozenset)):
        return sorted(value, key=repr)
    if isinstance(value, Path):
        return str(value)
    return repr(value)


def plain(value):
    """`value` as JSON reads it back (dict keys become strings, tuples lists)."""
    return json.loads(json.dumps(value, default=_default))


def _scenario(result, module) -> dict:
    out = {"name": result.scenario}
    spec = result.scenario_file
    if spec is None:
        out.update(source="built-in", description=getattr(module, "DESCRIPTION", ""))
    elif spec.path is not None:
        out.update(source="file", description=spec.description, path=str(spec.path))
        try:
            out["text"] = Path(spec.path).read_text()
        except OSError:   # moved or deleted during the run: the path still says which
            out["text"] = None
    else:
        out.update(source="dict", description=spec.description, dict=spec.source)
    return out


def _robot(robot) -> dict:
    if robot is None:
        return {}
    return {"name": robot.name, "path": str(robot.path), "digest": robot.digest(),
            "overrides": dict(robot.overrides)}


def attach(result, module, robot, seed, duration) -> None:
    """Fills result.log.info from a finished run (scenarios.run calls it)."""
    from .. import __version__

    if result.log is None:
        return
    result.log.info = plain({
        "scenario": _scenario(result, module),
        "robot": _robot(robot),
        "run": {"seed": seed, "duration": duration, "passed": result.passed,
                "kiloloop": __version__},
        "settings": result.settings,
        "criteria": result.criteria,
        "metrics": result.metrics,
    })


def refresh(result) -> None:
    """Re-reads the criteria, metrics and verdict into result.log.info, after a caller changed
    them (`kiloloop run --baseline` adds a row)."""
    info = result.log.info if result.log is not None else None
    if not info:
        return
    info["criteria"] = plain(result.criteria)
    info["metrics"] = plain(result.metrics)
    info.setdefault("run", {})["passed"] = bool(result.passed)
