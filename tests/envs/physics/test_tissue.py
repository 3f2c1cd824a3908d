"""Tissue that holds in the paper's (resistive) water: every passive element stays within
0.7-1.3 of its rest length under the shipped controllers (its hand MCs and the repertoire's
skills, learned there) and under 1,000 random actions. The default (reactive) water's are in
``test_reactive.py``, which reuses :func:`_passive_strain_range`."""

from pathlib import Path

import numpy as np

from animat.envs.core.batch import BodyBatch
from animat.envs.motor.fish import PAPER_SWIM, PAPER_TURN, swim_mc, to_action, turn_mc
from animat.envs.tasks.locomotion import SwimTask

REPERTOIRE = Path(__file__).resolve().parents[3] / "repertoires" / "fish.json"
PAPER = {"model": "resistive"}


def _passive_strain_range(actions: np.ndarray, water: dict | None = None) -> tuple[float, float]:
    """Min and max passive strain over an episode of actions (T, B, 6) in ``water`` (default
    the default water), seeded starts."""
    core = BodyBatch(actions.shape[1], SwimTask(), duration=1e3, water=water)
    core.reset_rows(np.arange(actions.shape[1]),
                    [np.random.default_rng(k) for k in range(actions.shape[1])])
    body, low, high = core.body, np.inf, 0.0
    passive = body.actuator < 0
    for action in actions:
        core.step(action.astype(np.float64))
        x = core.state.x
        assert np.isfinite(x).all(), "a body blew up"  # min/max would pass over a NaN
        r = x[:, body.elements[passive, 1]] - x[:, body.elements[passive, 0]]
        strain = np.linalg.norm(r, axis=2) / body.rest_lengths[passive]
        low, high = min(low, strain.min()), max(high, strain.max())
    return low, high


def _played(actuation, seconds=8.0, dt=0.05) -> np.ndarray:
    t = dt * np.arange(1, int(round(seconds / dt)) + 1)
    return to_action(actuation(t))[:, None]


def test_random_actions_keep_passive_elements_within_tissue_limits():
    actions = np.random.default_rng(0).uniform(-1, 1, (1000, 16, 6))
    low, high = _passive_strain_range(actions, PAPER)
    assert 0.7 <= low and high <= 1.3, (low, high)


def test_hand_motor_controllers_keep_passive_elements_within_tissue_limits():
    plays = [_played(lambda t, s=s: swim_mc(s, t, PAPER_SWIM)) for s in (0.3, 1.0)]
    plays += [_played(lambda t, left=left: turn_mc(np.pi / 2, t, left, PAPER_TURN))
              for left in (True, False)]
    low, high = _passive_strain_range(np.concatenate(plays, axis=1), PAPER)
    assert 0.7 <= low and high <= 1.3, (low, high)


def test_repertoire_skills_keep_passive_elements_within_tissue_limits():
    from animat.learners.controllers.tent import play
    from animat.learners.skills.repertoire import Repertoire

    skills = Repertoire.load(REPERTOIRE).skills.values()
    actions = np.full((160, len(skills), 6), -1.0)  # relaxed after each skill ends
    for k, skill in enumerate(skills):
        steps = int(round(skill.duration / 0.05))
        actions[:steps, k] = play(skill.controller, 0.05, steps)
    low, high = _passive_strain_range(actions, PAPER)
    assert 0.7 <= low and high <= 1.3, (low, high)
