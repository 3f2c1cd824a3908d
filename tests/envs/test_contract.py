"""One contract over the whole registry: every ``Animat/`` id passes Gymnasium's and
stable-baselines3's checkers without a warning, steps finite past an episode's end with the
reward its two terms, renders, and (with a native vector env) steps bit for bit like its single
envs. The behaviour of each room is tested beside it (test_dynamics, test_stunts, ...)."""

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import animat  # noqa: F401

IDS = sorted(i for i in gym.registry if i.startswith("Animat/"))
NATIVE = [i for i in IDS if gym.spec(i).vector_entry_point is not None]
SHORT = {"duration": 0.5}  # 10 env steps an episode (every env takes a duration)


def _numbers(obs) -> list[np.ndarray]:
    return [np.asarray(v) for v in (obs.values() if isinstance(obs, dict) else [obs])]


def _assert_rows_equal(batch, singles, first: int = 0) -> None:
    """Rows ``first``, ``first + 1``, ... of a vector env's observation (an array or a dict of
    them) equal the single envs' observations, bit for bit."""
    for k, single in enumerate(singles):
        if isinstance(batch, dict):
            for key in single:
                np.testing.assert_array_equal(batch[key][first + k], single[key], err_msg=key)
        else:
            np.testing.assert_array_equal(batch[first + k], single)


@pytest.mark.parametrize("env_id", IDS)
def test_the_checkers_pass_without_warnings(env_id):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(gym.make(env_id, render_mode="rgb_array", **SHORT).unwrapped)
        sb3_check_env(gym.make(env_id, **SHORT))


@pytest.mark.parametrize("env_id", IDS)
def test_a_rollout_past_an_episode_end_is_finite_and_renders(env_id):
    env = gym.make(env_id, render_mode="rgb_array", **SHORT)
    obs, _ = env.reset(seed=0)
    env.action_space.seed(0)
    ends = 0
    for _ in range(14):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert all(np.isfinite(v).all() for v in _numbers(obs)) and np.isfinite(reward)
        if "reward_ctrl" in info:
            assert reward == pytest.approx(info["reward_ctrl"] + info["reward_task"])
        if terminated or truncated:
            ends += 1
            obs, _ = env.reset()
    assert ends >= 1
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3


@pytest.mark.parametrize("env_id", NATIVE)
def test_the_native_vector_env_steps_like_its_single_envs(env_id):
    num = 3
    vec = gym.make_vec(env_id, num_envs=num, **SHORT)
    singles = [gym.make(env_id, **SHORT) for _ in range(num)]
    obs, _ = vec.reset(seed=10)
    _assert_rows_equal(obs, [e.reset(seed=10 + i)[0] for i, e in enumerate(singles)])
    rng = np.random.default_rng(0)
    done = np.zeros(num, dtype=bool)
    for _ in range(13):  # crosses an episode's end (10 steps) and the autoreset after it
        actions = rng.uniform(-1, 1, vec.action_space.shape).astype(np.float32)
        obs, reward, _, trunc, _ = vec.step(actions)
        for i, env in enumerate(singles):
            if done[i]:  # the vector env reset it at this step (next-step autoreset)
                o, r, t = env.reset()[0], 0.0, False
            else:
                o, r, _, t, _ = env.step(actions[i])
            _assert_rows_equal(obs, [o], i)
            assert reward[i] == r and trunc[i] == t
        done = trunc
