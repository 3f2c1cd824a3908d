"""The closed-loop stunt controller: the senses it reads are the dolphin's own, a table plays
the skills it names, the batch scores a table as single envs do, and bad input is one line."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from animat.envs.tasks.dolphin import pitch_of
from animat.learners.controllers.repertoire import Repertoire
from animat.learners.registry import make_learner
from animat.learners.rollout import score_episode
from animat.learners.skills.stunt_table import StuntTable, senses, table_shape

REPERTOIRE = str(Path(__file__).resolve().parents[3] / "repertoires" / "dolphin_reactive.json")
SKILLS = ["move_forward", "turn_down", "turn_up"]
LEAP = {"duration": 1.0}


def test_the_senses_are_the_dolphins_height_pitch_and_speed_along_its_body():
    env = gym.make("Animat/DolphinLeap-v0", start_pitch_deg=30.0, start_speed=4.0).unwrapped
    obs, _ = env.reset(seed=0)
    obs, _, _, _, info = env.step(-np.ones(6, np.float32))
    core = env.core
    layout = (core.proprioception_size, 6)
    height, pitch, speed = senses(obs[None], *layout)[0]
    _, com_vel, frames = core.kinematics()
    assert height == pytest.approx(info["height_bl"], abs=1e-6)
    assert pitch == pytest.approx(np.degrees(pitch_of(frames))[0], abs=1e-3)
    assert speed == pytest.approx(frames[0, 0] @ com_vel[0] / core.body.length, rel=1e-5)
    assert 20.0 < pitch < 40.0 and speed > 1.0


def test_a_table_of_rest_relaxes_and_a_table_of_one_skill_plays_it_from_its_start():
    repertoire = Repertoire.load(REPERTOIRE)
    layout = (150, 6)
    obs = np.zeros((2, 151))
    obs[:, layout[0] - 6 - 1] = 1.0  # level: the world's up (before the actuations) is the body's
    rest = StuntTable(repertoire, SKILLS, np.zeros(table_shape(), int), 0.05, 0.25, layout)
    rest.reset(2)
    assert (rest.act(obs) == -1.0).all()
    swim = StuntTable(repertoire, SKILLS, np.ones(table_shape(), int), 0.05, 0.25, layout)
    swim.reset(2)
    controller = repertoire["move_forward"].controller
    for k in range(6):
        expected = 2.0 * np.clip(controller(np.array([(k + 1) * 0.05])), 0.0, 1.0) - 1.0
        np.testing.assert_allclose(swim.act(obs), np.repeat(expected, 2, axis=0), rtol=1e-6)


@pytest.mark.parametrize("name, search", [("stunt_table", {"chains": 4}),
                                          ("stunt_table_coordinate", {"candidates": 4})])
def test_the_learner_learns_within_its_budget_and_its_agent_replays_its_score(
        tmp_path, name, search):
    learner = make_learner(name, "Animat/DolphinLeap-v0", LEAP,
                           {"repertoire": REPERTOIRE, "skills": SKILLS, "start_states": 2,
                            **search}, seed=3)
    result = learner.learn(4 * 2 * 20 * 3, tmp_path)
    assert result.env_steps <= 480
    assert np.array(result.artefacts["table"]).shape == table_shape()
    env = gym.make("Animat/DolphinLeap-v0", **LEAP)
    agent = learner.agent(result.artefacts, tmp_path)
    again = [score_episode(env, agent, seed) for seed in (3, 4)]
    assert np.mean([r["return"] for r in again]) == pytest.approx(result.metrics["eval/return"])


@pytest.mark.parametrize("env_id, params, message", [
    ("Animat/FishSwim-v0", {}, "needs a stunt env"),
    ("Animat/DolphinLeap-v0", {"skills": ["fly"]}, "no skill 'fly'"),
    ("Animat/DolphinLeap-v0", {"interval_s": 0}, "interval_s must be > 0 s"),
])
def test_bad_input_is_refused_in_one_line(env_id, params, message):
    with pytest.raises((ValueError, KeyError), match=message):
        make_learner("stunt_table", env_id, {}, {"repertoire": REPERTOIRE, **params}, seed=0)


def test_a_table_of_the_wrong_shape_or_codes_is_refused():
    repertoire = Repertoire.load(REPERTOIRE)
    for table in (np.zeros((4, 5), int), np.full(table_shape(), 9)):
        with pytest.raises(ValueError, match="a stunt table must be integers"):
            StuntTable(repertoire, SKILLS, table, 0.05, 0.25, (150, 6))
