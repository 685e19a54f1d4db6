"""kiloloop/QuadrupedTrot-v0 (kiloloop.envs): gymnasium's env checker passes, the same seed gives
the same episode, the action moves the feet, any quadruped robot file works, and the vectorized
variant over the batch runner matches the single environment step for step."""
import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import kiloloop as kl  # noqa: E402
from kiloloop.sil import native  # noqa: E402

from quadruped_robots import light_quadruped_urdf, minimal_robot_file  # noqa: E402

pytestmark = pytest.mark.skipif(not native.available(), reason="built without the native loop")
ENV = "kiloloop.envs:kiloloop/QuadrupedTrot-v0"


def test_env_checker_passes():
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make(ENV, episode_seconds=1.0)
    check_env(env.unwrapped, skip_render_check=True)


def rollout(env, actions, seed):
    obs, _ = env.reset(seed=seed)
    out = [obs]
    rewards = []
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(a)
        out.append(obs)
        rewards.append(reward)
        if terminated or truncated:
            break
    return np.array(out), np.array(rewards)


def test_same_seed_same_episode_and_the_action_matters():
    env = gymnasium.make(ENV, episode_seconds=1.0)
    zero = np.zeros((25, 12), np.float32)
    forward = np.tile(np.float32([0.5, 0.0, 0.0]), (25, 4))
    a = rollout(env, zero, seed=1)
    b = rollout(env, zero, seed=1)
    c = rollout(env, forward, seed=1)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert not np.array_equal(a[0], c[0])
    # Trotting forward at 0.5 m/s earns about 0.1 * 0.5 minus the torque and tilt terms.
    assert np.all(np.isfinite(a[1])) and a[1].max() < 0.1


def test_random_actions_run_and_episodes_end_cleanly():
    env = gymnasium.make(ENV, episode_seconds=0.5)
    env.action_space.seed(0)
    env.reset(seed=0)
    ends = 0
    for _ in range(60):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs) and np.isfinite(reward)
        if terminated or truncated:
            ends += 1
            env.reset()
    assert ends >= 2  # 0.5 s episodes of 25 steps


def test_any_quadruped_robot_file(tmp_path):
    urdf = light_quadruped_urdf(tmp_path / "light_dog.urdf")
    robot = kl.Robot.load(minimal_robot_file(tmp_path, "light_dog", urdf))
    env = gymnasium.make(ENV, robot=robot, speed=0.3, episode_seconds=0.5)
    obs, rewards = rollout(env, np.zeros((25, 12), np.float32), seed=0)
    assert len(rewards) == 25 and np.all(np.isfinite(obs))


def test_vector_env_matches_single_env():
    from kiloloop.envs.quadruped_trot import QuadrupedTrotEnv, QuadrupedTrotVecEnv

    vec = QuadrupedTrotVecEnv(num_envs=3, threads=2, episode_seconds=0.3)
    obs, _ = vec.reset(seed=4)
    seeds = [e.seed for e in vec._episodes]
    assert len(set(seeds)) == 3
    actions = np.random.default_rng(0).uniform(-0.3, 0.3, (8, 3, 12)).astype(np.float32)
    vec_obs, vec_rew, vec_done = [obs], [], []
    for a in actions:
        obs, rew, term, trunc, _ = vec.step(a)
        vec_obs.append(obs)
        vec_rew.append(rew)
        vec_done.append(term | trunc)
    single = QuadrupedTrotEnv(episode_seconds=0.3)
    core = single.unwrapped._core
    for i, seed in enumerate(seeds):
        # The same episode on this thread, one step at a time: the same numbers.
        e = core.episode(seed)
        assert np.array_equal(core.observe(e), vec_obs[0][i])
        for k, a in enumerate(actions[:, i]):
            core.act(e, a)
            e.rollout.advance(core.ticks)
            assert np.array_equal(core.observe(e), vec_obs[k + 1][i])
            assert core.reward(e) == vec_rew[k][i]
            if vec_done[k][i]:
                break
