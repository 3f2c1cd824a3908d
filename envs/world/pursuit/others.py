"""The pursuit's other fish (the prey, the distractors, the passers): their minds, by the living
world's mind and behaviours (:mod:`animat.envs.world`), in :class:`OtherFish`.

The prey fears the observer (row 0) as a predator and flees it; the distractors cruise at the
prey's speed; the passers at full speed; none is hungry or seeks a mate; the water is open (no
walls) round z = 0. The observer's own row is carried along (the world's functions take every
fish) and its commands dropped.
"""

from __future__ import annotations

import numpy as np

from ..behaviours import BehaviourParams
from ..intention import IntentionGenerator
from ..life import Lives
from ..mind import MentalState, MindParams
from ..oracle import Obstacles, OracleParams
from ..percepts import AvoidParams, Tank, perceive
from .start import OBSERVER, PREY, SEABED_Z


class OtherFish:
    """Minds for ``1 + distractors + passers`` fish beside the observer; ``fear_distance``
    (m): how near the observer puts the prey's fear at the threshold of flight."""

    def __init__(self, distractors: int, passers: int, prey_speed: float,
                 fear_distance: float) -> None:
        fish = self.fish = 2 + distractors + passers
        self.tank = Tank(half_size=1e3, seabed_z=SEABED_Z, top_z=-SEABED_Z)
        self.mind_params = MindParams(fear_distance=fear_distance)
        fears = np.zeros((fish, fish), bool)
        fears[PREY, OBSERVER] = True
        none = np.zeros((fish, fish), bool)
        self.relations = {"fears": fears, "hunts": none, "schools_with": none, "courts": none}
        self.habit_arrays = {name: np.zeros(fish, bool)
                             for name in ("eats_food", "predator", "schooling", "mates")}
        self.cruise = np.array([0.0, *[prey_speed] * (1 + distractors), *[1.0] * passers])
        self.intentions = IntentionGenerator(fish)
        self.senses = OracleParams(field_deg=360.0)  # it feels the observer even right behind

    def reset(self, headings: np.ndarray) -> None:
        """Each fish swims straight on along its ``headings`` (F, 3), level."""
        wander = headings.copy()
        wander[:, 2] = 0.0
        self.intentions.reset()
        none = np.zeros(self.fish)
        self.lives = Lives(MentalState.start(none, none), self.intentions, wander,
                           np.full(self.fish, np.inf), self.habit_arrays, self.cruise,
                           self.cruise, self.mind_params, BehaviourParams(), self.tank)

    def commands(self, heads: np.ndarray, kinematics, time: float, dt: float,
                 rng: np.random.Generator) -> np.ndarray:
        """(F - 1, 3) this step's navigation commands of every fish but the observer, from
        ``heads`` (F, 3) m and the batch's ``kinematics`` at ``time`` s."""
        headings = kinematics.frames[:, 0]
        percepts = perceive(heads, headings, kinematics.com, kinematics.com_vel,
                            np.zeros((0, 3)), self.relations, Obstacles.none(), self.tank,
                            self.senses, AvoidParams())
        no_focus = np.full((self.fish, 3), np.nan)
        return self.lives.commands(percepts, heads, headings, kinematics.com, time, dt,
                                   np.zeros(self.fish), np.zeros(self.fish, bool), rng,
                                   lambda intention: no_focus)[PREY:]
