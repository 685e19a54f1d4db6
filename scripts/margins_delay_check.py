"""Predictive check of `kiloloop margins` (issue 34): holding the controller's design delay, the
plant's command delay at which a scenario starts to fail, swept in the SIL, against the delay the
margins predict it fails at (the plant's delay plus the smallest delay margin of the family's
loops, each broken alone with the others closed).

    PYTHONPATH=python python scripts/margins_delay_check.py [--scenario quadruped-stand ...]
        [--step 0.001] [--seeds 0]

Prints per scenario: each loop's margins (linearization), the predicted failing delay, the first
swept plant delay whose run fails its criteria on any seed (and the first that falls or
diverges), and their ratio; exit 1 when the ratio leaves 1 +- 20 %.
"""
from __future__ import annotations

import argparse
import json
import sys

from kiloloop import scenarios
from kiloloop.margins import analyse, operating_point
from kiloloop.margins.loops import FAMILY_LOOPS

SCENARIOS = ("quadruped-stand", "aerial-hover")
TOLERANCE = 0.20
UNSTABLE = {"quadruped-stand": "fell", "aerial-hover": "diverged"}


def predicted(name: str) -> dict:
    module = scenarios.get(name)
    robot, settings = scenarios.prepare(module, None, [])
    op = operating_point(robot, settings)
    loops, impulse = {}, None
    for loop in FAMILY_LOOPS[robot.kind]:
        a = analyse(op, loop, inject=False, impulse=impulse)
        impulse = a.impulse
        loops[loop] = a.margins.as_dict()
    worst = min(loops, key=lambda k: loops[k]["delay_margin_s"] or float("inf"))
    return {"motor_delay_s": float(settings["motor_delay"]), "loops": loops, "worst": worst,
            "failing_delay_s": float(settings["motor_delay"]) + loops[worst]["delay_margin_s"]}


def swept(name: str, design: float, start: float, step: float, stop: float, seeds) -> dict:
    """The first plant delay (from `start` up by `step`) whose run fails, and the first unstable."""
    module = scenarios.get(name)
    first_fail = first_unstable = None
    delay = start
    while delay <= stop + 1e-12 and first_unstable is None:
        for seed in seeds:
            robot, settings = scenarios.prepare(
                module, None, [f"motor_delay={delay:.4f}", f"design_delay={design}"])
            result = scenarios.run(module, settings, robot, seed=seed)
            if not result.passed and first_fail is None:
                first_fail = round(delay, 6)
            if result.metrics[UNSTABLE[name]] > 0.5:
                first_unstable = round(delay, 6)
                break
        delay += step
    return {"first_failing_delay_s": first_fail, "first_unstable_delay_s": first_unstable}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scenario", action="append", choices=SCENARIOS)
    p.add_argument("--step", type=float, default=0.001, help="[s] sweep step")
    p.add_argument("--seeds", default="0", help="comma-separated")
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",")]
    ok, out = True, {}
    for name in args.scenario or SCENARIOS:
        pred = predicted(name)
        sweep = swept(name, pred["motor_delay_s"], pred["motor_delay_s"], args.step,
                      3.0 * pred["failing_delay_s"], seeds)
        fail = sweep["first_failing_delay_s"]
        ratio = None if fail is None else fail / pred["failing_delay_s"]
        ok &= ratio is not None and abs(ratio - 1.0) <= TOLERANCE
        out[name] = dict(pred, **sweep, ratio=ratio)
        if not args.json:
            print(f"{name}: plant delay {1e3 * pred['motor_delay_s']:.1f} ms, design delay held")
            for loop, m in pred["loops"].items():
                gm = m["gain_margin_db"]
                print(f"  {loop:<7} phase margin {m['phase_margin_deg']:6.1f} deg at "
                      f"{m['crossover_rad_s']:6.1f} rad/s, delay margin "
                      f"{1e3 * m['delay_margin_s']:6.1f} ms, gain margin "
                      f"{'inf' if gm is None else round(gm, 1)} dB")
            print(f"  predicted to fail at   {1e3 * pred['failing_delay_s']:.1f} ms "
                  f"(plant delay + the {pred['worst']} loop's delay margin)")
            ms = (lambda s: s if s is None else round(1e3 * s, 1))   # noqa: E731
            print(f"  swept: first failing   {ms(fail)} ms, first {UNSTABLE[name]} "
                  f"{ms(sweep['first_unstable_delay_s'])} ms")
            print(f"  ratio failing / predicted {ratio if ratio is None else round(ratio, 3)} "
                  f"({'within' if ratio and abs(ratio - 1) <= TOLERANCE else 'outside'} +-20 %)")
    if args.json:
        print(json.dumps(out, indent=1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
