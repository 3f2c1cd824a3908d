"""Repertoire files and macro sequences."""

import numpy as np
import pytest

from animat.learners.controllers.abstraction import abstract
from animat.learners.controllers.repertoire import Repertoire, Skill
from animat.learners.controllers.tent import TentController
from animat.learners.macro import MacroLearner, MacroSequence

CHANNELS = 6  # actuations of the test skills (any number)


def _skill(name, level):
    t = np.linspace(0, 1, 11)
    nodes = np.repeat((level + 0.2 * np.sin(2 * np.pi * t))[None], CHANNELS, axis=0)
    return Skill(name, abstract(TentController(nodes, 0.0, 1.0), 0.1),
                 {"task": "swim", "duration": 1.0, "coefficients_kept": 6})


def test_repertoire_round_trips_and_names_missing_skills(tmp_path):
    repertoire = Repertoire([_skill("a", 0.3), _skill("b", 0.6)])
    repertoire.save(tmp_path / "r.json")
    loaded = Repertoire.load(tmp_path / "r.json")
    assert loaded.names == ["a", "b"] and loaded["a"].metadata["task"] == "swim"
    t = np.linspace(0, 3, 30)
    np.testing.assert_allclose(loaded["b"].controller(t), repertoire["b"].controller(t))
    with pytest.raises(KeyError, match="no skill 'c'"):
        loaded["c"]


def test_macro_decodes_selection_order_and_durations(tmp_path):
    Repertoire([_skill("a", 0.3), _skill("b", 0.6)]).save(tmp_path / "r.json")
    learner = MacroLearner("Animat/FishReach-v0", {}, {"repertoire": str(tmp_path / "r.json"),
                                                      "slots": 3, "min_duration": 1.0,
                                                      "max_duration": 3.0})
    # slot genes: 0.1 -> empty, 0.5 -> "a", 0.9 -> "b" (3 choices: none, a, b)
    steps = learner.decode(np.array([0.9, 0.0, 0.1, 0.5, 0.5, 1.0]))
    assert steps == [("b", 1.0), ("a", 3.0)]
    sequence = MacroSequence(learner.repertoire, steps, overlap=0.05)
    assert sequence.duration == pytest.approx(4.0 - 0.05)
    after = sequence(np.array([5.0]))
    np.testing.assert_array_equal(after, 0.0)  # relaxed after the sequence


def test_macro_starts_from_a_given_sequence_and_refuses_a_bad_one(tmp_path):
    Repertoire([_skill("a", 0.3), _skill("b", 0.6)]).save(tmp_path / "r.json")
    params = {"repertoire": str(tmp_path / "r.json"), "slots": 3, "min_duration": 1.0,
              "max_duration": 3.0}
    start = [{"skill": "b", "duration": 2.5}, {"skill": "a", "duration": 1.0}]
    learner = MacroLearner("Animat/FishReach-v0", {}, {**params, "start_from": start})
    assert learner.decode(learner._x0(CHANNELS)) == [("b", 2.5), ("a", 1.0)]
    with pytest.raises(ValueError, match="duration 5.0 of 'a' is outside"):
        MacroLearner("Animat/FishReach-v0", {}, {**params, "start_from": [
            {"skill": "a", "duration": 5.0}]})
    with pytest.raises(ValueError, match="start_from must be a list"):
        MacroLearner("Animat/FishReach-v0", {}, {**params, "start_from": [{"skill": "a"}]})


def _skill_score(skill, refine: int) -> float:
    """A shipped skill's score from the 4 seeded start states, at the default step refined
    ``refine`` times (same env step, so the same actions): swims their mean speed (BL/s),
    turns the degrees of the 90 they achieve (90 - |final heading error|)."""
    from animat.envs.core.batch import DEFAULT_FRAME_SKIP
    from animat.envs.physics.system import DEFAULT_DT
    from animat.learners.rollout import BatchEvaluator

    kwargs = {**skill.metadata["env_kwargs"], "physics_dt": DEFAULT_DT / refine,
              "frame_skip": DEFAULT_FRAME_SKIP * refine}
    evaluator = BatchEvaluator(skill.metadata["env_id"], kwargs, num_envs=1, seed=0)
    _, metrics = evaluator.evaluate_players([skill.controller])
    if skill.metadata["task"] == "swim":
        return float(metrics["speed_bl_per_s"][0])
    return 90.0 - float(metrics["final_heading_error_deg"][0])


def test_shipped_skills_keep_their_score_at_half_the_step():
    """Learned skills are the animal's, not the solver's: each skill of the shipped
    repertoire keeps at least 80% of its score when the physics step is halved."""
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "repertoires" / "fish.json"
    for name, skill in Repertoire.load(path).skills.items():
        default, finer = _skill_score(skill, 1), _skill_score(skill, 2)
        assert default > 0, (name, default)
        assert finer >= 0.8 * default, (name, default, finer)
