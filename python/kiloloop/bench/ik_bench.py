"""IK benchmark: runs the compiled `kiloloop_bench_ik` (UR5 and the 7-DoF panda model, ours
beside KDL's ChainIkSolverPos_LMA and ChainIkSolverPos_NR_JL in the same process and run) and
prints its table. Timing happens in C++; see bench/bench_ik.cpp for the protocol.
"""
from __future__ import annotations

import json
import subprocess
from importlib.resources import files
from pathlib import Path

import kiloloop as kl


def run_ik_bench(quick: bool = False, poses: int | None = None) -> dict:
    exe = Path(str(files("kiloloop") / "bin" / "kiloloop_bench_ik"))
    models = kl.models_dir()
    cmd = [str(exe), str(models / "ur5" / "ur5.urdf"), str(models / "panda" / "panda.urdf"), "--json"]
    if poses is not None:
        cmd += ["--poses", str(poses)]
    elif quick:
        cmd.append("--quick")
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def print_ik_bench(r: dict) -> None:
    n = r["robots"][0]["poses"]
    print(f"IK, {n} seeded random reachable poses per robot (seed {r['seed']}), success = within "
          f"{r['position_tolerance']:g} m / {r['orientation_tolerance']:g} rad and the joint limits")
    for robot in r["robots"]:
        print(f"  {robot['robot']} ({robot['nq']} joints)")
        print(f"    {'solver':<32}{'success':>9}{'pose-only':>11}{'median us':>11}{'p99 us':>10}{'alloc':>7}")
        for s in robot["solvers"]:
            print(f"    {s['name']:<32}{100 * s['success_rate']:>8.2f}%{100 * s['pose_ok'] / robot['poses']:>10.2f}%"
                  f"{s['median_us']:>11.2f}{s['p99_us']:>10.2f}{s['allocations_per_call']:>7.2f}")
    print("  goal: >= 99.5 % success and faster than both KDL solvers; pose-only ignores the limits;")
    print("  \"+ our restarts\": the KDL solver in attempts of 15 iterations from the seed, then Halton points, 500 in all")
    print("  UR5 1 kHz path (C++)")
    print(f"    {'call':<58}{'median us':>11}{'p99 us':>10}{'alloc':>7}")
    for s in r.get("step_latency", []):
        print(f"    {s['name']:<58}{s['median_us']:>11.2f}{s['p99_us']:>10.2f}{s['allocations_per_call']:>7.2f}")
