"""The zoo (`make zoo`): every robot of bench/zoo_robots.py (example-robot-data's arms, quadrupeds
and multirotors, each from a minimal robot file written here) through every scenario of its
family, seeds 0-4, at the scenarios' default actuation delay (quadrupeds: 10 ms, and 35 ms rows).

    python -m kiloloop.bench.zoo [OUT_DIR] [--jobs 2] [--robots ur5,go1] [--scenarios arm-track,
        quadruped-] [--seeds 0-4] [--delays 10,35] [--fresh]

Writes OUT_DIR/zoo.json (every run: robot, kind, mass, scenario, seed, delay, outcome, criteria
with their values, wall time, refusal or error text) and OUT_DIR/zoo.md (one table per family:
robot (mass) x scenario; a cell is "5/5", or the passes and each failing criterion with the worst
seed's value, or "refused: reason"). Runs merge into an existing zoo.json (a run replaces the
record of the same robot, scenario, seed and delay) unless --fresh, so that a filtered run
updates its cells; the header of zoo.md says what the file holds and when it was run.

Outcomes: passed, failed (a criterion missed; a metric that could not be computed says why),
refused (kiloloop.errors.ScenarioRefused: the robot cannot pass for a physical reason, found at
start), input (any other InputError: a robot file or URDF kiloloop refuses, with the reason),
crashed (any other exception: a bug in kiloloop, with its type).
"""
from __future__ import annotations

import argparse
import datetime
import json
import math
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from . import zoo_robots

SEEDS = (0, 1, 2, 3, 4)
QUADRUPED_DELAYS = (0.010, 0.035)   # [s] the quadruped scenarios' motor_delay rows
PREFIX = {"arm": "arm-", "quadruped": "quadruped-", "aerial": "aerial-"}
FAMILY_TITLES = {"arm": "Arms", "quadruped": "Quadrupeds", "aerial": "Multirotors"}


def family_scenarios(kind: str) -> list[str]:
    """Every built-in scenario of a family (kiloloop.scenarios.names(), by prefix)."""
    from .. import scenarios

    return [n for n in scenarios.names() if n.startswith(PREFIX[kind])]


def delays_for(kind: str, delays_ms: list[float] | None) -> list[float | None]:
    """[s] the delays a family runs at: the quadrupeds' motor_delay rows (filtered by
    --delays, in ms); None (the scenario's own default) for the other families."""
    if kind != "quadruped":
        return [None]
    if delays_ms is None:
        return list(QUADRUPED_DELAYS)
    return [d / 1e3 for d in delays_ms]


def jobs_for(robots, scenario_filter, seeds, delays_ms) -> list[tuple]:
    """(robot, scenario, seed, delay) for every cell the filters keep, in table order."""
    out = []
    for name in robots:
        kind = zoo_robots.ROBOTS[name].kind
        for scenario in family_scenarios(kind):
            if scenario_filter and not any(scenario == f or (f.endswith("-") and
                                                             scenario.startswith(f))
                                           for f in scenario_filter):
                continue
            for delay in delays_for(kind, delays_ms):
                out += [(name, scenario, seed, delay) for seed in seeds]
    return out


def run_one(job: tuple) -> dict:
    """One run: job = (robot name, robot file, scenario, seed, delay [s] or None). Never raises:
    what went wrong is the record's outcome and text."""
    import kiloloop as kl

    from .. import scenarios
    from ..errors import InputError, ScenarioRefused

    name, path, scenario, seed, delay = job
    record = {"robot": name, "kind": zoo_robots.ROBOTS[name].kind, "scenario": scenario,
              "seed": seed, "delay_ms": None if delay is None else round(delay * 1e3, 3),
              "mass_kg": None, "outcome": "", "passed": False, "criteria": {}, "text": ""}
    t0 = time.perf_counter()
    try:
        robot = kl.Robot.load(path)
        record["mass_kg"] = float(robot.model().total_mass)
        sets = {} if delay is None else {"motor_delay": delay}
        result = scenarios.run_named(scenario, robot, sets, seed=seed)
        record["passed"] = bool(result.passed)
        record["outcome"] = "passed" if result.passed else "failed"
        record["criteria"] = {k: {"value": _number(c["value"]), "op": c["op"],
                                  "threshold": c["threshold"], "passed": bool(c["passed"]),
                                  **({"reason": c["reason"]} if c.get("reason") else {})}
                              for k, c in result.criteria.items()}
    except ScenarioRefused as e:
        record["outcome"], record["text"] = "refused", _one_line(e)
    except InputError as e:
        record["outcome"], record["text"] = "input", _one_line(e)
    except Exception as e:  # noqa: BLE001 - a bug in kiloloop is a result of the zoo too
        record["outcome"], record["text"] = "crashed", f"{type(e).__name__}: {_one_line(e)}"
    # The robot file lives in a temporary directory: named by its file name alone.
    record["text"] = record["text"].replace(str(path), Path(path).name)
    record["wall_s"] = round(time.perf_counter() - t0, 3)
    return record


def _number(v):
    """A criterion's value for JSON: a float, None for NaN / missing (never a number it is not)."""
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else (None if math.isnan(v) else v)


def _one_line(e: BaseException) -> str:
    text = str(e).strip()
    return text.splitlines()[0] if text else type(e).__name__


# --- the table ---

def _fmt(v) -> str:
    return "NaN" if v is None else f"{v:.4g}"


def _worst(records: list, criterion: str) -> dict:
    """The failing record whose value lies farthest beyond the criterion's threshold (a value
    that could not be computed counts as the worst)."""
    def beyond(r):
        c = r["criteria"][criterion]
        if c["value"] is None:
            return math.inf
        below = c["op"] in ("<", "<=")   # the limit is an upper bound
        return c["value"] - c["threshold"] if below else c["threshold"] - c["value"]
    return max(records, key=beyond)


def cell_text(records: list) -> str:
    """One table cell from a cell's runs (its seeds): "5/5"; or the passes, then each failing
    criterion with the worst seed's value (or why it was not computed); or "refused: reason"."""
    n = len(records)
    passed = sum(r["outcome"] == "passed" for r in records)
    if passed == n:
        return f"{n}/{n}"
    parts = []
    for outcome, label in (("refused", "refused"), ("input", "refused"), ("crashed", "crashed")):
        hit = [r for r in records if r["outcome"] == outcome]
        if hit:
            seeds = "" if len(hit) == n else f" (seeds {','.join(str(r['seed']) for r in hit)})"
            parts.append(f"{label}{seeds}: {hit[0]['text']}")
    failed = [r for r in records if r["outcome"] == "failed"]
    names = []
    for r in failed:
        names += [k for k, c in r["criteria"].items() if not c["passed"] and k not in names]
    for k in names:
        bad = [r for r in failed if k in r["criteria"] and not r["criteria"][k]["passed"]]
        w = _worst(bad, k)
        c = w["criteria"][k]
        value = c.get("reason") or f"{_fmt(c['value'])} ({c['op']} {c['threshold']:g})"
        parts.append(f"{k} {value} [seed {w['seed']}]")
    text = "; ".join(parts)
    if any(r["outcome"] in ("passed", "failed") for r in records):
        text = f"{passed}/{n}: {text}"
    return text.replace("|", "\\|")


def tables(records: list) -> str:
    """Markdown: one table per family, rows robot (mass) [x delay], columns its scenarios."""
    out = []
    for kind in ("arm", "quadruped", "aerial"):
        rows = [r for r in records if r["kind"] == kind]
        if not rows:
            continue
        scenarios = [s for s in family_scenarios(kind) if any(r["scenario"] == s for r in rows)]
        robots = [n for n in zoo_robots.names(kind) if any(r["robot"] == n for r in rows)]
        delays = sorted({r["delay_ms"] for r in rows}, key=lambda d: -1 if d is None else d)
        out.append(f"## {FAMILY_TITLES[kind]}\n")
        head = ["robot (mass)"] + (["delay"] if kind == "quadruped" else []) + \
            [s[len(PREFIX[kind]):] for s in scenarios]
        out.append("| " + " | ".join(head) + " |")
        out.append("|" + "---|" * len(head))
        for name in robots:
            masses = [r["mass_kg"] for r in rows if r["robot"] == name and r["mass_kg"]]
            label = f"{name} ({masses[0]:.1f} kg)" if masses else name
            for delay in delays:
                cells = []
                for s in scenarios:
                    group = sorted((r for r in rows if r["robot"] == name and r["scenario"] == s
                                    and r["delay_ms"] == delay), key=lambda r: r["seed"])
                    cells.append(cell_text(group) if group else "")
                if not any(cells):
                    continue
                lead = [label] + ([f"{delay:g} ms"] if kind == "quadruped" else [])
                out.append("| " + " | ".join(lead + cells) + " |")
        out.append("")
    return "\n".join(out)


def header(records: list) -> str:
    """What the file holds: per family the robots, seeds and delays run, and the dates."""
    lines = ["# The zoo: example-robot-data's robots x their family's scenarios", "",
             "Written by `make zoo` (python/kiloloop/bench/zoo.py; docs/zoo.md). Each robot from "
             "a minimal robot file (bench/zoo_robots.py), nothing tuned. A cell: passes / seeds "
             "run, then each failing criterion with the worst seed's value and its limit; "
             "\"refused\": the scenario (or the loader) refused the robot at start, with the "
             "reason. Per-run figures: bench/zoo.json.", "", "This file holds:"]
    for kind in ("arm", "quadruped", "aerial"):
        rows = [r for r in records if r["kind"] == kind]
        if not rows:
            continue
        seeds = sorted({r["seed"] for r in rows})
        delays = sorted({r["delay_ms"] for r in rows if r["delay_ms"] is not None})
        dates = sorted({r.get("date", "") for r in rows})
        wall = [r["wall_s"] for r in rows]
        lines.append(
            f"- {FAMILY_TITLES[kind].lower()}: {len({r['robot'] for r in rows})} robots, "
            f"{len(rows)} runs, seeds {','.join(map(str, seeds))}"
            + (f", delays {'/'.join(f'{d:g}' for d in delays)} ms" if delays else
               ", the scenarios' default delay")
            + f"; run {dates[0]}" + (f" to {dates[-1]}" if dates[-1] != dates[0] else "")
            + f"; wall time per run {min(wall):.1f}-{max(wall):.1f} s (mean "
              f"{sum(wall) / len(wall):.1f} s, one process each)")
    return "\n".join(lines) + "\n\n"


def write(records: list, out_dir: Path) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "zoo.json").write_text(json.dumps(records, indent=1) + "\n")
    (out_dir / "zoo.md").write_text(header(records) + tables(records))


def _key(r: dict) -> tuple:
    return (r["robot"], r["scenario"], r["seed"], r["delay_ms"])


def merge(old: list, new: list) -> list:
    """old's records with new's replacing those of the same (robot, scenario, seed, delay), in
    the zoo's order."""
    by_key = {_key(r): r for r in old}
    by_key.update({_key(r): r for r in new})
    order = {n: i for i, n in enumerate(zoo_robots.ROBOTS)}
    return sorted(by_key.values(), key=lambda r: (order.get(r["robot"], 1 << 30), r["scenario"],
                                                  r["delay_ms"] or 0.0, r["seed"]))


def _seeds(text: str) -> list[int]:
    out = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out += list(range(int(lo), int(hi or lo) + 1))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m kiloloop.bench.zoo", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out_dir", nargs="?", default="bench", type=Path)
    parser.add_argument("--jobs", type=int, default=2, help="processes at once (default 2)")
    parser.add_argument("--robots", default="", help="names or families (arm, quadruped, "
                        "aerial), comma-separated; default all")
    parser.add_argument("--scenarios", default="", help="names, or prefixes ending in '-' "
                        "(quadruped-), comma-separated; default every scenario of the family")
    parser.add_argument("--seeds", default="0-4", help="e.g. 0-4 or 0,2 (default 0-4)")
    parser.add_argument("--delays", default="", help="quadruped motor delays [ms], e.g. 10,35 "
                        "(default 10,35); other families run at their scenarios' default")
    parser.add_argument("--fresh", action="store_true", help="do not merge into zoo.json")
    args = parser.parse_args(argv)

    robots = []
    for item in (s for s in args.robots.split(",") if s):
        if item in PREFIX:
            robots += zoo_robots.names(item)
        elif item in zoo_robots.ROBOTS:
            robots.append(item)
        else:
            parser.error(f"unknown robot {item!r}; known: {', '.join(zoo_robots.ROBOTS)}")
    robots = robots or list(zoo_robots.ROBOTS)
    scenario_filter = [s for s in args.scenarios.split(",") if s]
    delays = [float(d) for d in args.delays.split(",") if d] or None
    if zoo_robots.erd_share() is None:
        print("example-robot-data is not installed (pip install example-robot-data)")
        return 1
    work = jobs_for(robots, scenario_filter, _seeds(args.seeds), delays)
    date = datetime.date.today().isoformat()
    records, t_start = [], time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        paths = {n: str(zoo_robots.robot_file(n, tmp)) for n in robots}
        print(f"zoo: {len(work)} runs on {args.jobs} processes", flush=True)
        with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = [pool.submit(run_one, (n, paths[n], s, seed, d)) for n, s, seed, d in work]
            for i, f in enumerate(as_completed(futures), 1):
                r = f.result()
                r["date"] = date
                records.append(r)
                detail = ", ".join(k for k, c in r["criteria"].items() if not c["passed"])
                print(f"[{i}/{len(work)}] {r['robot']} {r['scenario']} seed {r['seed']}"
                      + ("" if r["delay_ms"] is None else f" {r['delay_ms']:g} ms")
                      + f": {r['outcome']}" + (f" ({detail})" if detail else "")
                      + (f": {r['text']}" if r["text"] else "") + f"  {r['wall_s']:.1f} s",
                      flush=True)
    out = args.out_dir / "zoo.json"
    old = [] if args.fresh or not out.exists() else json.loads(out.read_text())
    write(merge(old, records), args.out_dir)
    n_pass = sum(r["outcome"] == "passed" for r in records)
    print(f"zoo: {n_pass}/{len(records)} passed in {time.perf_counter() - t_start:.0f} s; "
          f"{args.out_dir / 'zoo.md'}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
