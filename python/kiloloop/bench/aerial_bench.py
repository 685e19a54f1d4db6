"""Aerial manipulator benchmark: the C++ controller step (kiloloop_bench_aerial: median, p99, max,
heap allocations per call), the SIL real-time factor of aerial-hover (non-idealities on) with the
tick cost relative to one raw mj_step of the same model, and the inverse-dynamics cross-check
against MuJoCo's mj_inverse."""
from __future__ import annotations

import json
import subprocess
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
    from ..scenarios.aerial_settings import rig_from_settings
    from . import rig_sil_timing

    rig = rig_from_settings(parse_settings(aerial_hover.DEFAULTS, None), seed=0)
    return rig_sil_timing("aerial-hover", rig, aerial_hover.hold(rig), quick)


def run_aerial_bench(quick: bool) -> dict:
    from ..sil.aerial_crosscheck import inverse_dynamics_crosscheck

    return {"core": core_aerial(quick), "sil": sil_aerial(quick),
            "crosscheck": inverse_dynamics_crosscheck(n=50 if quick else 200)}


def print_aerial_bench(report: dict) -> None:
    from . import print_rig_sil

    core, sil = report["core"], report["sil"]
    m = core["machine"]
    print(f"Aerial manipulator, C++, {core['calls']} calls each  [{m['cpu']}, {m['nproc']} cores]")
    print(f"  {'call':<40}{'median':>8}{'p99':>8}{'max':>10}{'alloc':>7}")
    for r in core["results"]:
        print(f"  {r['name']:<40}{r['median_ns']:>8}{r['p99_ns']:>8}{r['max_ns']:>10}"
              f"{r['allocations_per_call']:>7.2f}")
    print("  times in ns; alloc = heap allocations per call")
    print_rig_sil(sil)
    x = report["crosscheck"]
    print(f"Inverse dynamics vs MuJoCo mj_inverse ({x['states']} random states, moving base, "
          f"friction off; goal < 1e-6)")
    print(f"  arm torques, max error             {x['max_tau_error_Nm']:10.2e} N m")
    print(f"  reaction force, max error          {x['max_force_error_N']:10.2e} N")
    print(f"  reaction torque, max error         {x['max_torque_error_Nm']:10.2e} N m")
