"""The `kiloloop` command: list scenarios, run one, run the benchmarks.

Exit codes, every subcommand: 0 passed (or done), 1 a scenario's criteria failed (b2b, pil:
outputs differ), 2 a usage or input error (one line on stderr naming the option, key or file: an
InputError from anywhere below, or an argparse error), 3 kiloloop itself failed (a bug: the
traceback is printed).
"""
from __future__ import annotations

import argparse
import contextlib
import json
import sys
import traceback
import warnings
from pathlib import Path

from .errors import InputError, UnreadKeyWarning, UrdfRepairWarning


def _format_value(v) -> str:
    if isinstance(v, float) and v != v:   # NaN: a metric not computed, with why when known
        return f"not computed: {v.reason}" if getattr(v, "reason", "") else "not computed (NaN)"
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def _print_summary(result, settings) -> None:
    print(f"scenario {result.scenario}: {'PASSED' if result.passed else 'FAILED'}")
    for key in ("controller",):
        if key in settings:
            print(f"  {key}: {settings[key]}")
    print("  metrics:")
    for name, value in result.metrics.items():
        print(f"    {name:<24} {_format_value(value)}")
    print("  criteria:")
    for name, c in result.criteria.items():
        mark = "ok  " if c["passed"] else "FAIL"
        if c.get("reason"):   # a metric the scenario could not compute: why, never a number
            print(f"    {mark} {name}: {c['reason']} (needs {c['op']} {c['threshold']})")
        else:
            print(f"    {mark} {name} = {_format_value(c['value'])} {c['op']} {c['threshold']}")


def cmd_list(_args) -> int:
    from . import scenarios

    for name in scenarios.names():
        print(f"{name:<20} {scenarios.get(name).DESCRIPTION}")
    print("\nscenario files to copy and edit (docs/scenarios.md):")
    for path in scenarios.example_files():
        print(f"  {path}")
    return 0


LOG_SUFFIXES = (".npz", ".mcap")


def _check_log_path(path) -> None:
    """--log FILE: a .npz or an .mcap (SignalLog.save picks the format by it), checked before
    the run rather than after it."""
    if path and Path(path).suffix.lower() not in LOG_SUFFIXES:
        raise InputError(f"--log {path}: expected a .npz or .mcap file")


def cmd_run(args) -> int:
    from . import scenarios

    _check_log_path(args.log)
    module = scenarios.get(args.scenario)   # a built-in scenario, or a scenario file as one
    robot, settings = scenarios.prepare(module, args.robot, args.set)
    duration = scenarios.check_duration(args.duration, module, settings, robot)
    if args.video:
        settings["video"] = args.video
    result = scenarios.run(module, settings, robot, seed=args.seed, duration=duration)
    if args.baseline:
        from .scenarios.scenario_file import baseline

        result.criteria["baseline"] = baseline.compare(
            result.log, args.baseline, {}, getattr(result, "components", None))
    if args.save_baseline:
        from .scenarios.scenario_file import baseline

        baseline.save(result.log, args.save_baseline, result.log.names())
    _report(args, module, result, settings)
    return 0 if result.passed else 1


def _report(args, module, result, settings) -> None:
    """What `kiloloop run` writes after a run: --log, --plot, then --json or the summary."""
    if args.log:
        from .scenarios.run_info import refresh

        refresh(result)   # the criteria as printed (--baseline's row included)
        result.log.save(args.log)
    if args.plot:
        from .scenarios.plots import plot_result

        title = f"{result.scenario} ({settings.get('controller', '')})".replace(" ()", "")
        plot_result(result, module.plot_signals(), args.plot, title=title)
    if args.json:
        print(json.dumps(result.to_json()))
    else:
        if hasattr(module, "scenario"):   # a scenario file: its criteria table says it all
            from .scenarios.scenario_file.report import summary

            print(summary(result))
        else:
            _print_summary(result, settings)
        for label, path in (("log", args.log), ("plot", args.plot), ("video", args.video),
                            ("baseline", args.save_baseline)):
            if path:
                print(f"  {label}: {path}")


def cmd_sweep(args) -> int:
    from . import sweep

    grid = sweep.parse_grid(args.grid)
    if not grid:
        raise InputError("give at least one --grid KEY=V1,V2,...")
    _check_log_path(args.log)
    results = sweep.run_sweep(args.scenario, grid, workers=args.workers, seed=args.seed,
                              duration=args.duration, robot=args.robot, sets=args.set,
                              backend=args.backend, log=args.log)
    metric = args.metric or sweep.default_metric(results)
    out = args.out or f"sweep-{args.scenario}"
    csv_path = sweep.write_csv(results, f"{out}.csv")
    png_path = sweep.write_heatmap(results, grid, metric, f"{out}.png",
                                   title=f"{args.scenario}: {metric}") if metric else None
    keys = list(grid)
    print(f"sweep {args.scenario}: {sum(r['passed'] for r in results)}/{len(results)} passed")
    for r in results:
        params = " ".join(f"{k}={r['params'][k]}" for k in keys)
        value = r["metrics"].get(metric, float("nan"))
        mark = "ok  " if r["passed"] else "FAIL"
        why = f"  diverged: {r['reason']}" if r["reason"] else ""
        print(f"  {mark} {params:<40} {metric}={_format_value(value)}{why}")
    print(f"  csv: {csv_path}")
    if args.log:
        print(f"  logs: {sweep.log_path(args.log, 0, len(results))} .. (one per run, the csv's "
              f"log column)")
    if png_path:
        print(f"  heat map: {png_path}")
    return 0


def cmd_log_show(args) -> int:
    from .sil.log_show import show

    print(show(args.file))
    return 0


def cmd_bench(args) -> int:
    from .bench import run_benchmarks

    return run_benchmarks(quick=args.quick, as_json=args.json, robot=args.robot)


def cmd_signals(args) -> int:
    from .robot import Robot
    from .scenarios.scenario_file.signals import components_of, table

    try:
        robot = Robot.load(args.robot)
    except (ValueError, FileNotFoundError) as e:
        print(f"kiloloop signals: {e}", file=sys.stderr)
        return 2
    print(f"signals of {robot.name} ({robot.kind}); every one against t [s]:")
    print(table(robot.kind, components_of(robot)))
    return 0


def cmd_robot_check(args) -> int:
    from .robot_check import check

    return check(args.file)


def _robot_sets(items) -> dict:
    """--set KEY=VALUE items as a dict (scenarios.prepare splits robot-file and scenario keys)."""
    from .scenarios import split_overrides

    robot_sets, scenario_sets = split_overrides(items)
    return {**robot_sets, **scenario_sets}


def cmd_export(args) -> int:
    from .firmware.export import write_export
    from .firmware.families import family_of
    from .firmware.recording import record_sil_run
    from .robot import Robot

    robot = Robot.load(args.robot)
    family = family_of(robot)
    # The controller exactly as the family's scenario configures it (a few ticks suffice).
    rec = record_sil_run(robot, family, duration=0.01, sets=_robot_sets(args.set))
    header = write_export(robot, family, rec.controller.model, rec.controller.config, args.out,
                          {"scenario": family.scenario})
    print(f"exported {robot.name} ({family.name}, {family.controller}): {header}, "
          f"{header.parent / 'manifest.json'}")
    return 0


def cmd_b2b(args) -> int:
    from .firmware.b2b import run_b2b
    from .firmware.build import BuildError
    from .scenarios import check_duration

    # Bits are compared, not metrics: any duration > 0 will do (no scenario minimum).
    duration = check_duration(args.duration)
    try:
        result = run_b2b(args.robot, duration=duration, seed=args.seed,
                         sets=_robot_sets(args.set), work=args.work, scenario=args.scenario)
    except BuildError as e:  # no compiler, a failed build: the environment, not the input
        print(f"kiloloop b2b: {e.args[0]}", file=sys.stderr)
        return 2
    return 0 if result.identical and result.model_identical else 1


def cmd_margins(args) -> int:
    from .margins.command import run

    return run(args)


def cmd_pil(args) -> int:
    from .firmware.build import BuildError
    from .firmware.pil import run_pil
    from .scenarios import check_duration

    duration = check_duration(args.duration)
    echo = (lambda *_: None) if args.json else print
    try:
        result = run_pil(args.robot, target=args.target, duration=duration, seed=args.seed,
                         sets=_robot_sets(args.set), work=args.work, scenario=args.scenario,
                         echo=echo)
    except BuildError as e:  # no cross compiler or QEMU, a failed build: the environment
        print(f"kiloloop pil: {e.args[0]}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(result.as_dict(), indent=2))
    return 0 if result.identical else 1


class _Parser(argparse.ArgumentParser):
    """argparse with its usage errors as InputError: one line, exit 2, like every input error
    (argparse's own prints the usage too)."""

    def error(self, message):
        raise InputError(f"{self.prog}: {message} (see {self.prog} --help)")


def _seed(text: str) -> int:
    """--seed: a whole number 0 .. 2^32 - 1 (numpy's generators refuse negative seeds)."""
    try:
        seed = int(text)
    except ValueError:
        seed = -1
    if not 0 <= seed < 2 ** 32:
        raise argparse.ArgumentTypeError(f"expected a whole number from 0 to {2 ** 32 - 1}, "
                                         f"got {text!r}")
    return seed


def _first_line(e: BaseException) -> str:
    text = str(e).strip()
    return text.splitlines()[0] if text else type(e).__name__


@contextlib.contextmanager
def _warnings_as_lines(prog: str):
    """kiloloop's own warnings (UnreadKeyWarning, UrdfRepairWarning) as one line
    `PROG: warning: ...` on stderr; any other warning as Python shows it."""
    with warnings.catch_warnings():
        warnings.simplefilter("always", UnreadKeyWarning)  # each run says it, not once a process
        show = warnings.showwarning

        def one_line(message, category, filename, lineno, file=None, line=None):
            if issubclass(category, (UnreadKeyWarning, UrdfRepairWarning)):
                print(f"{prog}: warning: {message}", file=sys.stderr)
            else:
                show(message, category, filename, lineno, file, line)

        warnings.showwarning = one_line
        yield


def main(argv=None) -> int:
    """Runs one subcommand; returns its exit code (module doc). Input errors raised anywhere
    below become one line and 2 here, for every subcommand; anything else is a bug: 3, with
    its traceback."""
    try:
        args = _build_parser().parse_args(argv)
    except InputError as e:  # the message names the (sub)command
        print(_first_line(e), file=sys.stderr)
        return 2
    prog = f"kiloloop {args.command}"
    try:
        with _warnings_as_lines(prog):
            return args.func(args)
    except InputError as e:
        print(f"{prog}: {_first_line(e)}", file=sys.stderr)
        return 2
    except Exception:  # noqa: BLE001 - not the user's doing: keep the traceback, not exit 1
        traceback.print_exc()
        print(f"{prog}: internal error (a bug in kiloloop; the traceback above says where)",
              file=sys.stderr)
        return 3


class _PrintCmakePrefix(argparse.Action):
    """--cmake-prefix: prints the kit's path and exits, like --version (no subcommand needed)."""

    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        from .firmware.build import kit_prefix
        kit = kit_prefix()
        if kit is None:
            parser.exit(2, "kiloloop: this installation has no firmware kit (a source tree's "
                           "package without a wheel install): `make build` installs one\n")
        print(kit)  # stdout: $(kiloloop --cmake-prefix)
        parser.exit(0)


def _build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="kiloloop", description=__doc__,
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cmake-prefix", action=_PrintCmakePrefix,
                        help="print the installed firmware kit's path, for find_package(kiloloop): "
                             "cmake -DCMAKE_PREFIX_PATH=$(kiloloop --cmake-prefix) (docs/firmware.md)")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list the SIL scenarios").set_defaults(func=cmd_list)
    run = sub.add_parser("run", help="run one SIL scenario")
    run.add_argument("scenario", metavar="SCENARIO|FILE.toml",
                     help="a built-in scenario (kiloloop list) or a scenario file (docs/scenarios.md)")
    run.add_argument("--duration", type=float, default=None, help="simulated time [s]")
    run.add_argument("--seed", type=_seed, default=None,
                     help="seed for noise and randomness (default: the file's, else 0)")
    run.add_argument("--robot", default=None, metavar="NAME|FILE",
                     help="robot name in models/ or a robot file (default: the scenario's own)")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="override a scenario setting, or a robot-file key by its dotted path "
                          "(controller.kp=400) (repeatable)")
    run.add_argument("--json", action="store_true", help="print one JSON object")
    run.add_argument("--plot", metavar="PNG", help="write a plot")
    run.add_argument("--log", metavar="FILE", help="write the signal log: FILE.npz (numpy) or "
                     "FILE.mcap (MCAP: Foxglove, PlotJuggler, ROS 2 tools)")
    run.add_argument("--video", metavar="MP4", help="render the run (MuJoCo offscreen, 30 fps)")
    run.add_argument("--save-baseline", metavar="NPZ",
                     help="write the run's signals as a baseline for later runs")
    run.add_argument("--baseline", metavar="NPZ",
                     help="compare the run with a baseline, every signal bit for bit (a "
                          "scenario file's [baseline] table sets tolerances)")
    run.set_defaults(func=cmd_run)
    sweep = sub.add_parser("sweep", help="run a scenario over a grid of settings, in parallel")
    sweep.add_argument("scenario")
    sweep.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...",
                       help="values of one setting (repeatable: every combination runs)")
    sweep.add_argument("--workers", type=int, default=None,
                       help="parallel threads or processes (default: the number of cores)")
    sweep.add_argument("--metric", default=None, help="metric of the heat map (default: the first)")
    sweep.add_argument("--out", default=None, metavar="PREFIX",
                       help="writes PREFIX.csv and PREFIX.png (default: sweep-SCENARIO)")
    sweep.add_argument("--duration", type=float, default=None, help="simulated time per run [s]")
    sweep.add_argument("--seed", type=_seed, default=0)
    sweep.add_argument("--robot", default=None, metavar="NAME|FILE")
    sweep.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       help="fixed overrides for every run (as in `kiloloop run`)")
    sweep.add_argument("--backend", choices=("local", "ray"), default="local",
                       help="local: threads for native scenarios, processes otherwise; "
                            "ray: a Ray cluster (RAY_ADDRESS) or a local Ray instance")
    sweep.add_argument("--log", default=None, metavar="FILE",
                       help="write each run's signal log, FILE-<i>.npz or .mcap as FILE's suffix "
                            "says (i: the csv's row)")
    sweep.set_defaults(func=cmd_sweep)
    bench = sub.add_parser("bench", help="timing and allocation benchmarks")
    bench.add_argument("--quick", action="store_true", help="fewer calls, for a smoke test")
    bench.add_argument("--json", action="store_true", help="print one JSON object")
    bench.add_argument("--robot", default=None, metavar="NAME|FILE",
                       help="also time the SIL loop and steps of this robot")
    bench.set_defaults(func=cmd_bench)
    log = sub.add_parser("log", help="signal logs (.npz, .mcap): show one")
    log_sub = log.add_subparsers(dest="log_command", required=True)
    show = log_sub.add_parser("show", help="signals (unit, frame, samples), duration, criteria")
    show.add_argument("file", metavar="FILE", help="a log written by --log (.npz or .mcap)")
    show.set_defaults(func=cmd_log_show)
    signals = sub.add_parser("signals", help="the signals a scenario file's criteria, "
                                             "baselines and plots read, for one robot")
    signals.add_argument("robot", metavar="NAME|FILE")
    signals.set_defaults(func=cmd_signals)
    robot = sub.add_parser("robot", help="robot files: check one")
    robot_sub = robot.add_subparsers(dest="robot_command", required=True)
    check = robot_sub.add_parser("check", help="load everything, print what was derived")
    check.add_argument("file", metavar="NAME|FILE")
    check.set_defaults(func=cmd_robot_check)
    export = sub.add_parser("export", help="a robot and its controller settings as one C++ header")
    export.add_argument("robot", metavar="NAME|FILE")
    export.add_argument("--out", required=True, metavar="DIR",
                        help="writes DIR/robot_export.hpp and DIR/manifest.json")
    export.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="robot-file or scenario override, as in `kiloloop run`")
    export.set_defaults(func=cmd_export)
    b2b = sub.add_parser("b2b", help="back-to-back: SIL log replayed through the exported "
                                     "firmware, outputs compared bit for bit")
    b2b.add_argument("robot", metavar="NAME|FILE")
    b2b.add_argument("--duration", type=float, default=None,
                     help="simulated time [s] (default: the scenario file's, else 1)")
    b2b.add_argument("--seed", type=_seed, default=None,
                     help="default: the scenario file's, else 0")
    b2b.add_argument("--scenario", default=None, metavar="FILE.toml",
                     help="record the SIL run of this scenario file (default: the family's "
                          "built-in b2b scenario)")
    b2b.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    b2b.add_argument("--work", default=None, metavar="DIR",
                     help="build directory (default: ~/.cache/kiloloop/firmware, or "
                          "$XDG_CACHE_HOME/kiloloop/firmware)")
    b2b.set_defaults(func=cmd_b2b)
    from .firmware.pil import TARGETS
    pil = sub.add_parser("pil", help="processor-in-the-loop: the SIL log replayed by the firmware "
                                     "cross-built for a target, under QEMU; bits, footprint, "
                                     "instructions per step")
    pil.add_argument("robot", metavar="NAME|FILE")
    pil.add_argument("--target", required=True, choices=sorted(TARGETS))
    pil.add_argument("--duration", type=float, default=None,
                     help="simulated time [s] (default: the scenario file's, else 1)")
    pil.add_argument("--seed", type=_seed, default=None,
                     help="default: the scenario file's, else 0")
    pil.add_argument("--scenario", default=None, metavar="FILE.toml",
                     help="record the SIL run of this scenario file (default: the family's "
                          "built-in b2b scenario)")
    pil.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    pil.add_argument("--work", default=None, metavar="DIR",
                     help="build directory (default: ~/.cache/kiloloop/firmware, or "
                          "$XDG_CACHE_HOME/kiloloop/firmware)")
    pil.add_argument("--json", action="store_true",
                     help="print the result as JSON (and nothing else)")
    pil.set_defaults(func=cmd_pil)
    margins = sub.add_parser("margins", help="gain, phase and delay margins of one loop at a "
                                             "scenario's operating point (docs/margins.md)")
    margins.add_argument("scenario", metavar="SCENARIO|FILE.toml")
    margins.add_argument("--loop", required=True, metavar="LOOP",
                         help="joint:<i> (arm); roll, pitch, height (quadruped); roll, pitch, "
                              "yaw, z (multirotor)")
    margins.add_argument("--robot", default=None, metavar="NAME|FILE")
    margins.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    margins.add_argument("--seed", type=_seed, default=0, help="the multi-sine's phases")
    margins.add_argument("--no-injection", action="store_true", help="linearization only")
    margins.add_argument("--no-linearization", action="store_true", help="injection only")
    margins.add_argument("--json", action="store_true", help="print one JSON object")
    margins.add_argument("--plot", metavar="PNG", help="write the Bode plot")
    margins.set_defaults(func=cmd_margins)
    from .ident.cli import add_parsers as add_identification  # excite, identify
    add_identification(sub)
    return parser


if __name__ == "__main__":
    sys.exit(main())
