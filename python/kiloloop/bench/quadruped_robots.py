"""Other real quadrupeds from minimal robot files (`make quadruped-robots`): every 12-DoF
quadruped in example-robot-data's wheel, each from the issue's minimal file (name, kind, urdf,
package_dirs, [legs] base and feet; nothing tuned), through stand, trot, push, slope and
tilt-stop at the default 10 ms actuation delay with the scenarios' default (realistic) sensors.
Writes bench/quadruped_robots.{md,json}. The base link and the feet are the only per-robot data:
the names each URDF gives them."""
from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

from . import zoo_robots

# Every quadruped of the zoo's table (bench/zoo_robots.py: URDF, base link, feet FL FR RL RR).
ROBOTS = zoo_robots.names("quadruped")
SCENARIOS = ("quadruped-stand", "quadruped-trot", "quadruped-push", "quadruped-slope",
             "quadruped-tilt-stop")


def robot_file(name: str, directory: Path) -> Path | None:
    """The zoo's minimal robot file of quadruped `name` in directory, or None without
    example-robot-data."""
    return zoo_robots.robot_file(name, directory)


def main(argv=None) -> int:
    import kiloloop as kl

    from .. import scenarios

    argv = list(argv or [])
    out_dir = Path(argv[0]) if argv else Path("bench")
    records, lines = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for name in ROBOTS:
            path = robot_file(name, Path(tmp))
            if path is None:
                print("example-robot-data not installed")
                return 1
            robot = kl.Robot.load(path)
            mass = robot.model().total_mass  # [kg]
            cells = []
            for scenario in SCENARIOS:
                t0 = time.perf_counter()
                try:
                    r = scenarios.run_named(scenario, robot, {}, seed=0)
                    failed = {k: c["value"] for k, c in r.criteria.items() if not c["passed"]}
                    cell = "pass" if r.passed else ("FALL" if r.metrics.get("fell") else "fail") + \
                        " (" + ", ".join(f"{k} {v:.4g}" for k, v in failed.items()) + ")"
                    records.append({"robot": name, "scenario": scenario, "passed": r.passed,
                                    "metrics": r.metrics, "wall_s": time.perf_counter() - t0})
                except Exception as e:  # a refusal is a result too
                    cell = f"error: {e}"
                    records.append({"robot": name, "scenario": scenario, "passed": False,
                                    "error": str(e)})
                cells.append(cell)
                print(name, scenario, cell, flush=True)
            label = f"{name} ({mass:.1f} kg)"
            lines.append(f"| {label} | " + " | ".join(cells) + " |")
    header = "| robot | " + " | ".join(s.replace("quadruped-", "") for s in SCENARIOS) + " |"
    text = "\n".join([header, "|---" * (len(SCENARIOS) + 1) + "|", *lines]) + "\n"
    print(text)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "quadruped_robots.md").write_text(text)
    (out_dir / "quadruped_robots.json").write_text(json.dumps(records, indent=1, default=float))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
