"""Whole scenario runs at once: `run_scenarios(scenario, runs, threads)` runs (robot, settings,
seed) on a pool of Python threads. Every scenario spends its loop in C++ with the GIL released
(sil/rig.py), so the loops of different runs overlap; the Python set-up and post-processing of each
run (URDF, MjSpec compile, metrics) take the GIL in turn. `kiloloop sweep` (sweep.py) uses it, and
`run_one` on Ray: every backend runs the same function, so the same seeds give the same rows.
Native rollouts without a scenario around them: sil/batch.py.
"""
from __future__ import annotations

import math
import os
import time
from concurrent.futures import ThreadPoolExecutor, as_completed

from .. import scenarios


def _divergence(result) -> str:
    reason = result.settings.get("divergence", "") if isinstance(result.settings, dict) else ""
    if reason:
        return str(reason)
    for name, value in result.metrics.items():
        if name.startswith("diverged") and value:
            return name
        if isinstance(value, float) and math.isnan(value):
            return f"NaN metric {name}"
    return ""


def run_one(scenario: str, params: dict, seed: int, duration: float | None, robot=None,
            sets=None, log: str | None = None) -> dict:
    """One scenario run (in a worker thread, process or Ray task); never raises (an exception
    becomes the failure reason). params (the grid point) and sets (fixed --set items) may name
    scenario settings or dotted robot-file keys. log: a .npz or .mcap path the run's signal log
    is written to (its info's run.params: the grid point); the result's "log" names it."""
    start = time.perf_counter()
    try:
        module = scenarios.get(scenario)
        overrides = overrides_of(sets, params)
        # run_sweep has warned about unread keys once; its workers stay quiet.
        robot_obj, settings = scenarios.prepare(module, robot, overrides, warn=False)
        result = scenarios.run(module, settings, robot_obj, seed=seed, duration=duration)
        metrics = {k: float(v) for k, v in result.metrics.items()}
        out = {"params": params, "passed": bool(result.passed), "metrics": metrics,
               "reason": _divergence(result), "wall_s": time.perf_counter() - start}
        if log and result.log is not None:
            result.log.info.setdefault("run", {})["params"] = dict(params)
            out["log"] = str(result.log.save(log))
        return out
    except Exception as e:  # noqa: BLE001 - a sweep records every failure and goes on
        return {"params": params, "passed": False, "metrics": {},
                "reason": f"error: {type(e).__name__}: {e}", "wall_s": time.perf_counter() - start}


def overrides_of(sets, params: dict) -> dict:
    """Fixed --set items and one grid point as one dict of overrides (the point wins)."""
    robot_sets, scenario_sets = scenarios.split_overrides(sets or [])
    return {**robot_sets, **scenario_sets, **params}


def run_scenarios(scenario: str, runs: list[dict], threads: int | None = None,
                  on_done=None) -> list[dict]:
    """Each run is {"params": {...}, "seed": int, "duration": float | None, "robot": ...,
    "sets": [...], "log": path or None}, as `kiloloop sweep` builds them; results in the given
    order, each the dict of run_one (a failure is captured in it, never raised). on_done(i,
    result) after each."""
    threads = max(1, int(threads or os.cpu_count() or 1))
    results: list[dict | None] = [None] * len(runs)
    with ThreadPoolExecutor(max_workers=threads) as pool:
        futures = {pool.submit(run_one, scenario, r.get("params", {}), r.get("seed", 0),
                               r.get("duration"), r.get("robot"), r.get("sets"), r.get("log")): i
                   for i, r in enumerate(runs)}
        for future in as_completed(futures):
            i = futures[future]
            results[i] = future.result()  # run_one never raises
            if on_done is not None:
                on_done(i, results[i])
    return results  # type: ignore[return-value]
