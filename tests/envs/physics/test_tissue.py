"""Tissue that holds in the paper's (resistive) water: every passive element stays within
0.7-1.3 of its rest length under the shipped controllers (its hand MCs and the repertoire's
skills, learned there) and under 1,000 random actions. The default (reactive) water's are in
``test_reactive.py``; both measure by :func:`tests.support.tissue.passive_strain_range`."""

from pathlib import Path

import numpy as np

from animat.envs.motor.fish import PAPER_SWIM, PAPER_TURN, swim_mc, to_action, turn_mc
from tests.support.tissue import passive_strain_range

REPERTOIRE = Path(__file__).resolve().parents[3] / "repertoires" / "fish.json"
PAPER = {"model": "resistive"}


def _played(actuation, seconds=8.0, dt=0.05) -> np.ndarray:
    t = dt * np.arange(1, int(round(seconds / dt)) + 1)
    return to_action(actuation(t))[:, None]


def test_random_actions_keep_passive_elements_within_tissue_limits():
    actions = np.random.default_rng(0).uniform(-1, 1, (1000, 16, 6))
    low, high = passive_strain_range(actions, PAPER)
    assert 0.7 <= low and high <= 1.3, (low, high)


def test_hand_motor_controllers_keep_passive_elements_within_tissue_limits():
    plays = [_played(lambda t, s=s: swim_mc(s, t, PAPER_SWIM)) for s in (0.3, 1.0)]
    plays += [_played(lambda t, left=left: turn_mc(np.pi / 2, t, left, PAPER_TURN))
              for left in (True, False)]
    low, high = passive_strain_range(np.concatenate(plays, axis=1), PAPER)
    assert 0.7 <= low and high <= 1.3, (low, high)


def test_repertoire_skills_keep_passive_elements_within_tissue_limits():
    from animat.learners.controllers.repertoire import Repertoire
    from animat.learners.controllers.tent import play

    skills = Repertoire.load(REPERTOIRE).skills.values()
    actions = np.full((160, len(skills), 6), -1.0)  # relaxed after each skill ends
    for k, skill in enumerate(skills):
        steps = int(round(skill.duration / 0.05))
        actions[:steps, k] = play(skill.controller, 0.05, steps)
    low, high = passive_strain_range(actions, PAPER)
    assert 0.7 <= low and high <= 1.3, (low, high)
