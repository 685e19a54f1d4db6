"""kiloloop's pytest plugin (the `pytest11` entry point `kiloloop`, installed with the package).

- Scenario files named `test_*.toml` are collected as tests, one test per file (a robot file
  named so, with `kind = ...`, is left alone). A failure shows the criteria table; the run's
  log (.npz), a plot of the signals its criteria read (.png) and, with `--kiloloop-video`, a
  video (.mp4) go to `--kiloloop-results DIR` (default `kiloloop-results/`), one folder per test.
- The fixture `kiloloop_run(scenario, robot=None, settings=None, seed=None, duration=None)` runs
  a scenario file (a path, or a dict in the file's format) or a built-in scenario by name, and
  returns its result (`.passed`, `.criteria`, `.metrics`, `.log`) for tests written in Python.

pytest's own options work as usual (`--junitxml`, `-k`, `-x`). Importing this module imports
nothing of kiloloop's: the runs import it when they start.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest


def pytest_addoption(parser):
    group = parser.getgroup("kiloloop", "kiloloop SIL scenario files")
    group.addoption("--kiloloop-results", default="kiloloop-results", metavar="DIR",
                    help="where failed scenario files leave their log, plot (and video)")
    group.addoption("--kiloloop-video", action="store_true",
                    help="also render a video of each failed scenario file (re-runs it)")
    group.addoption("--kiloloop-robot", default=None, metavar="NAME|FILE",
                    help="run every scenario file on this robot instead of its own")


def pytest_collect_file(parent, file_path: Path):
    if file_path.suffix == ".toml" and file_path.name.startswith("test_"):
        return ScenarioFileModule.from_parent(parent, path=file_path)
    return None


class ScenarioFileModule(pytest.File):
    def collect(self):
        from .scenarios.scenario_file import ScenarioFileError, looks_like_robot_file, schema

        try:
            data = schema.read(self.path)
        except ScenarioFileError:
            data = {}   # the item reports it
        if looks_like_robot_file(data):
            return
        yield ScenarioFileItem.from_parent(self, name=self.path.stem)


class ScenarioFailed(Exception):
    """A scenario file's criteria failed (the report shows its table)."""


class ScenarioFileItem(pytest.Item):
    def runtest(self):
        from .scenarios.scenario_file import load, run

        config = self.config
        scenario = load(self.path)
        result = run(scenario, robot=config.getoption("kiloloop_robot"))
        self.user_properties.append(("kiloloop_passed", result.passed))
        if not result.passed:
            outputs = save_outputs(result, scenario, self._results_dir(), config)
            raise ScenarioFailed(result, outputs)

    def _results_dir(self) -> Path:
        root = Path(self.config.getoption("kiloloop_results"))
        if not root.is_absolute():
            root = Path(self.config.invocation_params.dir) / root
        return root / re.sub(r"[^A-Za-z0-9_.-]", "_", self.path.stem)

    def repr_failure(self, excinfo):
        from .scenarios.scenario_file import ScenarioFileError
        from .scenarios.scenario_file.report import summary

        if isinstance(excinfo.value, ScenarioFailed):
            result, outputs = excinfo.value.args
            lines = [summary(result)] + [f"  {label}: {path}" for label, path in outputs]
            return "\n".join(lines)
        if isinstance(excinfo.value, ScenarioFileError):
            return f"scenario file error: {excinfo.value}"
        return super().repr_failure(excinfo)

    def reportinfo(self):
        return self.path, 0, f"scenario file: {self.path.name}"


def save_outputs(result, scenario, directory: Path, config) -> list[tuple[str, Path]]:
    """The failed run's log and plot (and video) in `directory`; [(label, path)]."""
    from .scenarios.scenario_file import run
    from .scenarios.scenario_file.report import write_log, write_plot

    directory.mkdir(parents=True, exist_ok=True)
    out = [("log", write_log(result, directory / "log.npz", scenario.family)),
           ("plot", write_plot(result, directory / "plot.png", scenario.family))]
    if config.getoption("kiloloop_video"):
        video = directory / "video.mp4"
        run(scenario, robot=config.getoption("kiloloop_robot"), video=str(video))
        out.append(("video", video))
    return out


@pytest.fixture
def kiloloop_run(tmp_path):
    """run(scenario, robot=None, settings=None, seed=None, duration=None) -> result.

    scenario: a scenario file's path, a dict in its format (a test's own mission), or a built-in
    scenario's name; settings: {key: value} as `--set` takes them (family settings and dotted
    robot-file keys)."""
    def run(scenario, robot=None, settings=None, seed=None, duration=None):
        from . import scenarios
        from .scenarios import scenario_file

        if isinstance(scenario, dict):
            parsed = scenario_file.from_dict(scenario, name=scenario.get("name", "test"))
            return scenario_file.run(parsed, robot=robot, overrides=settings, seed=seed,
                                     duration=duration)
        module = scenarios.get(str(scenario))
        loaded, values = scenarios.prepare(module, robot, settings)
        return scenarios.run(module, values, loaded, seed=seed, duration=duration)

    return run
