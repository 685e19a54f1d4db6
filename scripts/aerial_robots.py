"""Every aerial scenario on kiloloop's aerial manipulator and on the multirotors of
tests/aerial_test_robots.py (example-robot-data's iris, hector, borinot, hextilt; the hexa_arm,
octo_arm and hexa_tilt written there), seeds 0-4, nothing tuned per robot; writes
bench/aerial_robots.md (a cell: passed seeds, else the failing criteria's worst value, or the
refusal).

    PYTHONPATH=python:tests python scripts/aerial_robots.py [--seeds 0,1,2,3,4] [OUT.md]
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

SCENARIOS = ["aerial-hover", "aerial-attitude-step", "aerial-arm-sweep", "aerial-reach",
             "aerial-rotor-fault", "aerial-wind", "aerial-push"]
ROBOTS = ["aerial_manipulator", "iris", "hector", "borinot", "hextilt", "hexa_arm", "octo_arm",
          "hexa_tilt"]


def cell(results) -> str:
    """'5/5', or the failing criteria with their worst value over the failing seeds."""
    if isinstance(results, str):
        return results
    passed = sum(r.passed for r in results)
    if passed == len(results):
        return f"{passed}/{len(results)}"
    worst: dict[str, float] = {}
    for r in results:
        for k, c in r.criteria.items():
            if not c["passed"]:
                v = c["value"]
                worst[k] = v if k not in worst else (max(worst[k], v) if c["op"] == "<"
                                                     else min(worst[k], v))
    return f"{passed}/{len(results)}: " + ", ".join(f"{k} {v:.3g}" for k, v in worst.items())


def main(argv) -> None:
    from aerial_test_robots import write_all
    from kiloloop import scenarios
    from kiloloop.errors import InputError, ScenarioRefused
    from kiloloop.robot import Robot

    seeds = [0, 1, 2, 3, 4]
    if "--seeds" in argv:
        i = argv.index("--seeds")
        seeds = [int(s) for s in argv[i + 1].split(",")]
        del argv[i:i + 2]
    out = Path(argv[0] if argv else "bench/aerial_robots.md")
    files = write_all(tempfile.mkdtemp())
    rows = []
    for name in ROBOTS:
        robot = Robot.load(files.get(name, name))
        cells = []
        for scenario in SCENARIOS:
            try:
                results = [scenarios.run_named(scenario, robot, {}, seed=s) for s in seeds]
            except ScenarioRefused as e:
                results = "refused: " + str(e).removeprefix(f"{robot.name}: ")
            except InputError as e:  # a default setting that does not fit this robot
                results = f"not run: {e}"
            cells.append(cell(results))
            print(name, scenario, cells[-1], flush=True)
        rows.append(f"| {name} | " + " | ".join(cells) + " |")
    out.write_text(
        "# Aerial scenarios on multirotors from real descriptions\n\n"
        f"`PYTHONPATH=python:tests python scripts/aerial_robots.py` (seeds "
        f"{', '.join(map(str, seeds))}, default settings, robot files from "
        "tests/aerial_test_robots.py: nothing tuned per robot). A cell: seeds passed, else the "
        "failing criteria (worst value), or the refusal at start.\n\n"
        "| robot | " + " | ".join(SCENARIOS) + " |\n|" + "---|" * (len(SCENARIOS) + 1) + "\n"
        + "\n".join(rows) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
