"""Arm toolbox figures for `kiloloop bench`: per-step latency and allocations of the Cartesian
impedance, hybrid force/position, supervisor and singularity monitor steps (the compiled
`kiloloop_bench_arm` program, timing in C++), the planner's time, and the arm SIL scenarios'
headline metrics."""
from __future__ import annotations

import json
import subprocess
from importlib.resources import files
from pathlib import Path

import kiloloop as kl


def run_arm_bench(quick: bool) -> dict:
    exe = Path(str(files("kiloloop") / "bin" / "kiloloop_bench_arm"))
    urdf = kl.models_dir() / "ur5" / "ur5.urdf"
    cmd = [str(exe), str(urdf), "--json"] + (["--quick"] if quick else [])
    core = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    from ..scenarios import get, parse_settings

    picks = {"arm-rrt": ("box_contact_ticks", "min_box_distance_m", "plan_iterations",
                         "path_length_rad", "trajectory_duration_s"),
             "arm-press": ("max_force_error_N", "rms_force_error_N", "max_x_error_m"),
             "arm-estop": ("speed_at_estop_rad_s", "stop_time_s", "planned_stop_time_s",
                           "max_stop_distance_rad", "hold_drift_rad")}
    scenarios = {}
    for name, keys in picks.items():
        module = get(name)
        r = module.run(parse_settings(module.DEFAULTS, None))
        scenarios[name] = {"passed": r.passed, **{k: r.metrics[k] for k in keys}}
    return {"core": core, "scenarios": scenarios}


def print_arm_bench(arm: dict) -> None:
    core = arm["core"]
    print(f"Arm toolbox, C++ steps on the UR5, {core['calls']} calls each (times in ns)")
    print(f"  {'call':<32}{'median':>8}{'p99':>8}{'max':>10}{'alloc':>7}")
    for r in core["results"]:
        print(f"  {r['name']:<32}{r['median_ns']:>8}{r['p99_ns']:>8}{r['max_ns']:>10}"
              f"{r['allocations_per_call']:>7.2f}")
    p = core["plan"]
    print(f"  planner (RRT-Connect + shortcut + trapezoid, arm-rrt problem, {p['seeds']} seeds): "
          f"median {p['median_ms']:.2f} ms, p99 {p['p99_ms']:.2f} ms, iterations median "
          f"{p['median_iterations']} max {p['max_iterations']}, failures {p['failures']}")
    for name, m in arm["scenarios"].items():
        figures = ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                            for k, v in m.items() if k != "passed")
        print(f"  {name:<10} {'PASSED' if m['passed'] else 'FAILED'}: {figures}")
