"""`kiloloop margins SCENARIO|FILE --loop LOOP [--robot R] [--set k=v] [--json] [--plot PNG]`:
the scenario's robot and settings (as `kiloloop run` resolves them), its operating point, the
loop analysed by injection and linearization; the summary, or one JSON object."""
from __future__ import annotations

import json

from .analysis import NYQUIST, analyse
from .operating_point import operating_point


def _fmt(value, unit: str, scale: float = 1.0) -> str:
    return "inf" if value is None else f"{scale * value:.4g} {unit}"


def summary(scenario: str, robot, d: dict) -> str:
    lines = [f"margins of {robot.name} loop {d['loop']} at {scenario}'s operating point "
             f"(broken at the actuators, signal in {d['unit']}):"]
    for method in ("linearization", "injection"):
        if method in d:
            m = d[method]
            lines.append(f"  {method:<14} gain margin {_fmt(m['gain_margin_db'], 'dB')}, phase "
                         f"margin {_fmt(m['phase_margin_deg'], 'deg')}, delay margin "
                         f"{_fmt(m['delay_margin_s'], 'ms', 1e3)}, crossover "
                         f"{_fmt(m['crossover_rad_s'], 'rad/s')}")
    if d.get("max_gain_difference_db") is not None:
        lines.append(f"  agreement up to {d['agreement_up_to_rad_s']:.0f} rad/s (Nyquist/3): "
                     f"{d['max_gain_difference_db']:.3f} dB, "
                     f"{d['max_phase_difference_deg']:.3f} deg at most")
    return "\n".join(lines)


def run(args) -> int:
    from .. import scenarios

    module = scenarios.get(args.scenario)
    robot, settings = scenarios.prepare(module, args.robot, args.set)
    op = operating_point(robot, settings, args.seed)
    a = analyse(op, args.loop, seed=args.seed, inject=not args.no_injection,
                linearize=not args.no_linearization)
    d = dict(a.as_dict(), scenario=getattr(module, "NAME", args.scenario), robot=robot.name,
             nyquist_rad_s=NYQUIST)
    if args.plot:
        from .bode_plot import plot

        plot(a, args.plot, title=f"{robot.name} {args.loop}")
    print(json.dumps(d) if args.json else summary(d["scenario"], robot, d))
    if args.plot and not args.json:
        print(f"  plot: {args.plot}")
    return 0
