"""The triggered macro controller: the approach plays as the open-loop macro does until the
dolphin's own sensed height reaches the trigger, the flight then plays from its own start, the
batch scores a candidate as single envs do, and bad input is one line."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from animat.learners.controllers.repertoire import Repertoire
from animat.learners.macro import MacroSequence
from animat.learners.registry import make_learner
from animat.learners.rollout import score_episode
from animat.learners.skills.stunt_trigger import TriggeredPolicy, TriggeredSequence

REPERTOIRE = str(Path(__file__).resolve().parents[3] / "repertoires" / "dolphin_reactive.json")
SKILLS = ["move_forward", "turn_up", "spin_up"]
DT, STEPS, HEIGHT_AT = 0.05, 40, 3


def _sequence(trigger_bl: float) -> TriggeredSequence:
    repertoire = Repertoire.load(REPERTOIRE)
    return TriggeredSequence(MacroSequence(repertoire, [("move_forward", 1.0)], 0.05),
                             MacroSequence(repertoire, [("spin_up", 0.5)], 0.05), trigger_bl)


def test_the_approach_plays_until_the_sensed_height_reaches_the_trigger_then_the_flight():
    sequence = _sequence(-0.5)
    approach, flight = sequence.tracks(DT, STEPS)
    policy = TriggeredPolicy([sequence], np.zeros(2, int), DT, STEPS, HEIGHT_AT)
    obs = np.zeros((2, 5))
    obs[:, HEIGHT_AT] = -1.0
    for k in range(STEPS):
        if k == 7:
            obs[0, HEIGHT_AT] = -0.4  # the first dolphin reaches the trigger at step 7
        if k == 9:
            obs[0, HEIGHT_AT] = -2.0  # and sinks again: its flight goes on
        actions = policy.act(obs)
        np.testing.assert_array_equal(actions[1], approach[k])  # never reached: approach
        np.testing.assert_array_equal(actions[0], approach[k] if k < 7 else flight[k - 7])
    policy.reset()
    np.testing.assert_array_equal(policy.act(obs)[0], approach[0])  # a new episode


def test_the_same_candidate_launches_its_flight_when_each_start_reaches_the_surface():
    """Closed loop: from starts that differ, the flight begins at different env steps."""
    env = gym.make_vec("Animat/DolphinLeap-v0", num_envs=4, duration=3.0)
    repertoire = Repertoire.load(REPERTOIRE)
    sequence = TriggeredSequence(MacroSequence(repertoire, [("turn_up", 1.5),
                                                            ("move_forward", 1.5)], 0.05),
                                 MacroSequence(repertoire, [("spin_up", 1.0)], 0.05), -1.0)
    height_at = int(env.single_observation_space.shape[0]) - 1
    policy = TriggeredPolicy([sequence], np.zeros(4, int), env.dt, env.episode_steps,
                             height_at)
    obs, _ = env.reset(seed=[0, 1, 2, 3])
    for _ in range(env.episode_steps):
        obs, *_ = env.step(policy.act(obs))
    assert (policy.launched > 0).all() and len(set(policy.launched.tolist())) > 1


def test_the_learner_learns_within_its_budget_and_its_agent_replays_its_score(tmp_path):
    learner = make_learner("macro_triggered", "Animat/DolphinSomersault-v0", {"duration": 1.0},
                           {"repertoire": REPERTOIRE, "skills": SKILLS, "slots": 2,
                            "flight_slots": 2, "start_states": 2, "chains": 4}, seed=3)
    result = learner.learn(4 * 2 * 20 * 3, tmp_path)
    assert result.env_steps <= 480
    artefacts = result.artefacts
    assert artefacts["parameters"] == 9 and -1.0 <= artefacts["trigger_height_bl"] <= 0.5
    env = gym.make("Animat/DolphinSomersault-v0", duration=1.0)
    agent = learner.agent(artefacts, tmp_path)
    again = [score_episode(env, agent, seed) for seed in (3, 4)]
    assert np.mean([r["return"] for r in again]) == pytest.approx(result.metrics["eval/return"])


def test_the_approach_can_start_from_a_learned_sequence_and_the_flight_from_random_genes():
    start = [{"skill": "turn_up", "duration": 1.5}, {"skill": "move_forward", "duration": 0.5}]
    learner = make_learner("macro_triggered", "Animat/DolphinLeap-v0", {},
                           {"repertoire": REPERTOIRE, "skills": SKILLS, "slots": 2,
                            "flight_slots": 2, "start_from": start}, seed=0)
    x0 = learner._x0(6)
    assert x0.shape == (9,)
    sequence = learner.controller(x0, 9.0)
    assert sequence.approach.steps == [("turn_up", 1.5), ("move_forward", 0.5)]
    assert -1.0 <= sequence.trigger_bl <= 0.5 and len(sequence.flight.steps) <= 2


@pytest.mark.parametrize("env_id, params, message", [
    ("Animat/FishSwim-v0", {}, "needs a stunt env"),
    ("Animat/DolphinLeap-v0", {"flight_slots": 0}, "flight_slots must be an integer >= 1"),
    ("Animat/DolphinLeap-v0", {"trigger_low": 0.5, "trigger_high": 0.0},
     "need -10 <= trigger_low < trigger_high"),
    ("Animat/DolphinLeap-v0", {"skills": ["fly"]}, "no skill 'fly'"),
])
def test_bad_input_is_refused_in_one_line(env_id, params, message):
    with pytest.raises((ValueError, KeyError), match=message):
        make_learner("macro_triggered", env_id, {}, {"repertoire": REPERTOIRE, **params},
                     seed=0)
