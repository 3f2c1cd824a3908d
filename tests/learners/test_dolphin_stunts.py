"""The dolphin's repertoire and the stunts composed from it: shipped skills that are the
animal's (not the solver's), and the macro learner (the fish's, from a random start)
discovering a leap."""

from pathlib import Path

import numpy as np
import pytest

from animat.learners.controllers.repertoire import Repertoire
from animat.learners.macro import MacroLearner
from animat.learners.rollout import BatchEvaluator

ROOT = Path(__file__).resolve().parents[2]
REPERTOIRE = ROOT / "repertoires" / "dolphin.json"
DOLPHIN_STEP = {"physics_dt": 0.05 / 160, "frame_skip": 160}  # half the dolphin's step
PAPER_WATER = {"model": "resistive"}  # the water the shipped repertoire was learned in


def _skill_score(skill, finer: bool) -> float:
    kwargs = {**skill.metadata["env_kwargs"], **(DOLPHIN_STEP if finer else {})}
    evaluator = BatchEvaluator(skill.metadata["env_id"], kwargs, num_envs=1, seed=0)
    _, metrics = evaluator.evaluate_players([skill.controller])
    for speed in ("speed_bl_per_s", "arc_speed_bl_per_s"):
        if speed in metrics:
            return float(metrics[speed][0])
    return float(skill.metadata["env_kwargs"]["angle_deg"] - metrics["final_turn_error_deg"][0])


def test_shipped_dolphin_skills_turn_and_swim_and_keep_their_score_at_half_the_step():
    repertoire = Repertoire.load(REPERTOIRE)
    assert sorted(repertoire.names) == ["arc_down", "arc_up", "move_forward", "turn_down",
                                        "turn_left", "turn_right", "turn_up"]
    for name, skill in repertoire.skills.items():
        default, finer = _skill_score(skill, False), _skill_score(skill, True)
        least = 1.5 if name == "move_forward" else 1.0 if name.startswith("arc_") else 20.0
        assert default > least, (name, default)  # BL/s, or degrees turned
        assert abs(finer - default) <= 0.2 * default, (name, default, finer)


@pytest.mark.slow  # 1 M env steps of learning: 57 s
def test_the_macro_learner_discovers_a_leap_from_the_repertoire():
    """The macro learner over the paper's-water repertoire (repertoires/dolphin.json) in that
    water, 1 M env steps, from the point start, on the stages schedule: the learned sequence
    turns up and drives forward, and its centre of mass clears the surface by over half a body
    length at the apex, at the default step and at half of it."""
    learner = MacroLearner("Animat/DolphinLeap-v0", {"duration": 8.0, "water": PAPER_WATER},
                           {"repertoire": str(REPERTOIRE), "slots": 4, "min_duration": 0.25,
                            "max_duration": 4.0, "chains": 64, "schedule": "stages"}, 0)
    result = learner.learn(1_000_000)
    sequence = [step["skill"] for step in result.artefacts["sequence"]]
    assert result.metrics["eval/apex_height_bl"] >= 0.5, (result.metrics, sequence)
    ups = [k for k, name in enumerate(sequence) if name == "turn_up"]
    assert ups and "move_forward" in sequence[ups[0] + 1:], sequence
    evaluator = BatchEvaluator("Animat/DolphinLeap-v0",
                               {"duration": 8.0, "water": PAPER_WATER, **DOLPHIN_STEP},
                               num_envs=1, seed=0)
    agent = learner.agent(result.artefacts, None)  # the learned sequence, open loop
    _, metrics = evaluator.evaluate(agent.actions[None])
    assert np.all(metrics["apex_height_bl"] >= 0.5), metrics["apex_height_bl"]
