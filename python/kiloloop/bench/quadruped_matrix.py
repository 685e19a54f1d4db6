"""Robot x scenario x delay table for the quadruped family (`make matrix`): every quadruped
scenario on our model and on example-robot-data's Go1 (a minimal robot file: name, kind, urdf,
package_dirs, [legs]), at the default 10 ms and at 35 ms motor delay. Prints a Markdown table and
writes it (with the metrics as JSON) under bench/: with ideal sensors (ideal_sensors=true, the
plant's orientation as an exact AHRS). `--realistic`: the same table with the realistic sensors
(the scenarios' default, ideal_sensors=false: MEMS IMU with bias, the controller's own attitude
filter, encoder-difference joint velocity), written as quadruped_matrix_realistic.{md,json}."""
from __future__ import annotations

import json
import sys
import tempfile
import time
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


def _headline(name: str, m: dict) -> str:
    keys = {"quadruped-stand": "height_error_after_1s_m", "quadruped-trot": "roll_pitch_rms_deg",
            "quadruped-push": "roll_after_recovery_deg", "quadruped-slope": "foot_drift_m",
            "quadruped-tilt-stop": "ticks_late", "quadruped-turn": "yaw_rate_rms_error",
            "quadruped-slope-trot": "velocity_rms_error_down",
            "quadruped-stones": "velocity_rms_error", "quadruped-compliant": "velocity_rms_error",
            "quadruped-rough": "velocity_rms_error"}
    k = keys.get(name)
    text = f"{k} {m[k]:.4g}" if k in m else ""
    if name in ("quadruped-stones", "quadruped-compliant", "quadruped-rough") and "max_slip_radii" in m:
        text += f"; roll/pitch RMS {m['roll_pitch_rms_deg']:.3g} deg; slip {m['max_slip_radii']:.2f} radii"
        if "max_sinkage_m" in m:
            text += f"; sinkage {m['max_sinkage_m'] * 1e3:.0f} mm"
    if name == "quadruped-turn" and "peak_load_FL_bw" in m:
        text += "; peak load FL/FR/RL/RR " + "/".join(
            f"{m['peak_load_' + leg + '_bw']:.2f}" for leg in ("FL", "FR", "RL", "RR")) + " x weight"
    return text


def main(argv=None) -> int:
    from .. import scenarios

    argv = list(argv or [])
    realistic = "--realistic" in argv
    argv = [a for a in argv if a != "--realistic"]
    out_dir = Path(argv[0]) if argv else Path("bench")
    stem = "quadruped_matrix_realistic" if realistic else "quadruped_matrix"
    rows, records = [], []
    with tempfile.TemporaryDirectory() as tmp:
        robots = [("quadruped", "quadruped")]
        go1 = go1_file(Path(tmp))
        if go1 is not None:
            robots.append(("go1", str(go1)))
        for label, robot in robots:
            for name, extra in ROWS:
                for delay in DELAYS:
                    sets = dict(extra, motor_delay=delay)
                    # Realistic sensors are the scenarios' default; the ideal table asks for ideal.
                    sets["ideal_sensors"] = "false" if realistic else "true"
                    t0 = time.perf_counter()
                    try:
                        r = scenarios.run_named(name, robot, sets, seed=0)
                        passed, m = r.passed, r.metrics
                        fell = m.get("fell", 0.0)
                        cell = ("pass" if passed else ("FALL" if fell else "fail")) + \
                            f" ({_headline(name, m)})"
                    except Exception as e:  # a refusal is a row too
                        passed, m, cell = False, {}, f"error: {e}"
                    label_sets = ", ".join(f"{k}={v}" for k, v in extra.items())
                    rows.append((label, name + (f" [{label_sets}]" if label_sets else ""),
                                 f"{delay * 1e3:.0f} ms", cell))
                    records.append({"robot": label, "scenario": name, "sets": sets,
                                    "passed": passed, "metrics": m,
                                    "wall_s": time.perf_counter() - t0})
                    print(" | ".join(rows[-1]), flush=True)
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
