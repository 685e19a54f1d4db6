"""The timing shared by the native SIL figures of every family (native_bench.py, the arm row and
the report; native_quadruped_bench.py; native_aerial_bench.py): interleaved native-tick and raw
`mj_step` runs, batch scaling, and the figures computed from them. native_bench.py's docstring
says what is timed and why CPU time."""
from __future__ import annotations

import os
import statistics
import time

import mujoco

from ..sil import batch, native

REPEATS = 5
BATCH = 8  # rollouts in the thread-scaling batch (issue 13: 8 on 2 threads vs 1)


def timed_batch(rollouts: list, threads: int, cpu: list | None = None) -> float:
    """[s] wall time of one batch run of configured rollouts (set-up excluded); appends the
    process CPU time [s] it took to `cpu` when given (CPU time / wall = cores actually obtained:
    on a shared machine, other processes' load shows here rather than as a slower loop)."""
    cpu0, start = time.process_time(), time.perf_counter()
    batch.run(rollouts, threads=threads)
    wall = time.perf_counter() - start
    if cpu is not None:
        cpu.append(time.process_time() - cpu0)
    assert all(r.ok for r in rollouts), [r.error for r in rollouts if not r.ok]
    return wall


def timed_ticks_and_raw(make_rollout, commands_of, plant, ticks: int, actuators: list,
                        repeats: int = REPEATS) -> tuple[list, list, list, list]:
    """`repeats` interleaved runs on this thread: one native rollout (make_rollout(), configured),
    then raw `mj_step` from C++ replaying the commands it applied (commands_of(its log)) on the
    plant's model from the same start state: the same motion, so the same contacts and solver
    work, and the difference is the loop. Returns CPU and wall seconds: (tick_cpu, tick_wall,
    raw_cpu, raw_wall)."""
    raw_cpu, raw_wall, tick_cpu, tick_wall = [], [], [], []
    for _ in range(repeats):
        r = make_rollout()
        c0, w0 = time.thread_time(), time.perf_counter()
        r.run()
        tick_cpu.append(time.thread_time() - c0)
        tick_wall.append(time.perf_counter() - w0)
        assert r.ok and r.ticks_run == ticks, r.error
        ctrl = commands_of(r.log())
        data = mujoco.MjData(plant.model)
        mujoco.mj_copyData(data, plant.model, plant.data)
        c0, w0 = time.thread_time(), time.perf_counter()
        native._native.step_raw(plant.model, data, ticks, ctrl, actuators)
        raw_cpu.append(time.thread_time() - c0)
        raw_wall.append(time.perf_counter() - w0)
    return tick_cpu, tick_wall, raw_cpu, raw_wall


def tick_figures(duration: float, ticks: int, substeps: int, physics_dt: float, raw_cpu: list,
                 raw_wall: list, tick_cpu: list, tick_wall: list, controller: float) -> dict:
    """The single-thread figures of a family's row from REPEATS interleaved runs: CPU seconds
    of the native rollout (tick_*) and of raw mj_step replaying its commands (raw_*), and the
    adapter + controller alone [s per tick]."""
    raw = min(raw_cpu) / (ticks * substeps)
    tick = min(tick_cpu) / ticks
    return {
        "sim_seconds": duration,
        "ticks": ticks,
        "physics_dt": physics_dt,
        "raw_mj_step_us": raw * 1e6,
        "tick_us": tick * 1e6,
        "tick_over_mj_step": tick / (raw * substeps),
        # Adapter + compiled controller alone; the rest of the tick over mj_step is the loop.
        "controller_step_us": controller * 1e6,
        "loop_glue_us": (tick - raw * substeps - controller) * 1e6,
        "tick_over_mj_step_wall": (min(tick_wall) / ticks) / (min(raw_wall) / (ticks * substeps)),
        # Simulated seconds per second of one core's CPU time (wall: per elapsed second).
        "real_time_factor": duration / (tick * ticks),
        "real_time_factor_wall": duration / min(tick_wall),
    }


def batch_figures(make_rollouts, duration: float) -> dict:
    """All cores (one thread per core, 2 rollouts per core at least) and the BATCH-rollout batch
    on 1 and 2 threads, medians of REPEATS; make_rollouts(count) builds fresh rollouts."""
    cores = os.cpu_count() or 1
    count = max(BATCH, 2 * cores)
    all_cores = statistics.median(timed_batch(make_rollouts(count), cores) for _ in range(REPEATS))
    cpu1: list = []
    cpu2: list = []
    t1 = statistics.median(timed_batch(make_rollouts(BATCH), 1, cpu1) for _ in range(REPEATS))
    load1 = os.getloadavg()[0]
    t2 = statistics.median(timed_batch(make_rollouts(BATCH), 2, cpu2) for _ in range(REPEATS))
    return {
        "cores": cores,
        "real_time_factor_all_cores": count * duration / all_cores,
        "batch": BATCH,
        "batch_1_thread_s": t1,
        "batch_2_threads_s": t2,
        "batch_speedup_2_over_1": t1 / t2,
        # CPU seconds per batch: equal for 1 and 2 threads = no extra work from threading.
        "batch_1_thread_cpu_s": statistics.median(cpu1),
        "batch_2_threads_cpu_s": statistics.median(cpu2),
        # Between the 1-thread and after the 2-thread batches.
        "load_average_1min": 0.5 * (load1 + os.getloadavg()[0]),
    }
