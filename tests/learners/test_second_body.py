"""The body seam: a second animal defined entirely as data in the tests
(:func:`tests.support.bodies.eel_body`), with its own node count and actuator count, swims in
the fish envs via ``body=`` and goes through a learning round, with no change to library
code."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import animat  # noqa: F401
from animat.envs.physics.system import DEFAULT_DT, STABILITY_MARGIN, stable_step
from animat.learners.registry import make_learner
from tests.support.bodies import eel_body


def test_an_eel_defined_here_swims_in_the_fish_env():
    eel = eel_body()
    assert DEFAULT_DT < STABILITY_MARGIN * stable_step(eel)
    env = gym.make("Animat/FishSwim-v0", body=eel, duration=2.0)
    check_env(env.unwrapped, skip_render_check=True)
    assert env.action_space.shape == (4,)
    assert env.observation_space.shape == (2 * 14 * 3 + 6 + 4,)
    env.reset(seed=0)
    t = np.arange(40) * env.unwrapped.dt
    wave = np.sin(2 * np.pi * 2.0 * t)
    for k in range(40):  # left and right alternate, the back segment lagging
        w0, w1 = wave[k], np.sin(2 * np.pi * 2.0 * t[k] - 0.8)
        env.step(np.array([w0, w1, -w0, -w1], np.float32))
    assert env.unwrapped.node_positions.shape == (14, 3)
    assert np.isfinite(env.unwrapped.node_positions).all()
    vec = gym.make_vec("Animat/FishSwim-v0", num_envs=3, body=eel, duration=1.0)
    assert vec.single_action_space.shape == (4,)


def test_an_eel_without_cross_sections_swims_in_the_resistive_water_only():
    """The default (reactive) water acts on a body's cross-sections: a body that has none is
    refused in one line naming the way out, and swims in the paper's resistive water."""
    eel = eel_body(sections=False)
    with pytest.raises(ValueError, match="needs a body with cross-sections; body 'eel' has "
                       "none: use water=") as error:
        gym.make("Animat/FishSwim-v0", body=eel)
    assert "\n" not in str(error.value)
    env = gym.make("Animat/FishSwim-v0", body=eel, duration=1.0, water={"model": "resistive"})
    env.reset(seed=0)
    for _ in range(20):
        env.step(env.action_space.sample())
    assert np.isfinite(env.unwrapped.node_positions).all()


def test_an_eel_goes_through_an_annealing_round():
    eel = eel_body()
    learner = make_learner("annealing", "Animat/FishSwim-v0", {"body": eel, "duration": 1.0},
                           {"chains": 4, "nodes": 5, "start_states": 2}, seed=0)
    result = learner.learn(4 * 2 * 20 * 2)  # two rounds of 4 chains x 2 starts x 20 steps
    assert result.env_steps == 4 * 2 * 20 * 2
    assert np.array(result.artefacts["controller"]["nodes"]).shape[0] == 4  # one row per actuator
    assert np.isfinite(result.metrics["eval/speed_bl_per_s"])
