"""Native tick cost of one family, outside `kiloloop bench`: the figures in bench/RESULTS.md's
per-function tables come from here.

  python scripts/tick_cost.py quadruped --repeats 5     # tick / raw mj_step, the bench's method
  valgrind --tool=callgrind --toggle-collect='kiloloop::sil::Rollout::run()' \
      python scripts/tick_cost.py quadruped --once 1.0  # instructions a tick: divide by 1,000

--repeats: CPU time of the calling thread, least of REPEATS runs of a 4 s rollout, against raw
`mj_step` replaying the commands the motors applied from the same start state (as
python/kiloloop/bench/native_quadruped_bench.py and native_aerial_bench.py). --once: one rollout
of the given simulated seconds and nothing else, so that a profiler's counts are the loop's.
"""
from __future__ import annotations

import argparse


def _family(name: str):
    """(rig, make_rollout(duration), applied_commands(rig, log), actuator ids) of a family."""
    if name == "quadruped":
        from kiloloop.bench import native_quadruped_bench as b
        rig, command = b._setup()
        actuators = [int(a) for a in rig.plant._act]
        return (rig, lambda s: b._rollouts(rig, command, 1, s)[0],
                lambda rig, log: b._applied_torques(rig, log["tau"]), actuators)
    from kiloloop.bench import native_aerial_bench as b
    rig, command = b._setup()
    actuators = [int(a) for a in rig.plant._rotor_act] + [int(a) for a in rig.plant._act]
    return rig, lambda s: b._rollouts(rig, command, 1, s)[0], b._applied_commands, actuators


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("family", choices=["quadruped", "aerial"])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--once", type=float, metavar="SECONDS",
                        help="run one rollout of SECONDS and exit (for callgrind)")
    args = parser.parse_args()
    from kiloloop.sil import native

    rig, make_rollout, applied, actuators = _family(args.family)
    if args.once is not None:
        rollout = make_rollout(args.once)
        rollout.run()
        print(f"{args.family}: {native.ticks_of(args.once)} ticks, ok={rollout.ok}")
        return
    from kiloloop.bench.native_timing import timed_ticks_and_raw

    duration = 4.0
    ticks = native.ticks_of(duration)
    tick, _, raw, _ = timed_ticks_and_raw(lambda: make_rollout(duration),
                                          lambda log: applied(rig, log), rig.plant, ticks,
                                          actuators, repeats=args.repeats)
    print(f"{args.family}: tick {min(tick) / ticks * 1e6:.2f} us, raw mj_step "
          f"{min(raw) / ticks * 1e6:.2f} us, tick / raw mj_step {min(tick) / min(raw):.3f}")


if __name__ == "__main__":
    main()
