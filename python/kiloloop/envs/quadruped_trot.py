"""kiloloop/QuadrupedTrot-v0: a quadruped trotting forward under the compiled QuadrupedController
in the native SIL loop (C++, GIL released), with the quadruped scenarios' non-idealities (sensor
noise, encoder quantization, motor delay, saturation).

Action (12,) in [-1, 1]: foot-target offsets (dx, dy, dz) per foot (FL, FR, RL, RR), trunk frame,
added to the controller's swing footholds (QuadrupedInput.foothold_offset), scaled by
ACTION_SCALE body heights [m]: derived from the robot, so any robot file of the quadruped family
gets a comparable action range. Held for action_period (20 control ticks by default).

Reward per step, at its last tick: 0.1 v_forward - 0.05 roll^2 - 0.05 pitch^2 - 0.01 |tau|
(v_forward [m/s] in the heading frame, roll/pitch [rad], tau [N m] the commanded joint torques).

Observation (46,), float32, ground truth of the simulator (the policy gets privileged state; the
controller underneath still runs on its noisy sensors): trunk height [m], roll, pitch [rad],
trunk velocity in the heading frame (3) [m/s], trunk angular velocity, body frame (3) [rad/s],
joint positions (12) [rad] and velocities (12) [rad/s] (plant order), the previous action (12),
the commanded speed [m/s].

Episodes: the robot stands for WARMUP seconds (in reset) and then trots at `speed`; an episode
ends when the trunk falls below 0.4 of its standing height (terminated) or after
episode_seconds (truncated).
"""
from __future__ import annotations

import mujoco
import numpy as np
from gymnasium import Env, spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

import kiloloop as kl

from ..sil import native
from ..sil.events import FellBelow
from ..sil.timing import CONTROL_DT, whole_periods
from ..scenarios.quadruped_settings import COMMON_DEFAULTS, rig_from_settings
from ..scenarios.quadruped_metrics import heading_velocity, roll_pitch, trot_command

ACTION_SCALE = 0.1   # [body heights] foot offset per unit action
WARMUP = 0.5         # [s] standing before the trot command, run in reset()
OBS_SIZE = 1 + 2 + 3 + 3 + 12 + 12 + 12 + 1


def _robot(robot):
    if robot is None or isinstance(robot, kl.Robot):
        return robot
    return kl.Robot.load(robot)  # a name under models/ or a robot file


class _Episode:
    """One episode's native rollout on its own MjData, controller and adapter."""

    def __init__(self, rig, speed: float, ticks: int, seed: int):
        plant = rig.plant
        self.data = mujoco.MjData(plant.model)
        mujoco.mj_copyData(self.data, plant.model, plant.data)  # the plant's reset state
        command = trot_command(speed, WARMUP)
        self.adapter = rig.adapter(command, kl.QuadrupedController(rig.model, rig.config))
        duration = WARMUP + ticks * CONTROL_DT
        self.rollout = rig.rollout(duration, command, stop=FellBelow(0.8 * rig.fall_height),
                                   data=self.data, adapter=self.adapter, seed=seed)


class _Core:
    """What the single and the vectorized environment share: the rig (plant model, controller
    configuration, signal models), spaces, episode set-up, observation and reward."""

    def __init__(self, robot=None, speed: float = 0.5, action_period: float = 0.02,
                 episode_seconds: float = 10.0, settings: dict | None = None):
        self.settings = dict(COMMON_DEFAULTS, **(settings or {}))
        self.rig = rig_from_settings(self.settings, 0, robot=_robot(robot))
        self.rig.plant.reset()
        self.speed = float(speed)
        self.ticks = max(1, whole_periods(action_period, CONTROL_DT))
        self.episode_ticks = whole_periods(episode_seconds, CONTROL_DT)
        self.scale = ACTION_SCALE * float(self.rig.config.body_height)  # [m]
        self.action_space = spaces.Box(-1.0, 1.0, (12,), np.float32)
        self.observation_space = spaces.Box(-np.inf, np.inf, (OBS_SIZE,), np.float32)

    def episode(self, seed: int) -> _Episode:
        native.check()
        e = _Episode(self.rig, self.speed, self.episode_ticks, seed)
        e.seed = seed  # the sensor noise stream
        e.rollout.advance(whole_periods(WARMUP, CONTROL_DT))
        e.action = np.zeros(12, np.float32)
        return e

    def act(self, e: _Episode, action) -> None:
        a = np.clip(np.asarray(action, dtype=np.float32).reshape(12), -1.0, 1.0)
        e.action = a
        native._native.set_foothold_offset(e.adapter, self.scale * a.astype(float))

    def observe(self, e: _Episode) -> np.ndarray:
        r, p = self.rig.plant, e.rollout
        quat = p.last("base_quat")
        roll, pitch = roll_pitch(quat[None, :])
        log = {"base_quat": quat[None, :], "base_vel": p.last("base_vel")[None, :]}
        v_heading = heading_velocity(log)[0]
        obs = np.concatenate([[p.last("base_pos")[2], roll[0], pitch[0]], v_heading,
                              [p.last("base_vel")[2]], p.last("base_omega"),
                              e.data.qpos[r._qadr], e.data.qvel[r._dadr], e.action, [self.speed]])
        return obs.astype(np.float32)

    def reward(self, e: _Episode) -> float:
        p = e.rollout
        quat = p.last("base_quat")[None, :]
        roll, pitch = roll_pitch(quat)
        v = heading_velocity({"base_quat": quat, "base_vel": p.last("base_vel")[None, :]})[0, 0]
        tau = np.linalg.norm(p.last("tau"))
        return float(0.1 * v - 0.05 * roll[0] ** 2 - 0.05 * pitch[0] ** 2 - 0.01 * tau)

    def outcome(self, e: _Episode) -> tuple[bool, bool, dict]:
        p = e.rollout
        if not p.ok:
            raise RuntimeError(f"native loop stopped at tick {p.ticks_run}: {p.error}")
        terminated = bool(p.stopped)
        truncated = bool(p.finished and not terminated)
        return terminated, truncated, {"t": (p.ticks_run - 1) * CONTROL_DT}


class QuadrupedTrotEnv(Env):
    """kiloloop/QuadrupedTrot-v0 (see the module docstring). robot: None (the default
    quadruped), a name, a robot file path or a kl.Robot; settings: quadruped scenario settings
    (COMMON_DEFAULTS keys) for the non-idealities."""

    metadata = {"render_modes": []}

    def __init__(self, robot=None, speed: float = 0.5, action_period: float = 0.02,
                 episode_seconds: float = 10.0, settings: dict | None = None, render_mode=None):
        self._core = _Core(robot, speed, action_period, episode_seconds, settings)
        self.action_space = self._core.action_space
        self.observation_space = self._core.observation_space
        self.render_mode = render_mode
        self._episode = None

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self._episode = self._core.episode(int(self.np_random.integers(2 ** 31)))
        return self._core.observe(self._episode), {}

    def step(self, action):
        if self._episode is None:
            raise RuntimeError("step() before reset()")
        e = self._episode
        self._core.act(e, action)
        e.rollout.advance(self._core.ticks)
        terminated, truncated, info = self._core.outcome(e)
        return self._core.observe(e), self._core.reward(e), terminated, truncated, info


class QuadrupedTrotVecEnv(VectorEnv):
    """num_envs episodes stepped together on `threads` C++ threads (sil/batch.py's runner,
    GIL released). Autoreset: next step (gymnasium's default): the step after an episode ends
    resets that environment and ignores its action."""

    metadata = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 8, threads: int | None = None, robot=None,
                 speed: float = 0.5, action_period: float = 0.02, episode_seconds: float = 10.0,
                 settings: dict | None = None, render_mode=None):
        import os

        self._core = _Core(robot, speed, action_period, episode_seconds, settings)
        self.num_envs = int(num_envs)
        self.threads = max(1, int(threads or os.cpu_count() or 1))
        self.single_action_space = self._core.action_space
        self.single_observation_space = self._core.observation_space
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.render_mode = render_mode
        self._episodes: list = [None] * self.num_envs
        self._done = np.zeros(self.num_envs, bool)

    def _seed(self) -> int:
        return int(self.np_random.integers(2 ** 31))

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self._episodes = [self._core.episode(self._seed()) for _ in range(self.num_envs)]
        self._done[:] = False
        return np.stack([self._core.observe(e) for e in self._episodes]), {}

    def step(self, actions):
        actions = np.asarray(actions, dtype=np.float32).reshape(self.num_envs, 12)
        stepping = []
        for i, e in enumerate(self._episodes):
            if self._done[i]:
                self._episodes[i] = self._core.episode(self._seed())
            else:
                self._core.act(e, actions[i])
                stepping.append(e.rollout)
        native._native.advance_batch(stepping, self._core.ticks, self.threads)
        obs = np.zeros((self.num_envs, OBS_SIZE), np.float32)
        rewards = np.zeros(self.num_envs)
        terminated = np.zeros(self.num_envs, bool)
        truncated = np.zeros(self.num_envs, bool)
        for i, e in enumerate(self._episodes):
            obs[i] = self._core.observe(e)
            if self._done[i]:
                self._done[i] = False  # just reset: reward 0, not done
                continue
            rewards[i] = self._core.reward(e)
            terminated[i], truncated[i], _ = self._core.outcome(e)
        self._done = terminated | truncated
        return obs, rewards, terminated, truncated, {}
