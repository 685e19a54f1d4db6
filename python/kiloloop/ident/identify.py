"""`kiloloop identify ROBOT LOG... --out PATCH.toml`: the family's identification of the logs
against the robot file (the nominal model), written as a robot-file patch (patch.py)."""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..sil.log import SignalLog


def identify(robot, log_paths, out_path=None, smoothing: float | None = None
             ) -> tuple[object, list[str], dict]:
    """(the identification, summary lines, JSON-ready dict); writes the patch when out_path.
    smoothing [s]: an arm's zero-phase filter half-width (None: arm.identify_arm's choice)."""
    logs = []
    for p in log_paths:
        if not Path(p).is_file():
            raise InputError(f"identify: log {p}: file not found")
        logs.append(SignalLog.load(p))
    if robot.kind == "arm":
        from . import arm as family

        ident = (family.identify_arm(robot, logs) if smoothing is None
                 else family.identify_arm(robot, logs, smoothing=smoothing))
    elif robot.kind == "aerial":
        from . import multirotor as family

        ident = family.identify_multirotor(robot, logs)
    else:
        raise InputError(f"identify: no identification for a {robot.kind} yet (arms, "
                         "multirotors)")
    lines = family.summary(ident)
    report = {"robot": robot.name, "kind": robot.kind, "logs": [str(p) for p in log_paths],
              **ident.as_dict()}
    if out_path is not None:
        from .patch import write

        data = family.patch_data(robot, ident, out_path)
        header = [f"Robot file identified by `kiloloop identify` from {len(logs)} log(s)",
                  f"({', '.join(Path(p).name for p in log_paths)}) against {robot.path}:",
                  "that file's tables with the identified values in their places.", ""]
        write(data, out_path, header + lines)
        report["patch"] = str(out_path)
    return ident, lines, report
