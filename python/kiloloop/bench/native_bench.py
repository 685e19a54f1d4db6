"""Native SIL figures for `kiloloop bench` (`sil_native` in --json): per family, the native tick
against one raw `mj_step` of the same model (both called from C++), the real-time factor on one
core and on all cores (a batch on one thread per core), the batch speed-up of 2 threads over 1,
(the quadruped row: native_quadruped_bench.py, with the gym environment's steps per second; the
aerial row: native_aerial_bench.py). A family
reports null when the bench runs on another robot file (`--robot`: the arm row only).

Timing is taken around whole C++ calls (the loop itself reads no clock). Costs per tick and per
mj_step are CPU time of the calling thread (`time.thread_time`: the loop and the raw steps run on
it), the least of `REPEATS` interleaved runs: on a shared machine the wall clock also counts other
processes' turns, the thread's CPU time does not. Wall-clock figures sit beside them
(`*_wall`), and the multi-thread figures are wall clock by nature, with the load average.
"""
from __future__ import annotations

import time

import mujoco
import numpy as np

import kiloloop as kl

from .native_aerial_bench import aerial_native
from .native_quadruped_bench import quadruped_native
from .native_timing import REPEATS, batch_figures, tick_figures, timed_ticks_and_raw


def _arm_track_setup(robot=None):
    """(robot, rig, points, trajectory, controller factory) of arm-track on an arm robot file."""
    from .. import scenarios
    from ..scenarios import arm_track
    from ..scenarios.arm_controllers import controller
    from ..sil.rig import Rig

    robot_obj, settings = scenarios.prepare(arm_track, robot)
    rig = Rig(robot_obj)
    points = arm_track.waypoints(rig, settings)
    rig.plant.q0 = points[0]
    rig.plant.reset()
    traj = kl.QuinticTrajectory(points, np.array([0.0, settings["t_1"], settings["t_2"]]))

    def make():
        return controller(robot_obj, rig.model, "computed_torque", points[0])
    return robot_obj, rig, traj, make


def _rollouts(rig, traj, make, count: int, duration: float) -> list:
    """`count` arm-track rollouts on the rig's model, each with its own MjData and controller."""
    from ..sil import native
    from ..sil.arm_adapters import JointTracking

    out = []
    for _ in range(count):
        data = mujoco.MjData(rig.plant.model)
        mujoco.mj_copyData(data, rig.plant.model, rig.plant.data)
        out.append(rig.rollout(duration, JointTracking(make(), traj), data=data,
                               observe=native.Observe("q_true", "ee")))
    return out


def arm_native(quick: bool, robot=None) -> dict:
    from ..sil import native
    from ..sil.arm_adapters import JointTracking
    from ..sil.timing import substeps as substeps_of

    duration = 1.0 if quick else 4.5
    robot_obj, rig, traj, make = _arm_track_setup(robot)
    ticks = native.ticks_of(duration)
    substeps = substeps_of(rig.plant.timestep)

    # The physics timestep equals the control period here (the raw replay's one step a tick).
    assert substeps == 1, "raw replay assumes one physics step per control tick"
    actuators = [int(a) for a in rig.plant._act]
    tick_cpu, tick_wall, raw_cpu, raw_wall = timed_ticks_and_raw(
        lambda: _rollouts(rig, traj, make, 1, duration)[0],
        lambda log: np.ascontiguousarray(log["tau"]), rig.plant, ticks, actuators)
    # The compiled controller behind the adapter alone, on the start measurement (no physics).
    ctrl_cpu = []
    y = np.concatenate([rig.plant.q(), rig.plant.qd()])
    for _ in range(REPEATS):
        adapter = JointTracking(make(), traj).native_adapter()
        c0 = time.thread_time()
        native._native.step_adapter(adapter, y, ticks)
        ctrl_cpu.append(time.thread_time() - c0)
    controller = min(ctrl_cpu) / ticks
    batches = batch_figures(lambda n: _rollouts(rig, traj, make, n, duration), duration)
    ticking = tick_figures(duration, ticks, substeps, rig.plant.timestep, raw_cpu, raw_wall,
                           tick_cpu, tick_wall, controller)
    return {"scenario": "arm-track", "robot": robot_obj.name, **ticking, **batches}


def run_native_bench(quick: bool, robot=None) -> dict:
    from ..sil import native

    if not native.available():
        return {"available": False, "arm": None, "quadruped": None, "aerial": None}
    return {"available": True, "arm": arm_native(quick, robot),
            "quadruped": quadruped_native(quick) if robot is None else None,
            "aerial": aerial_native(quick) if robot is None else None}


def print_native_bench(r: dict) -> None:
    print("Native SIL (the C++ closed loop on the plant's MuJoCo model)")
    if not r.get("available"):
        print("  not built (no mujoco wheel at configure time)")
        return
    for family in ("arm", "quadruped", "aerial"):
        a = r.get(family)
        if a is None:
            print(f"  {family:<10} no native adapter yet")
            continue
        print(f"  {family}: {a['scenario']} on {a['robot']}, {a['sim_seconds']} s simulated; "
              f"CPU time, least of {REPEATS}")
        print(f"    raw mj_step (from C++)              {a['raw_mj_step_us']:8.2f} us")
        print(f"    native tick                         {a['tick_us']:8.2f} us")
        print(f"      of which adapter + controller     {a['controller_step_us']:8.2f} us   "
              f"loop (models, FIFOs, events, logs) {a['loop_glue_us']:.2f} us")
        print(f"    tick / raw mj_step                  {a['tick_over_mj_step']:8.2f}   (goal <= 1.2; "
              f"wall clock {a['tick_over_mj_step_wall']:.2f})")
        print(f"    real-time factor, one core          {a['real_time_factor']:8.0f} x   (wall clock "
              f"{a['real_time_factor_wall']:.0f} x)")
        print(f"    real-time factor, {a['cores']} cores (batch) {a['real_time_factor_all_cores']:8.0f} x")
        print(f"    batch of {a['batch']}: 1 thread {a['batch_1_thread_s']:.3f} s, 2 threads "
              f"{a['batch_2_threads_s']:.3f} s -> {a['batch_speedup_2_over_1']:.2f} x (goal >= 1.8)")
        print(f"      CPU time 1 thread {a['batch_1_thread_cpu_s']:.3f} s, 2 threads "
              f"{a['batch_2_threads_cpu_s']:.3f} s; load average {a['load_average_1min']:.1f} "
              f"on {a['cores']} cores")
        for key, label in (("env", "gym env, random actions"), ("env_vector", "gym vector env")):
            if key in a:
                e = a[key]
                print(f"    {label:<36}{e['steps_per_second']:8.0f} steps/s  ({e['steps']} steps of "
                      f"{e['ticks_per_step']} ticks, {e['num_envs']} env(s), {e['episodes_ended']} "
                      f"episodes ended)")
