"""The one error a scenario file raises: which file, which key, what is wrong (one line)."""
from __future__ import annotations

from ...errors import InputError


class ScenarioFileError(InputError):
    """A scenario file that cannot run as written. str(): "FILE: KEY: what", fit for one line
    (an InputError: the CLI prints it and exits 2; the pytest plugin shows it as the test's
    failure)."""

    def __init__(self, where, key: str, what: str):
        self.where, self.key, self.what = str(where), key, what
        super().__init__(f"{self.where}: {key}: {what}" if key else f"{self.where}: {what}")
