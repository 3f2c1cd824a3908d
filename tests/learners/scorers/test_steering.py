"""The closed-loop maneuver as a learner (``steering``): scored over seeded reach episodes by the
protocol every learner uses, its agent playing the same episodes alike, and what it cannot steer
refused in one line."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401
from animat.learners.registry import make_learner
from animat.learners.rollout import score_episode
from animat.learners.validation import BudgetError

REPERTOIRE = str(Path(__file__).resolve().parents[3] / "repertoires" / "fish_reactive.json")
REACH = {"duration": 3.0, "distance_bl": (2.0, 2.0), "bearing_deg": (-180.0, 180.0)}


def steering(env_id="Animat/FishReach-v0", env_kwargs=None, **params):
    return make_learner("steering", env_id, REACH if env_kwargs is None else env_kwargs,
                        {"repertoire": REPERTOIRE, "episodes": 2, **params}, seed=5)


def test_the_steering_is_scored_on_its_seeds_and_its_agent_plays_them_alike(tmp_path):
    learner = steering()
    result = learner.learn(2 * 60, tmp_path)
    assert result.env_steps == 120
    assert {"eval/return", "eval/closest_bl", "eval/reached", "eval/final_distance_bl"} <= set(
        result.metrics)
    assert (tmp_path / "repertoire.json").exists()  # the run keeps the skills it steered with
    env = gym.make("Animat/FishReach-v0", **REACH)
    again = [score_episode(env, learner.agent({}, tmp_path), seed) for seed in (5, 6)]
    assert np.mean([r["return"] for r in again]) == pytest.approx(result.metrics["eval/return"])
    assert result.artefacts["episodes"][0]["closest_bl"] == again[0]["closest_bl"]


def test_what_it_cannot_steer_is_refused_in_one_line():
    with pytest.raises(ValueError, match="needs a reach env") as error:
        steering("Animat/FishSwim-v0", {})
    assert "\n" not in str(error.value)
    with pytest.raises(ValueError, match="turn_below_deg <= turn_above_deg"):
        steering(steering={"turn_above_deg": 5.0, "turn_below_deg": 10.0})
    with pytest.raises(BudgetError, match="120 env steps scoring takes"):
        steering().check_budget(100)
