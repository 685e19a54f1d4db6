"""Robot x scenario matrix on real robots of example-robot-data, each from a minimal robot file
(only name, kind, urdf, package_dirs and the family's naming table): `make robot-matrix`.

Prints one line per run (PASS, or the failed criteria with their values) and a summary table;
bench/robot_matrix.txt keeps the latest output. Nothing is tuned per robot: what fails here is
what a new user would see.
"""
from __future__ import annotations

import argparse
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

ARMS = {  # name: (URDF under robots/, chain root, chain tip)
    "ur3": ("ur_description/urdf/ur3_robot.urdf", "base_link", "tool0"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "base_link", "tool0"),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "base_link", "tool0"),
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", "link_base", "link7"),
    "z1": ("z1_description/urdf/z1.urdf", "link00", "link06"),
    "so100": ("so_arm_description/urdf/so100.urdf", "base", "gripper"),
}
ARM_SCENARIOS = ("arm-track", "arm-line", "arm-rrt", "arm-press", "arm-estop")


def share() -> Path:
    return Path(sysconfig.get_paths()["purelib"]) / "cmeel.prefix" / "share"


def arm_file(directory: Path, name: str) -> Path:
    urdf, root, tip = ARMS[name]
    path = directory / f"{name}.toml"
    path.write_text(f'name = "{name}"\nkind = "arm"\n'
                    f'urdf = "{share() / "example-robot-data" / "robots" / urdf}"\n'
                    f'package_dirs = ["{share()}"]\n[chain]\nroot = "{root}"\ntip = "{tip}"\n')
    return path


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
