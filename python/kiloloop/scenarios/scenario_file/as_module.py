"""A scenario file seen as a scenario module (NAME, KIND, ROBOT, DEFAULTS, run, plot_signals), so
that everything that takes a built-in scenario by name takes a file by its path: `kiloloop run`,
`kiloloop sweep`, the batch runner (`kiloloop.scenarios.batch.run_scenarios`), the b2b recording. The file's
family settings become DEFAULTS (so `--set` and `--grid` layer on them), its robot-file keys
ROBOT_OVERRIDES (applied before `--set`'s)."""
from __future__ import annotations

from .. import split_overrides
from . import runner
from .errors import ScenarioFileError
from .report import REFERENCE_OF
from .schema import load
from .signals import BY_FAMILY


class FileScenario:
    def __init__(self, path):
        self.scenario = load(path)
        s = self.scenario
        self.NAME = s.name
        self.KIND = s.family
        self.ROBOT = s.robot
        self.DESCRIPTION = s.description or f"scenario file {s.path}"
        self.DURATION = s.duration
        self.SEED = s.seed
        robot_sets, family_sets = split_overrides(s.settings)
        self.ROBOT_OVERRIDES = robot_sets
        try:
            from .. import parse_settings

            self.DEFAULTS = parse_settings(runner.defaults(s.family), family_sets)
        except ValueError as e:
            raise ScenarioFileError(s.where, "settings", str(e)) from None
        self.CRITERIA = {c.key: (c.op, c.threshold) for c in s.criteria}

    def prepare(self, robot=None, overrides=None):
        """(robot, settings) as scenarios.prepare gives them, with the file's layering: its
        robot-file keys, then the overrides'; its settings, then the overrides'."""
        return runner.prepare(self.scenario, robot, overrides)

    def run(self, settings: dict, seed: int | None = None, duration: float | None = None,
            robot=None):
        settings = dict(settings)
        video = settings.pop("video", None)
        family = {k: v for k, v in settings.items() if k in self.DEFAULTS}
        return runner.run(self.scenario, robot=robot, overrides=family, seed=seed,
                          duration=duration, video=video)

    def plot_signals(self) -> list[tuple]:
        table = BY_FAMILY[self.KIND]
        names = []
        for c in self.scenario.criteria:
            if c.signal not in names:
                names.append(c.signal)
        if not names:
            names = {"arm": ["q", "ee_error", "tau"],
                     "quadruped": ["vx", "roll", "pitch", "height"],
                     "aerial": ["position", "position_error", "attitude_error"]}[self.KIND]
        return [(n, n, REFERENCE_OF.get(n), table[n].unit) for n in names]
