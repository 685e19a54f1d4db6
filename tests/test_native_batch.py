"""Batch rollouts (sil/batch.py) and scenario runs (scenarios/batch.py): each rollout its own MjData and controller, C++ threads, the GIL
released; the logs do not depend on the thread count and equal single runs."""
import mujoco
import numpy as np
import pytest

import kiloloop as kl
from kiloloop import scenarios
from kiloloop.scenarios import arm_track
from kiloloop.sil import batch, native
from kiloloop.scenarios.arm_controllers import controller
from kiloloop.scenarios.batch import run_scenarios
from kiloloop.sil.arm_adapters import JointTracking
from kiloloop.sil.rig import Rig
from kiloloop.sil.signals import Signals

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")


def make_rollouts(count, duration=0.3):
    """`count` arm-track rollouts on one plant model, each with its own MjData, controller and
    seed (sensor noise on, so that the seeds matter)."""
    robot, settings = scenarios.prepare(arm_track)
    rig = Rig(robot, Signals(q_sigma=1e-4))
    points = arm_track.waypoints(rig, settings)
    rig.plant.q0 = points[0]
    rig.plant.reset()
    traj = kl.QuinticTrajectory(points, np.array([0.0, settings["t_1"], settings["t_2"]]))
    out = []
    for seed in range(count):
        data = mujoco.MjData(rig.plant.model)
        mujoco.mj_copyData(data, rig.plant.model, rig.plant.data)
        reference = JointTracking(controller(robot, rig.model, "computed_torque", points[0]), traj)
        out.append(rig.rollout(duration, reference, data=data, seed=seed,
                               observe=native.Observe("q_true")))
    return out


def test_thread_count_does_not_change_the_logs():
    one = batch.run(make_rollouts(4), threads=1)
    two = batch.run(make_rollouts(4), threads=2)
    for a, b in zip(one, two):
        assert a.ok and b.ok and a.ticks_run == 300
        la, lb = a.log(), b.log()
        for name in la:
            assert np.array_equal(la[name], lb[name]), name
    assert not np.array_equal(one[0].log()["tau"], one[1].log()["tau"])  # seeds differ


def test_batch_entry_points_on_kl_sil():
    rollouts = make_rollouts(2, duration=0.05)
    assert kl.sil.run_batch(rollouts, threads=2) == rollouts
    assert all(r.ok for r in rollouts)


def test_scenario_runs_on_threads_capture_each_failure():
    results = run_scenarios("arm-track", [{"params": {"damping": "0"}, "duration": 0.2},
                                          {"params": {"damping": "bad"}, "duration": 0.2}],
                            threads=2)
    assert results[0]["metrics"]["ticks"] == 200
    assert not results[1]["passed"] and results[1]["reason"].startswith("error: InputError")


def test_the_gil_is_released_while_rollouts_run():
    import threading
    import time

    rollouts = make_rollouts(6, duration=2.0)
    worker = threading.Thread(target=batch.run, args=(rollouts, 1))
    stamps = []
    start = time.perf_counter()
    worker.start()
    while worker.is_alive():  # this thread runs only while the batch does not hold the GIL
        stamps.append(time.perf_counter())
    worker.join()
    wall = time.perf_counter() - start
    assert all(r.ok for r in rollouts)
    # Held GIL: one gap as long as the whole C++ run. Released: only scheduler-sized gaps.
    gap = max(b - a for a, b in zip(stamps, stamps[1:]))
    print(f"batch {wall:.3f} s, longest pause of the main thread {gap:.3f} s")
    assert gap < 0.5 * wall
