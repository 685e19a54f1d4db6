"""The aerial row of the native SIL bench (native_bench.py): aerial-hover (non-idealities on) on
the default aerial manipulator, its native tick against raw mj_step replaying the commands the
rotors and arm motors received in that run (same start state, same motion), the adapter +
controller alone, real-time factors on one core and on all cores, the 8-rollout batch on 1 and 2
threads. Same conventions as the arm and quadruped rows
(native_bench.py), the figure code shared with them (native_timing.py): CPU time of the calling
thread, least of REPEATS runs."""
from __future__ import annotations

import time

import mujoco
import numpy as np

import kiloloop as kl

from .native_timing import REPEATS, batch_figures, tick_figures, timed_ticks_and_raw


def _setup():
    from ..scenarios import aerial_hover, parse_settings
    from ..scenarios.aerial_metrics import hold
    from ..scenarios.aerial_settings import rig_from_settings

    rig = rig_from_settings(parse_settings(aerial_hover.DEFAULTS, None), seed=0)
    return rig, hold(rig)


def _rollouts(rig, command, count: int, duration: float) -> list:
    from ..sil import native

    ticks = native.ticks_of(duration)
    out = []
    for seed in range(count):
        data = mujoco.MjData(rig.plant.model)
        mujoco.mj_copyData(data, rig.plant.model, rig.plant.data)
        adapter = rig.adapter(command, kl.AerialController(rig.model, rig.config), ticks)
        out.append(rig.rollout(duration, command, data=data, adapter=adapter, seed=seed))
    return out


def _applied_commands(rig, log: dict) -> np.ndarray:
    """What reached the actuators in a native run: [thrust; tau (plant order)] through the
    transport delay (the first command held until it arrives)."""
    u = np.concatenate([log["thrust_cmd"], log["tau"][:, rig.to_plant]], axis=1)
    d = rig.family.motor(rig.parts, rig.signals).delay_ticks
    applied = np.empty_like(u)
    applied[d:] = u[:len(u) - d]
    applied[:d] = u[0]
    return np.ascontiguousarray(applied)


def aerial_native(quick: bool) -> dict:
    from ..sil import native

    duration = 1.0 if quick else 4.0
    rig, command = _setup()
    ticks = native.ticks_of(duration)
    assert round(0.001 / rig.plant.timestep) == 1, "raw replay assumes one physics step per tick"
    actuators = [int(a) for a in rig.plant._rotor_act] + [int(a) for a in rig.plant._act]
    tick_cpu, tick_wall, raw_cpu, raw_wall = timed_ticks_and_raw(
        lambda: _rollouts(rig, command, 1, duration)[0],
        lambda log: _applied_commands(rig, log), rig.plant, ticks, actuators)
    # The adapter + controller alone on the start measurement (hovering, no physics).
    m = rig.family.measurement(rig.parts, rig.signals, rig.seed, command)
    d = rig.plant.data
    y = np.array([(d.sensordata, d.qpos, d.qvel)[s][a] for a, s in zip(m.addresses, m.sources)])
    ctrl_cpu = []
    for _ in range(REPEATS):
        adapter = rig.adapter(command, kl.AerialController(rig.model, rig.config), ticks)
        c0 = time.thread_time()
        native._native.step_adapter(adapter, y, ticks)
        ctrl_cpu.append(time.thread_time() - c0)
    controller = min(ctrl_cpu) / ticks

    batches = batch_figures(lambda n: _rollouts(rig, command, n, duration), duration)
    ticking = tick_figures(duration, ticks, 1, rig.plant.timestep, raw_cpu, raw_wall, tick_cpu,
                           tick_wall, controller)
    return {"scenario": "aerial-hover", "robot": rig.robot.name, **ticking, **batches}
