"""The sensor seam: a toy sensor added through ``sensors=`` gives a Dict observation that both
Gymnasium's and stable-baselines3's env checkers accept, in the single and the vector env."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import animat  # noqa: F401
from animat.envs.core.sensors import Proprioception, TaskEntries
from tests.support.sensors import DepthGauge


def test_a_toy_sensor_gives_a_dict_observation_both_checkers_accept():
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    env = gym.make("Animat/FishSwim-v0", sensors=[Proprioception(), DepthGauge()],
                   duration=1.0)
    assert isinstance(env.observation_space, gym.spaces.Dict)
    assert set(env.observation_space.spaces) == {"proprioception", "depth"}
    check_env(env.unwrapped, skip_render_check=True)
    sb3_check_env(env.unwrapped, warn=True)
    obs, _ = env.reset(seed=0)
    assert obs["depth"].shape == (1,) and obs["proprioception"].shape == (150,)
    assert env.observation_space.contains(obs)


def test_the_vector_env_batches_each_sensor_and_keeps_final_observations():
    vec = gym.make_vec("Animat/FishSwim-v0", num_envs=3, duration=0.1,
                       sensors=[Proprioception(), DepthGauge()], autoreset_mode="same_step")
    obs, _ = vec.reset(seed=0)
    assert obs["depth"].shape == (3, 1) and obs["proprioception"].shape == (3, 150)
    for _ in range(2):
        obs, _, _, truncated, info = vec.step(np.zeros((3, 6), np.float32))
    assert truncated.all() and info["final_obs"]["depth"].shape == (3, 1)
    assert vec.observation_space.contains(obs)


def test_sensor_names_must_be_unique():
    with pytest.raises(ValueError, match="unique"):
        gym.make("Animat/FishSwim-v0", sensors=[DepthGauge(), DepthGauge()])


def test_proprioception_and_the_task_entries_apart_make_the_default_observation():
    default = gym.make_vec("Animat/FishReach-v0", num_envs=2, duration=0.2)
    apart = gym.make_vec("Animat/FishReach-v0", num_envs=2, duration=0.2,
                         sensors=[Proprioception(task_entries=False), TaskEntries()])
    assert apart.single_observation_space["proprioception"].shape == (150,)
    assert apart.single_observation_space["task"].shape == (3,)
    assert default.single_observation_space.shape == (153,)
    obs, parts = default.reset(seed=4)[0], apart.reset(seed=4)[0]
    action = np.linspace(-1.0, 1.0, 12, dtype=np.float32).reshape(2, 6)
    for _ in range(3):
        joined = np.concatenate([parts["proprioception"], parts["task"]], axis=1)
        assert joined.dtype == obs.dtype and np.array_equal(joined, obs)
        assert apart.observation_space.contains(parts)
        obs, parts = default.step(action)[0], apart.step(action)[0]
    swim = gym.make("Animat/FishSwim-v0", sensors=[Proprioception(task_entries=False),
                                                   TaskEntries()], duration=0.1)
    obs, _ = swim.reset(seed=0)
    assert obs["task"].shape == (0,) and obs["proprioception"].shape == (150,)
