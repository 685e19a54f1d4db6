"""`kiloloop sweep`: a scenario over a grid of settings, in parallel.

    kiloloop sweep aerial-hover --grid att_kp=200,400,800 --grid gyro_sigma=0.01,0.05 --workers 2
    kiloloop sweep arm-track --grid damping=0,0.5,1 --backend ray

Backends: `local` (default) runs on a pool of threads (sil/batch.py: every scenario's loop is in
C++ with the GIL released, so the loops overlap; the Python set-up and metrics take turns); `ray` sends every run to a Ray cluster as one task (RAY_ADDRESS, or a local
Ray instance started for the sweep; `pip install 'kiloloop[ray]'`). Every backend calls the same
`run_one`, so the same seeds give the same rows.

Every combination of the --grid values runs through the scenario's own `run` (the same criteria
as `kiloloop run`); each run reports pass/fail, its metrics and, when it diverged (attitude beyond
60 deg, NaN, solver failure, an exception), the reason. A failed or crashed run never stops the
sweep. Writes a CSV table (one row per run) and a PNG heat map of one metric over the first two
grid keys (averaged over any further keys); with `--log runs.mcap` (or .npz) every run's signal
log too, runs-<i>.mcap for row i (its grid point in the log's settings and run.params), written
by the worker that ran it (with Ray: a path the workers can reach).
"""
from __future__ import annotations

import csv
import itertools
import os
import sys
from pathlib import Path

from . import scenarios
from .errors import InputError
from .scenarios.batch import run_one, run_scenarios  # noqa: F401  (sweep.run_one)
from .scenarios.batch import overrides_of as _overrides


def parse_grid(items: list[str]) -> dict[str, list[str]]:
    """["k=v1,v2", ...] -> {"k": ["v1", "v2"]} (values stay strings: the scenario converts them)."""
    grid: dict[str, list[str]] = {}
    for item in items:
        if "=" not in item:
            raise InputError(f"--grid {item!r}: expected KEY=V1,V2,...")
        key, values = item.split("=", 1)
        vals = [v for v in values.split(",") if v != ""]
        if not key or not vals:
            raise InputError(f"--grid {item!r}: expected KEY=V1,V2,...")
        if key in grid:
            raise InputError(f"--grid {key!r} given twice")
        grid[key] = vals
    return grid


def combinations(grid: dict[str, list[str]]) -> list[dict[str, str]]:
    keys = list(grid)
    return [dict(zip(keys, values)) for values in itertools.product(*(grid[k] for k in keys))]


def _progress(done: int, total: int, failed: int, stream) -> None:
    width = 30
    filled = int(width * done / total) if total else width
    stream.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total}  failed {failed}")
    if done == total:
        stream.write("\n")
    stream.flush()


BACKENDS = ("local", "ray")


def log_path(template, i: int, total: int) -> str:
    """Run i's log: `runs.mcap` -> `runs-007.mcap` (zero-padded to the number of runs)."""
    path = Path(template)
    return str(path.with_name(f"{path.stem}-{i:0{len(str(max(total - 1, 0)))}d}{path.suffix}"))


def run_sweep(scenario: str, grid: dict[str, list[str]], workers: int | None = None,
              seed: int = 0, duration: float | None = None, stream=None, robot=None,
              sets=None, backend: str = "local", log=None) -> list[dict]:
    """All combinations on `workers` threads or processes (default: the machine's cores), or on
    Ray; results in grid order. A worker that dies takes only its own run with it. Grid keys are
    scenario settings or dotted robot-file keys (controller.kp); robot and sets as in
    `kiloloop run`; log: a .npz or .mcap path, each run's log written to log_path(log, i)."""
    from .errors import InputError

    if backend not in BACKENDS:
        raise InputError(f"--backend {backend!r}: expected one of {', '.join(BACKENDS)}")
    stream = sys.stderr if stream is None else stream  # looked up now: tests swap sys.stderr
    module = scenarios.get(scenario)  # unknown scenario: KeyError before any process starts
    combos = combinations(grid)
    # Checked here before any process starts: the robot file and the fixed --set once, every
    # grid value's conversion and list length, and the duration against each point's minimum.
    first = combos[0] if combos else {}
    robot_obj, base = scenarios.prepare(module, robot, _overrides(sets, first))
    for point in combos:
        robot_sets, scenario_sets = scenarios.split_overrides(point)
        point_robot = robot_obj.with_overrides(robot_sets) if robot_sets else robot_obj
        settings = scenarios.parse_settings(base, scenario_sets)
        scenarios.check_settings(module, settings, scenarios.check_robot_sizes(point_robot))
        scenarios.check_duration(duration, module, settings, point_robot)
    workers = max(1, int(workers or os.cpu_count() or 1))
    logs = [log_path(log, i, len(combos)) if log else None for i in range(len(combos))]
    if backend == "ray":
        return _run_ray(scenario, combos, workers, seed, duration, robot, sets, stream, logs)
    counter = {"done": 0, "failed": 0}
    _progress(0, len(combos), 0, stream)

    def on_done(_i, result):
        counter["done"] += 1
        counter["failed"] += not result["passed"]
        _progress(counter["done"], len(combos), counter["failed"], stream)

    runs = [{"params": p, "seed": seed, "duration": duration, "robot": robot, "sets": sets,
             "log": path} for p, path in zip(combos, logs)]
    return run_scenarios(scenario, runs, threads=workers, on_done=on_done)


def _run_ray(scenario, combos, workers, seed, duration, robot, sets, stream,
             logs) -> list[dict]:
    """Every run as one Ray task (run_one, 1 CPU, no retries: a run is deterministic, so a retry
    would fail the same way). Uses the Ray instance already initialized, else RAY_ADDRESS, else a
    local one with `workers` CPUs, shut down afterwards. A task whose worker dies becomes a
    failed row with the reason."""
    try:
        import ray
    except ImportError:
        raise InputError("--backend ray needs Ray: pip install 'kiloloop[ray]'") from None
    started = False
    if not ray.is_initialized():
        address = os.environ.get("RAY_ADDRESS")
        ray.init(address=address, num_cpus=None if address else workers,
                 include_dashboard=False, log_to_driver=False)
        started = True
    try:
        task = ray.remote(num_cpus=1, max_retries=0)(run_one)
        refs = {task.remote(scenario, p, seed, duration, robot, sets, logs[i]): i
                for i, p in enumerate(combos)}
        results: list[dict | None] = [None] * len(combos)
        failed = 0
        _progress(0, len(combos), 0, stream)
        pending = list(refs)
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for ref in done:
                i = refs[ref]
                try:
                    results[i] = ray.get(ref)
                except Exception as e:  # noqa: BLE001 - the worker died or Ray lost the task
                    results[i] = {"params": combos[i], "passed": False, "metrics": {},
                                  "reason": f"worker died: {type(e).__name__}: {e}",
                                  "wall_s": float("nan")}
                failed += not results[i]["passed"]
                _progress(len(combos) - len(pending), len(combos), failed, stream)
        return results  # type: ignore[return-value]
    finally:
        if started:
            ray.shutdown()


def write_csv(results: list[dict], path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    keys = list(results[0]["params"]) if results else []
    metrics = sorted({m for r in results for m in r["metrics"]})
    logs = ["log"] if any(r.get("log") for r in results) else []   # a column with --log only
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys + ["passed", "reason", "wall_s"] + logs + metrics)
        for r in results:
            w.writerow([r["params"][k] for k in keys] + [int(r["passed"]), r["reason"],
                                                          f"{r['wall_s']:.3f}"] +
                       [r.get("log") or "" for _ in logs] +
                       [repr(r["metrics"].get(m, float("nan"))) for m in metrics])
    return path


def write_heatmap(results: list[dict], grid: dict[str, list[str]], metric: str, path,
                  title: str = "") -> Path:
    """Mean of `metric` over the first two grid keys (one row when there is one key); failed
    runs are hatched with their reason's first word."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    keys = list(grid)
    xk = keys[0]
    yk = keys[1] if len(keys) > 1 else None
    xs, ys = grid[xk], (grid[yk] if yk else [""])
    total = np.zeros((len(ys), len(xs)))
    count = np.zeros((len(ys), len(xs)))
    failed = np.zeros((len(ys), len(xs)), dtype=bool)
    for r in results:
        i = ys.index(r["params"][yk]) if yk else 0
        j = xs.index(r["params"][xk])
        value = r["metrics"].get(metric, float("nan"))
        if not r["passed"]:
            failed[i, j] = True
        if value == value:  # not NaN
            total[i, j] += value
            count[i, j] += 1
    with np.errstate(invalid="ignore"):
        grid_values = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    fig, ax = plt.subplots(figsize=(1.6 + 1.1 * len(xs), 1.4 + 0.8 * len(ys)))
    im = ax.imshow(np.ma.masked_invalid(grid_values), cmap="viridis", aspect="auto")
    fig.colorbar(im, ax=ax, label=metric)
    lo, hi = np.nanmin(grid_values), np.nanmax(grid_values)
    for i in range(len(ys)):
        for j in range(len(xs)):
            v = grid_values[i, j]
            text = "n/a" if v != v else f"{v:.3g}"
            # Light text on the dark end of viridis, dark text on the light end.
            light = v != v or hi <= lo or (v - lo) / (hi - lo) < 0.6
            ax.text(j, i, text + ("\nFAIL" if failed[i, j] else ""), ha="center", va="center",
                    color="w" if light else "k", fontsize=8)
    ax.set_xticks(range(len(xs)), xs)
    ax.set_xlabel(xk)
    ax.set_yticks(range(len(ys)), ys)
    if yk:
        ax.set_ylabel(yk)
    extra = f" (mean over {', '.join(keys[2:])})" if len(keys) > 2 else ""
    ax.set_title((title or metric) + extra, fontsize=9)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def default_metric(results: list[dict]) -> str:
    for r in results:
        if r["metrics"]:
            return next(iter(r["metrics"]))
    return ""
