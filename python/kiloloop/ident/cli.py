"""The `kiloloop excite` and `kiloloop identify` subcommands (kiloloop/cli.py adds them)."""
from __future__ import annotations

import json
import math
from pathlib import Path

from ..errors import InputError

LOG_SUFFIXES = (".npz", ".mcap")


def add_parsers(sub) -> None:
    ex = sub.add_parser("excite", help="an excitation run in the SIL, logged for `identify`")
    ex.add_argument("robot", metavar="ROBOT", help="a robot name or robot file (its [sim.*] is "
                    "the plant)")
    ex.add_argument("--out", required=True, metavar="LOG", help="the log (.npz or .mcap)")
    ex.add_argument("--duration", type=float, default=None,
                    help="simulated time [s] (default 30)")
    ex.add_argument("--seed", type=int, default=0, help="the excitation's random coefficients")
    ex.add_argument("--delay", type=float, default=None, help="the plant's actuation delay [s] "
                    "(default: what the robot file declares for its family's scenarios)")
    ex.add_argument("--motor-lag", type=float, default=0.0,
                    help="a first-order lag [s] of the produced torque (an arm)")
    ex.add_argument("--q-sigma", type=float, default=0.0, metavar="RAD",
                    help="an arm's encoder noise on q [rad] (white, seeded)")
    ex.add_argument("--qd-sigma", type=float, default=0.0, metavar="RAD_S",
                    help="an arm's encoder noise on qd [rad/s]")
    ex.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="robot-file keys, e.g. sim.joints.damping=2 (the plant)")
    ex.set_defaults(func=cmd_excite)
    idf = sub.add_parser("identify", help="plant parameters from logs, as a robot-file patch")
    idf.add_argument("robot", metavar="ROBOT", help="the nominal robot name or file")
    idf.add_argument("logs", nargs="+", metavar="LOG", help="logs of `excite` or a real robot")
    idf.add_argument("--out", default=None, metavar="PATCH.toml",
                     help="write the identified robot file here (use it with --robot)")
    idf.add_argument("--json", action="store_true", help="print the result as JSON only")
    idf.add_argument("--smoothing", type=float, default=None, metavar="S",
                     help="an arm's zero-phase filter half-width [s] (default: none where "
                     "the fit is exact, else the best of 2.5, 5, 10 ms; 0: none)")
    idf.set_defaults(func=cmd_identify)


def _robot(name, sets=()):
    from ..robot import Robot

    overrides = {}
    for item in sets:
        if "=" not in item:
            raise InputError(f"--set {item}: expected KEY=VALUE")
        k, v = item.split("=", 1)
        overrides[k.strip()] = v.strip()
    return Robot.load(name, overrides or None)


def cmd_excite(args) -> int:
    from .excite import DEFAULT_DURATION, excite

    if Path(args.out).suffix.lower() not in LOG_SUFFIXES:
        raise InputError(f"--out {args.out}: expected a .npz or .mcap file")
    duration = DEFAULT_DURATION if args.duration is None else float(args.duration)
    if not (math.isfinite(duration) and duration > 0):
        raise InputError(f"--duration {args.duration}: expected a finite number of seconds > 0")
    if args.seed < 0:
        raise InputError(f"--seed {args.seed}: expected >= 0")
    for option, value in (("--delay", args.delay), ("--motor-lag", args.motor_lag),
                          ("--q-sigma", args.q_sigma), ("--qd-sigma", args.qd_sigma)):
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise InputError(f"{option} {value}: expected a finite number >= 0")
    robot = _robot(args.robot, args.set)
    noise = {k: v for k, v in (("q_sigma", args.q_sigma), ("qd_sigma", args.qd_sigma)) if v}
    log = excite(robot, duration, args.seed, delay=args.delay, motor_lag=args.motor_lag,
                 noise=noise)
    log.save(args.out)
    print(f"excite {robot.name}: {duration:g} s, {len(log['t'])} ticks, signals "
          f"{', '.join(log.names())} -> {args.out}")
    return 0


def cmd_identify(args) -> int:
    from .identify import identify

    if args.out is not None and Path(args.out).suffix.lower() != ".toml":
        raise InputError(f"--out {args.out}: expected a .toml file")
    robot = _robot(args.robot)
    if args.smoothing is not None and not (math.isfinite(args.smoothing) and args.smoothing >= 0):
        raise InputError(f"--smoothing {args.smoothing}: expected >= 0")
    _, lines, report = identify(robot, args.logs, args.out, args.smoothing)
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        print(f"identify {robot.name} from {len(args.logs)} log(s):")
        for line in lines:
            print("  " + line)
        if args.out:
            print(f"  -> {args.out} (run scenarios on it with --robot {args.out})")
    return 0
