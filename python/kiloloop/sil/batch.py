"""Many SIL runs at once on one machine (MuJoCo's `rollout` shape).

Two levels:
- `run(rollouts, threads)`: native Rollouts (sil/native.py), each with its own MjData and
  controller objects, on a pool of C++ threads with the GIL released. The loop is deterministic and
  rollouts share nothing mutable, so results do not depend on the thread count.
- `run_scenarios(scenario, runs, threads)`: whole scenario runs (robot, settings, seed) on a pool
  of Python threads. A native-capable scenario spends its loop in C++ with the GIL released, so the
  loops of different runs overlap; the Python set-up and post-processing of each run (URDF,
  MjSpec compile, metrics) still take the GIL in turn. `kiloloop sweep` uses it for scenarios that
  run natively (`native_capable`), processes for the others.

    from kiloloop.sil import batch, native
    rollouts = [native.rollout(plant, tick.native_adapter(), 4.5, data=mujoco.MjData(plant.model))
                for tick in ticks]
    batch.run(rollouts, threads=2)

Each new MjData starts at the plant's state (native.start_state: a copy of plant.data), as the
plant's own data would; the README's batch example runs in tests/test_doc_snippets.py.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

from . import native


def run(rollouts: list, threads: int | None = None) -> list:
    """Runs every native Rollout once on `threads` C++ threads (default: all cores); returns the
    rollouts (read .ok, .error, .log() or native.signal_log(r)). A failed rollout (a MuJoCo
    error) is reported in its .ok/.error; the others go on."""
    native.check()
    threads = max(1, int(threads or os.cpu_count() or 1))
    native._native.run_batch(list(rollouts), threads)
    return list(rollouts)


def native_capable(scenario: str, sets=None, grid=None) -> bool:
    """True when the scenario's runs take the native loop: its `native` setting is on by default,
    not turned off by `sets` (["native=false"]) nor swept in `grid`, and this build has it."""
    from .. import scenarios

    module = scenarios.get(scenario)
    if not (native.available() and module.DEFAULTS.get("native") is True):
        return False
    if grid and "native" in grid:
        return False
    for item in sets or []:
        key, _, value = item.partition("=")
        if key == "native" and value.lower() in ("0", "false", "no", "off"):
            return False
    return True


def run_scenarios(scenario: str, runs: list[dict], threads: int | None = None,
                  on_done=None) -> list[dict]:
    """Each run is {"params": {...}, "seed": int, "duration": float | None, "robot": ...,
    "sets": [...]}, as `kiloloop sweep` builds them; results in the given order, each the dict of
    sweep.run_one (a failure is captured in it, never raised). on_done(i, result) after each."""
    from ..sweep import run_one

    threads = max(1, int(threads or os.cpu_count() or 1))
    results: list[dict | None] = [None] * len(runs)
    with ThreadPoolExecutor(max_workers=threads) as pool:
        futures = {pool.submit(run_one, scenario, r.get("params", {}), r.get("seed", 0),
                               r.get("duration"), r.get("robot"), r.get("sets")): i
                   for i, r in enumerate(runs)}
        from concurrent.futures import as_completed

        for future in as_completed(futures):
            i = futures[future]
            results[i] = future.result()  # run_one never raises
            if on_done is not None:
                on_done(i, results[i])
    return results  # type: ignore[return-value]
