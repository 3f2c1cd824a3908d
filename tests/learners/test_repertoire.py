"""Repertoire files and macro sequences."""

import numpy as np
import pytest

from learners.abstraction import abstract
from learners.controller import TentController
from learners.macro import MacroLearner, MacroSequence
from learners.repertoire import Repertoire, Skill

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
