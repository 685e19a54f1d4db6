#!/usr/bin/env python3
"""`make pil`: the processor-in-the-loop set (issue 31). Every robot below replayed on every
target below under QEMU, a SIL log of --duration seconds each: our three robots and one robot
file of each family written from example-robot-data (ur3, go1, iris: the tests' own helpers
write them). Prints one markdown table (bits, footprint, instructions per step, implied step
time); --json prints the results instead. Exit 1 if any replay is not bit-identical.

    python scripts/pil_matrix.py [--targets aarch64,...] [--duration 2] [--json]
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from importlib.metadata import PackageNotFoundError, distribution
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))  # the example-robot-data robot files' writers


def robots(directory: Path) -> list[tuple[str, str]]:
    """(label, robot argument) for every robot of the set."""
    import aerial_test_robots
    import quadruped_robots
    import robot_files

    out = [("ur5", "ur5"), ("quadruped", "quadruped"), ("aerial_manipulator", "aerial_manipulator")]
    try:
        distribution("example-robot-data")
    except PackageNotFoundError:
        print("pil_matrix: example-robot-data is not installed: our three robots only",
              file=sys.stderr)
        return out
    ur3 = robot_files.minimal_arm(directory, robot_files.erd_urdf(
        "ur_description/urdf/ur3_robot.urdf"), "base_link", "tool0", "ur3")
    out.append(("ur3 (example-robot-data)", str(ur3)))
    out.append(("go1 (example-robot-data)", str(quadruped_robots.go1_robot_file(directory))))
    out.append(("iris (example-robot-data)", str(aerial_test_robots.write_all(directory)["iris"])))
    return out


def main() -> int:
    from kiloloop.firmware.pil import TARGETS, prebuild, run_pil

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", default=",".join(TARGETS),
                    help=f"comma-separated, of {', '.join(TARGETS)}")
    ap.add_argument("--duration", type=float, default=2.0, help="SIL log length [s]")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    results = []
    # The whole core of each target (every family): one build serves all robots.
    prebuild(dict.fromkeys(args.targets.split(",")), work=ROOT / "build" / "firmware")
    with tempfile.TemporaryDirectory() as tmp:
        for target in args.targets.split(","):
            for label, robot in robots(Path(tmp)):
                print(f"pil {label} on {target} ...", file=sys.stderr, flush=True)
                r = run_pil(robot, target=target, duration=args.duration,
                            work=ROOT / "build" / "firmware", echo=lambda *_: None)
                results.append((label, r))
    if args.json:
        print(json.dumps([dict(r.as_dict(), label=label) for label, r in results], indent=2))
    else:
        print("| robot | target | replay | text / data / bss [B] | heap at init [B] | "
              "step stack [B] | instructions per step, median / max | implied step, worst |")
        print("|---|---|---|---|---|---|---|---|")
        for label, r in results:
            print(f"| {label} | {r.target} | {r.replay_output} | {r.text_bytes} / {r.data_bytes} "
                  f"/ {r.bss_bytes} | {r.heap_init_bytes} | {r.stack_step_bytes} | "
                  f"{r.instructions_median} / {r.instructions_max} | {r.step_us_worst:.1f} us "
                  f"({r.processor}, {r.clock_hz / 1e6:g} MHz, CPI {r.cpi:g}) |")
    return 0 if all(r.identical for _, r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
