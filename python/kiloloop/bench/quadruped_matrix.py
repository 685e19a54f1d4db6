"""Robot x scenario x delay table for the quadruped family (`make matrix`): every quadruped
scenario on our model and on example-robot-data's Go1 (a minimal robot file: name, kind, urdf,
package_dirs, [legs]), at the default 10 ms and at 35 ms motor delay. Prints a Markdown table and
writes it (with the metrics as JSON) under bench/: with ideal sensors (ideal_sensors=true, the
plant's orientation as an exact AHRS). `--realistic`: the same table with the realistic sensors
(the scenarios' default, ideal_sensors=false: MEMS IMU with bias, the controller's own attitude
filter, encoder-difference joint velocity), written as quadruped_matrix_realistic.{md,json}.
`--seeds N`: every cell over seeds 0..N-1 (how many pass, the worst headline figure and the
seeds that fail), written as <stem>_seeds.{md,json} (`make matrix-seeds`: realistic, 5 seeds);
`--jobs J` runs J scenarios at once (default: the machine's cores; results do not depend on it)."""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from .quadruped_robots import robot_file

ROWS = [  # (scenario, extra --set for the 35 ms column too)
    ("quadruped-stand", {}),
    ("quadruped-trot", {}),
    ("quadruped-push", {}),
    ("quadruped-push", {"impulse_per_kg": 0.4}),
    ("quadruped-slope", {}),
    ("quadruped-slope", {"slope_deg": 15.0}),
    ("quadruped-tilt-stop", {}),
    ("quadruped-turn", {}),
    ("quadruped-slope-trot", {}),
    ("quadruped-stones", {}),
    ("quadruped-compliant", {}),
    ("quadruped-rough", {}),
]
DELAYS = (0.010, 0.035)


def go1_file(directory: Path) -> Path | None:
    """Go1's minimal robot file in directory (quadruped_robots.py), or None without
    example-robot-data."""
    return robot_file("go1", directory)


# The figure each scenario's cell shows.
HEADLINE = {"quadruped-stand": "height_error_after_1s_m", "quadruped-trot": "roll_pitch_rms_deg",
            "quadruped-push": "roll_after_recovery_deg", "quadruped-slope": "foot_drift_m",
            "quadruped-tilt-stop": "ticks_late", "quadruped-turn": "yaw_rate_rms_error",
            "quadruped-slope-trot": "velocity_rms_error_down",
            "quadruped-stones": "velocity_rms_error", "quadruped-compliant": "velocity_rms_error",
            "quadruped-rough": "velocity_rms_error"}


def _headline(name: str, m: dict) -> str:
    k = HEADLINE.get(name)
    text = f"{k} {m[k]:.4g}" if k in m else ""
    if name in ("quadruped-stones", "quadruped-compliant", "quadruped-rough") and "max_slip_radii" in m:
        text += f"; roll/pitch RMS {m['roll_pitch_rms_deg']:.3g} deg; slip {m['max_slip_radii']:.2f} radii"
        if "max_sinkage_m" in m:
            text += f"; sinkage {m['max_sinkage_m'] * 1e3:.0f} mm"
    if name == "quadruped-turn" and "peak_load_FL_bw" in m:
        text += "; peak load FL/FR/RL/RR " + "/".join(
            f"{m['peak_load_' + leg + '_bw']:.2f}" for leg in ("FL", "FR", "RL", "RR")) + " x weight"
    return text


def _headline_value(name: str, m: dict) -> float:
    """The headline figure as a number (the worst seed is the largest)."""
    key = HEADLINE.get(name)
    return float(m.get(key, float("inf"))) if key else 0.0


def _run_one(job: tuple) -> dict:
    """One scenario run: job = (robot label, robot, scenario, extra sets, delay, realistic, seed)."""
    from .. import scenarios

    label, robot, name, extra, delay, realistic, seed = job
    sets = dict(extra, motor_delay=delay)
    # Realistic sensors are the scenarios' default; the ideal table asks for ideal.
    sets["ideal_sensors"] = "false" if realistic else "true"
    t0 = time.perf_counter()
    try:
        r = scenarios.run_named(name, robot, sets, seed=seed)
        passed, m, error = r.passed, r.metrics, ""
        failed = [k for k, c in r.criteria.items() if not c["passed"]]
    except Exception as e:  # a refusal is a row too
        passed, m, error, failed = False, {}, str(e), []
    return {"robot": label, "scenario": name, "sets": sets, "seed": seed, "passed": passed,
            "metrics": m, "failed": failed, "error": error, "wall_s": time.perf_counter() - t0}


def _cell(name: str, record: dict) -> str:
    """One seed's cell: pass / fail / FALL and the headline figure."""
    if record["error"]:
        return f"error: {record['error']}"
    m = record["metrics"]
    verdict = "pass" if record["passed"] else ("FALL" if m.get("fell", 0.0) else "fail")
    return f"{verdict} ({_headline(name, m)})"


def _seeds_cell(name: str, records: list) -> str:
    """Several seeds' cell: how many pass, the worst seed (a failing one first, then the largest
    headline figure) and every failing seed with the criteria it misses."""
    n_pass = sum(r["passed"] for r in records)
    text = f"{n_pass}/{len(records)} pass"
    worst = max(records, key=lambda r: (not r["passed"], _headline_value(name, r["metrics"])))
    text += f"; worst seed {worst['seed']}: {_cell(name, worst)}"
    fails = [f"{r['seed']} ({', '.join(r['failed']) or 'error'})" for r in records if not r["passed"]]
    if fails:
        text += "; failing seeds " + ", ".join(fails)
    return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m kiloloop.bench.quadruped_matrix")
    parser.add_argument("out_dir", nargs="?", default="bench", type=Path)
    parser.add_argument("--realistic", action="store_true")
    parser.add_argument("--seeds", type=int, default=0)
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args(argv)
    realistic, n_seeds, jobs, out_dir = args.realistic, args.seeds, args.jobs, args.out_dir
    stem = "quadruped_matrix_realistic" if realistic else "quadruped_matrix"
    if n_seeds:
        stem += "_seeds"
    seeds = list(range(n_seeds)) if n_seeds else [0]
    with tempfile.TemporaryDirectory() as tmp:
        robots = [("quadruped", "quadruped")]
        go1 = go1_file(Path(tmp))
        if go1 is not None:
            robots.append(("go1", str(go1)))
        cells = [(label, robot, name, extra, delay) for label, robot in robots
                 for name, extra in ROWS for delay in DELAYS]
        work = [(*cell, realistic, seed) for cell in cells for seed in seeds]
        with ProcessPoolExecutor(max_workers=max(1, jobs)) as pool:
            records = list(pool.map(_run_one, work))
    rows = []
    for k, (label, _, name, extra, delay) in enumerate(cells):
        group = records[k * len(seeds):(k + 1) * len(seeds)]
        cell = _seeds_cell(name, group) if n_seeds else _cell(name, group[0])
        label_sets = ", ".join(f"{key}={v}" for key, v in extra.items())
        rows.append((label, name + (f" [{label_sets}]" if label_sets else ""), f"{delay * 1e3:.0f} ms", cell))
    table = ["| robot | scenario | delay | result |", "|---|---|---|---|"]
    table += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows]
    text = "\n".join(table) + "\n"
    print(text)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / f"{stem}.md").write_text(text)
    (out_dir / f"{stem}.json").write_text(json.dumps(records, indent=1, default=float))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
