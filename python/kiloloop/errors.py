"""The errors a user's input causes, as opposed to kiloloop's own bugs.

`kiloloop` maps every InputError, from any subcommand, to one line on stderr and exit code 2
(cli.py `main`); any other exception is a bug and keeps its traceback. Raise InputError where a
value the user gave (a --set, a robot file, a scenario setting, --duration) or what the robot
can do (no box fits, no tool-down pose) makes the request impossible; the message names the key,
and the file when there is one. InputError is a ValueError, so callers that catch ValueError
(tests, scripts) keep working.

Nothing here imports the rest of kiloloop: robot/, sil/ and scenarios/ all raise these.
"""
from __future__ import annotations

import contextlib


class InputError(ValueError):
    """A request that the user's input makes impossible; the message fits on one line."""


class UnknownName(InputError, KeyError):
    """An unknown scenario (or other registry) name. Also a KeyError, as it always was."""

    def __str__(self) -> str:  # KeyError quotes its message; one line reads better bare
        return str(self.args[0]) if self.args else ""


class ScenarioRefused(InputError):
    """A scenario that this robot cannot pass for a physical reason, found at start from the robot's
    data before anything runs: an effort limit below what the scenario needs, a workspace that
    cannot hold its targets. The message names the robot, the scenario, the reason and the
    figures (what is needed against what the robot has), e.g. "z1: arm-press needs 30 N at the
    tool, its wrist joints give 12 N". Raised instead of failing mid-run."""


class UnreadKeyWarning(UserWarning):
    """A --set robot-file key that the scenario being run does not read (it has no effect)."""


class UrdfRepairWarning(UserWarning):
    """A change to a robot's URDF that only its robot file asked for (`balance_inertia`): the
    link and by how much (robot/urdf_doc.py). Shown once a process for each change."""


@contextlib.contextmanager
def configuring(what: str):
    """Within: a ValueError from a compiled object's constructor (a controller's configure, a
    trajectory: the C++ validate refusing a gain, a limit or a time, all of which come from the
    robot file and the scenario settings) becomes an InputError `WHAT: reason` (the reason names
    the field). Only around such constructors: a ValueError anywhere else is not the user's
    doing."""
    try:
        yield
    except InputError:
        raise
    except ValueError as e:
        reason = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise InputError(f"{what}: {reason}") from e
