"""The inner lives of F world fish, one step at a time: what :class:`MarineWorld` and the
pursuit's prey and passer (:mod:`animat.envs.world.pursuit.env`) both run. From a step's
percepts the mind advances (:func:`~animat.envs.world.mind.advance`), the intention generator
chooses (:class:`~animat.envs.world.intention.IntentionGenerator`), the wanderers' headings are
renewed when due, and the behaviour routines give each fish its navigation command
(:func:`~animat.envs.world.behaviours.commands`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .behaviours import BehaviourParams, commands, wander_directions
from .intention import IntentionGenerator
from .mind import MentalState, MindParams, advance
from .percepts import Percepts, Tank


@dataclass
class Lives:
    """``mind``, ``intentions``; ``wander`` (F, 3) each wanderer's heading and ``wander_due``
    (F,) s when it is renewed (inf: never); the species' ``habit_arrays`` (for
    :meth:`IntentionGenerator.decide`), ``cruise`` and ``sprint`` (F,) speeds; and the
    params of the mind, the behaviours and the tank."""

    mind: MentalState
    intentions: IntentionGenerator
    wander: np.ndarray
    wander_due: np.ndarray
    habit_arrays: dict
    cruise: np.ndarray
    sprint: np.ndarray
    mind_params: MindParams
    behaviour: BehaviourParams
    tank: Tank

    def commands(self, percepts: Percepts, heads: np.ndarray, headings: np.ndarray,
                 com: np.ndarray, time: float | np.ndarray, dt: float, meals: np.ndarray,
                 mated: np.ndarray, rng: np.random.Generator | Sequence[np.random.Generator],
                 focus_of: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        """(F, 3) this step's navigation commands at ``time`` s (scalar, or (F,) per fish)
        after an env step of ``dt`` s with ``meals`` (F,) eaten and ``mated`` (F,);
        ``focus_of(intention)`` gives the
        positions (F, 3) of the fish's focus (nan: none); ``rng`` draws the wanderers' new
        headings (one generator, or one per equal block of fish:
        :func:`~animat.envs.world.behaviours.uniform_angles`)."""
        advance(self.mind, dt, meals, mated, percepts.predator_distance, self.mind_params)
        intention = self.intentions.decide(percepts, self.mind, self.habit_arrays, time)
        due = time >= self.wander_due
        self.wander = wander_directions(rng, heads, self.wander, due, self.tank, self.behaviour)
        self.wander_due = np.where(due, time + self.behaviour.wander_change, self.wander_due)
        return commands(intention, focus_of(intention), percepts, heads, headings, com,
                        self.wander, self.cruise, self.sprint, self.behaviour)
