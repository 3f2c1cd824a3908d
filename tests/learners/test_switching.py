"""The learned closed-loop maneuver (learner ``switching``): its closed-loop batch scores a
table as one env steered by it would, it learns within its budget, its run's agent plays what
it reported, and what it cannot steer is refused in one line."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401
from animat.learners.controllers.repertoire import Repertoire
from animat.learners.registry import make_learner
from animat.learners.rollout import score_episode
from animat.learners.skills.steering import (
    TABLE_SHAPE,
    SkillSteering,
    SteeringAgent,
    SteeringParams,
)
from animat.learners.switching import ClosedLoopEvaluator

REPERTOIRE = str(Path(__file__).resolve().parents[2] / "repertoires" / "fish_reactive.json")
REACH = {"duration": 2.0, "distance_bl": (2.0, 4.0), "bearing_deg": (-180.0, 180.0)}


def test_the_closed_loop_batch_scores_each_table_as_one_env_steered_by_it():
    repertoire = Repertoire.load(REPERTOIRE)
    rules = SteeringParams()
    tables = np.random.default_rng(0).integers(0, 7, (3,) + TABLE_SHAPE)
    evaluator = ClosedLoopEvaluator(
        lambda t: SkillSteering(repertoire, rules, 0.05, t), "Animat/FishReach-v0", REACH,
        num_envs=2, seed=7, num_starts=2)
    returns, metrics = evaluator.evaluate_players(tables)
    assert evaluator.env_steps == 3 * 2 * 40  # a chunk's padding is not counted
    env = gym.make("Animat/FishReach-v0", **REACH)
    for p, table in enumerate(tables):
        agent = SteeringAgent(SkillSteering(repertoire, rules, 0.05, table))
        single = [score_episode(env, agent, seed) for seed in (7, 8)]
        assert returns[p] == pytest.approx(np.mean([r["return"] for r in single]), rel=1e-9)
        assert metrics["closest_bl"][p] == pytest.approx(
            np.mean([r["closest_bl"] for r in single]), rel=1e-9)


@pytest.mark.parametrize("edges", [None, [0.5, 1.0, 2.0, 4.0]])
def test_the_switching_learner_learns_within_its_budget_and_its_agent_plays_its_result(
        tmp_path, edges):
    """By default a table of TABLE_SHAPE; with ``range_edges_bl``, one range bin more than
    edges, which its agent reads the same way."""
    params = {"repertoire": REPERTOIRE, "start_states": 2, "chains": 4}
    if edges:
        params["range_edges_bl"] = edges
    learner = make_learner("switching", "Animat/FishReach-v0", REACH, params, seed=3)
    result = learner.learn(4 * 2 * 40 * 3, tmp_path)
    shape = (TABLE_SHAPE[0], len(edges) + 1) if edges else TABLE_SHAPE
    assert result.env_steps <= 960 and np.array(result.artefacts["table"]).shape == shape
    assert {"eval/reached", "eval/closest_bl"} <= set(result.metrics)
    env = gym.make("Animat/FishReach-v0", **REACH)
    agent = learner.agent(result.artefacts, tmp_path)
    again = [score_episode(env, agent, seed) for seed in (3, 4)]
    assert np.mean([r["return"] for r in again]) == pytest.approx(result.metrics["eval/return"])


def test_a_switching_learner_needs_a_reach_env_and_a_repertoire():
    with pytest.raises(ValueError, match="needs a reach env"):
        make_learner("switching", "Animat/FishSwim-v0", {}, {"repertoire": REPERTOIRE})
    with pytest.raises(ValueError, match="needs params.repertoire"):
        make_learner("switching", "Animat/FishReach-v0", REACH, {})


def test_the_coordinate_search_keeps_a_move_only_where_it_scores_better_and_plays_its_result(
        tmp_path):
    learner = make_learner("switching_coordinate", "Animat/FishReach-v0", REACH,
                           {"repertoire": REPERTOIRE, "start_states": 2}, seed=3)
    cost = 2 * 40  # an episode from each start
    result = learner.learn(cost * (1 + 6 * 3), tmp_path)  # the start, then three cells
    assert result.env_steps == cost * (1 + 6 * 3)
    start = learner.controller(np.random.default_rng(3).uniform(0.0, 1.0, 24), 2.0)
    changed = np.array(result.artefacts["table"]) != start
    assert changed.sum() <= 3
    env = gym.make("Animat/FishReach-v0", **REACH)
    again = [score_episode(env, learner.agent(result.artefacts, tmp_path), seed)
             for seed in (3, 4)]
    first = [score_episode(env, SteeringAgent(SkillSteering(
        Repertoire.load(REPERTOIRE), SteeringParams(), 0.05, start)), seed) for seed in (3, 4)]
    assert np.mean([r["return"] for r in again]) == pytest.approx(result.metrics["eval/return"])
    assert result.metrics["eval/return"] >= np.mean([r["return"] for r in first]) - 1e-9
    assert (result.metrics["eval/return"] > np.mean([r["return"] for r in first])) == \
        bool(changed.any())


def test_the_coordinate_search_takes_its_levels_from_the_repertoire():
    with pytest.raises(ValueError, match="levels is the repertoire's moves"):
        make_learner("switching_coordinate", "Animat/FishReach-v0", REACH,
                     {"repertoire": REPERTOIRE, "levels": 3})


@pytest.mark.parametrize("edges", [[], [1.0, 1.0], [0.0, 1.0], "far"])
def test_range_edges_that_are_not_increasing_positive_numbers_are_refused_in_one_line(edges):
    with pytest.raises(ValueError, match="range_edges_bl must be"):
        make_learner("switching", "Animat/FishReach-v0", REACH,
                     {"repertoire": REPERTOIRE, "range_edges_bl": edges}, seed=0)
