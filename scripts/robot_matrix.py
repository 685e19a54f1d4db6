"""Robot x scenario matrix on real robots of example-robot-data, each from a minimal robot file
(only name, kind, urdf, package_dirs and the family's naming table): `make robot-matrix`.

Prints one line per run (PASS, or the failed criteria with their values) and a summary table;
bench/robot_matrix.txt keeps the latest output. Nothing is tuned per robot: what fails here is
what a new user would see.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

from kiloloop.bench import zoo_robots

# The seven arms this matrix has always run (the zoo's table has them, and more: `make zoo`).
ARMS = ("ur3", "ur5", "ur10", "panda", "xarm7", "z1", "so100")
ARM_SCENARIOS = ("arm-track", "arm-line", "arm-rrt", "arm-press", "arm-estop")


def arm_file(directory: Path, name: str) -> Path:
    """The zoo's minimal robot file of arm `name` (bench/zoo_robots.py) in directory."""
    return zoo_robots.robot_file(name, directory)


def main(argv=None) -> int:
    from kiloloop import scenarios

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--robots", default=",".join(ARMS))
    parser.add_argument("--scenarios", default=",".join(ARM_SCENARIOS))
    args = parser.parse_args(argv)
    robots, names = args.robots.split(","), args.scenarios.split(",")
    table = {}
    with tempfile.TemporaryDirectory() as tmp:
        for robot in robots:
            path = arm_file(Path(tmp), robot)
            for name in names:
                start = time.perf_counter()
                try:
                    r = scenarios.run_named(name, path)
                    failed = {k: c["value"] for k, c in r.criteria.items() if not c["passed"]}
                    cell = "pass" if not failed else "FAIL"
                    detail = "" if not failed else " ".join(f"{k}={v:.4g}" for k, v in
                                                            failed.items())
                except Exception as e:  # noqa: BLE001 - a derivation that finds nothing
                    cell, detail = "ERROR", f"{type(e).__name__}: {e}"
                table[robot, name] = cell
                print(f"{robot:<8} {name:<11} {cell:<5} {time.perf_counter() - start:5.1f} s "
                      f"{detail}", flush=True)
    print()
    print(f"{'':<8} " + " ".join(f"{n:<10}" for n in names))
    for robot in robots:
        print(f"{robot:<8} " + " ".join(f"{table[robot, n]:<10}" for n in names))
    return 0


if __name__ == "__main__":
    sys.exit(main())
