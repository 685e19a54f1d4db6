"""Aerial manipulator benchmark: the C++ controller step (kiloloop_bench_aerial: median, p99, max,
heap allocations per call), the SIL real-time factor of aerial-hover (non-idealities on) with the
tick cost relative to one raw mj_step of the same model, and the inverse-dynamics cross-check
against MuJoCo's mj_inverse."""
from __future__ import annotations

import json
import subprocess
import time
from importlib.resources import files
from pathlib import Path

import kiloloop as kl


def core_aerial(quick: bool) -> dict:
    exe = Path(str(files("kiloloop") / "bin" / "kiloloop_bench_aerial"))
    urdf = kl.models_dir() / "aerial_manipulator" / "aerial_manipulator.urdf"
    cmd = [str(exe), str(urdf), "--json"] + (["--quick"] if quick else [])
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def sil_aerial(quick: bool) -> dict:
    from ..scenarios import aerial_hover, parse_settings
    from ..sil.aerial_rig import rig_from_settings
    from . import _raw_mj_step_seconds

    duration = 2.0 if quick else 10.0
    settings = parse_settings(aerial_hover.DEFAULTS, None)
    rig = rig_from_settings(settings, seed=0)
    start = time.perf_counter()
    log = rig.run(duration, aerial_hover.hold(rig))
    wall = time.perf_counter() - start
    ticks = len(log["t"])
    raw = _raw_mj_step_seconds(rig.plant, ticks)
    ctrl, inp, out = rig.controller, rig.input, rig.output
    calls = 2000 if quick else 20000
    start = time.perf_counter()
    for k in range(calls):
        inp.t = inp.stamp = k * 0.001
        ctrl.step(inp, out)
    step_py = (time.perf_counter() - start) / calls
    return {"scenario": "aerial-hover", "sim_seconds": duration, "ticks": ticks,
            "physics_dt": rig.plant.timestep, "real_time_factor": duration / wall,
            "tick_cost_us": wall / ticks * 1e6, "raw_mj_step_us": raw * 1e6,
            "tick_over_mj_step": (wall / ticks) / raw, "python_controller_step_us": step_py * 1e6}


def run_aerial_bench(quick: bool) -> dict:
    from ..sil.aerial_crosscheck import inverse_dynamics_crosscheck
    from ..sil.aerial_rig import aerial_paths

    return {"core": core_aerial(quick), "sil": sil_aerial(quick),
            "crosscheck": inverse_dynamics_crosscheck(*aerial_paths(), n=50 if quick else 200)}


def print_aerial_bench(report: dict) -> None:
    core, sil = report["core"], report["sil"]
    m = core["machine"]
    print(f"Aerial manipulator, C++, {core['calls']} calls each  [{m['cpu']}, {m['nproc']} cores]")
    print(f"  {'call':<40}{'median':>8}{'p99':>8}{'max':>10}{'alloc':>7}")
    for r in core["results"]:
        print(f"  {r['name']:<40}{r['median_ns']:>8}{r['p99_ns']:>8}{r['max_ns']:>10}"
              f"{r['allocations_per_call']:>7.2f}")
    print("  times in ns; alloc = heap allocations per call")
    print(f"SIL {sil['scenario']} ({sil['sim_seconds']} s simulated, non-idealities on, physics dt "
          f"{sil['physics_dt'] * 1e3:g} ms)")
    print(f"  real-time factor                   {sil['real_time_factor']:8.1f} x")
    print(f"  SIL tick cost                      {sil['tick_cost_us']:8.1f} us")
    print(f"  raw mj_step cost                   {sil['raw_mj_step_us']:8.1f} us")
    print(f"  SIL tick / raw mj_step             {sil['tick_over_mj_step']:8.2f}")
    print(f"  controller step via Python         {sil['python_controller_step_us']:8.2f} us")
    x = report["crosscheck"]
    print(f"Inverse dynamics vs MuJoCo mj_inverse ({x['states']} random states, moving base, "
          f"friction off; goal < 1e-6)")
    print(f"  arm torques, max error             {x['max_tau_error_Nm']:10.2e} N m")
    print(f"  reaction force, max error          {x['max_force_error_N']:10.2e} N")
    print(f"  reaction torque, max error         {x['max_torque_error_Nm']:10.2e} N m")
