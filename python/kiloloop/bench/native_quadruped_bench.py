"""The quadruped row of the native SIL bench (native_bench.py): quadruped-trot (non-idealities
on) on the default quadruped, its native tick against raw mj_step replaying the torques the
motors applied in that run (same start state, same motion and contacts), real-time factors on one
core and on all cores, the 8-rollout batch on 1 and 2 threads, and the gym environment's steps per second (kiloloop/QuadrupedTrot-v0, random actions).
Same conventions as the arm row: CPU time of the calling thread, least of REPEATS runs."""
from __future__ import annotations

import time

import mujoco
import numpy as np

import kiloloop as kl

from .native_timing import BATCH, REPEATS, batch_figures, tick_figures, timed_ticks_and_raw


def _setup():
    from ..scenarios import parse_settings, quadruped_trot
    from ..scenarios.quadruped_settings import rig_from_settings
    from ..scenarios.quadruped_metrics import trot_command

    settings = parse_settings(quadruped_trot.DEFAULTS, None)
    rig = rig_from_settings(settings, seed=0)
    return rig, trot_command(settings["speed"])


def _rollouts(rig, command, count: int, duration: float) -> list:
    out = []
    for seed in range(count):
        data = mujoco.MjData(rig.plant.model)
        mujoco.mj_copyData(data, rig.plant.model, rig.plant.data)
        adapter = rig.adapter(command, kl.QuadrupedController(rig.model, rig.config))
        out.append(rig.rollout(duration, command, data=data, adapter=adapter, seed=seed))
    return out


def _applied_torques(rig, tau_ctrl: np.ndarray) -> np.ndarray:
    """What reached the motors in a native run: the controller's torques (controller order) in
    plant order, through the transport delay (zeros first) and the saturation."""
    motor = rig.family.motor(rig.parts, rig.signals)
    tau = tau_ctrl[:, rig.to_plant]
    delayed = np.zeros_like(tau)
    d = motor.delay_ticks
    delayed[d:] = tau[:len(tau) - d] if d else tau
    if motor.limit:
        limit = np.asarray(motor.limit)
        delayed = np.clip(delayed, -limit, limit)
    return np.ascontiguousarray(delayed)


def env_steps_per_second(steps: int, num_envs: int = 0) -> dict:
    """Random-action rollout of kiloloop/QuadrupedTrot-v0 for `steps` steps (resetting after each
    episode end): steps per second of wall time; num_envs > 0: the vectorized env on all cores,
    steps counting every sub-environment's."""
    from ..envs.quadruped_trot import QuadrupedTrotEnv, QuadrupedTrotVecEnv

    if num_envs:
        env = QuadrupedTrotVecEnv(num_envs=num_envs)
        env.action_space.seed(0)
        env.reset(seed=0)
        start, done_steps, episodes = time.perf_counter(), 0, 0
        while done_steps < steps:
            _, _, term, trunc, _ = env.step(env.action_space.sample())
            done_steps += num_envs
            episodes += int(np.sum(term | trunc))
    else:
        env = QuadrupedTrotEnv()
        env.action_space.seed(0)
        env.reset(seed=0)
        start, done_steps, episodes = time.perf_counter(), 0, 0
        while done_steps < steps:
            _, _, term, trunc, _ = env.step(env.action_space.sample())
            done_steps += 1
            if term or trunc:
                episodes += 1
                env.reset()
    wall = time.perf_counter() - start
    return {"steps": done_steps, "episodes_ended": episodes, "wall_s": wall,
            "steps_per_second": done_steps / wall,
            "ticks_per_step": env._core.ticks, "num_envs": num_envs or 1}


def quadruped_native(quick: bool) -> dict:
    from ..sil import native

    duration = 1.0 if quick else 4.0
    rig, command = _setup()
    ticks = native.ticks_of(duration)
    assert round(0.001 / rig.plant.timestep) == 1, "raw replay assumes one physics step per tick"
    actuators = [int(a) for a in rig.plant._act]
    tick_cpu, tick_wall, raw_cpu, raw_wall = timed_ticks_and_raw(
        lambda: _rollouts(rig, command, 1, duration)[0],
        lambda log: _applied_torques(rig, log["tau"]), rig.plant, ticks, actuators)
    # The adapter + controller alone on the start measurement (standing, no physics).
    ctrl_cpu = []
    y = rig.plant.data.sensordata[rig.measurement_addresses()].copy()
    for _ in range(REPEATS):
        adapter = rig.adapter(command, kl.QuadrupedController(rig.model, rig.config))
        c0 = time.thread_time()
        native._native.step_adapter(adapter, y, ticks)
        ctrl_cpu.append(time.thread_time() - c0)
    controller = min(ctrl_cpu) / ticks

    batches = batch_figures(lambda n: _rollouts(rig, command, n, duration), duration)
    env_steps = 1000 if quick else 10000
    ticking = tick_figures(duration, ticks, 1, rig.plant.timestep, raw_cpu, raw_wall, tick_cpu,
                           tick_wall, controller)
    return {"scenario": "quadruped-trot", "robot": rig.robot.name, **ticking, **batches,
            "env": env_steps_per_second(env_steps),
            "env_vector": env_steps_per_second(env_steps, num_envs=BATCH)}
