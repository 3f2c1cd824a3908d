"""The pursuit's other fish (the prey, the distractors, the passers): their minds, by the living
world's mind and behaviours (:mod:`animat.envs.world`), in :class:`OtherFish`.

The prey fears the observer (row 0 of its world) as a predator and flees it; the distractors
cruise at the prey's speed; the passers at full speed; none is hungry or seeks a mate; the
water is open (no walls) round z = 0. The observer's own row is carried along (the world's
functions take every fish) and its commands are the env's to replace.

The minds of N worlds run as one batch of N F fish (world w's fish in rows w F .. w F + F - 1):
every relation is within a world (block-diagonal), a fish of another world is neither
perceived nor a collision danger (it is not there: only the pairs within a world are looked
at), the clock is per world and each world's wanderers draw
from that world's generator, so a world's fish get the commands they would get alone.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..behaviours import BehaviourParams
from ..intention import IntentionGenerator
from ..life import Lives
from ..mind import MentalState, MindParams
from ..oracle import Obstacles, OracleParams
from ..percepts import AvoidParams, Tank, perceive
from .start import OBSERVER, PREY, SEABED_Z


class OtherFish:
    """Minds for ``worlds`` worlds of ``2 + distractors + passers`` fish each (the observer's
    row included); ``fear_distance`` (m): how near the observer puts the prey's fear at the
    threshold of flight."""

    def __init__(self, distractors: int, passers: int, prey_speed: float,
                 fear_distance: float, worlds: int = 1) -> None:
        fish = self.fish = 2 + distractors + passers
        rows = worlds * fish
        self.tank = Tank(half_size=1e3, seabed_z=SEABED_Z, top_z=-SEABED_Z)
        self.mind_params = MindParams(fear_distance=fear_distance)
        world_of = np.repeat(np.arange(worlds), fish)
        self.apart = world_of[:, None] != world_of[None, :]  # (rows, rows): other worlds
        # every (fish, fish) pair of a world, sorted: all the pairs that may count
        self.pairs = (np.repeat(np.arange(rows), fish),
                      np.repeat(world_of * fish, fish) + np.tile(np.arange(fish), rows))
        fears = np.zeros((rows, rows), bool)
        starts = np.arange(worlds) * fish
        fears[starts + PREY, starts + OBSERVER] = True
        none = np.zeros((rows, rows), bool)
        self.relations = {"fears": fears, "hunts": none, "schools_with": none, "courts": none}
        habits = {name: np.zeros(rows, bool)
                  for name in ("eats_food", "predator", "schooling", "mates")}
        cruise = np.tile([0.0, *[prey_speed] * (1 + distractors), *[1.0] * passers], worlds)
        self.intentions = IntentionGenerator(rows)
        self.senses = OracleParams(field_deg=360.0)  # it feels the observer even right behind
        zeros = np.zeros(rows)
        self.lives = Lives(MentalState.start(zeros, zeros), self.intentions,
                           np.zeros((rows, 3)), np.full(rows, np.inf), habits, cruise, cruise,
                           self.mind_params, BehaviourParams(), self.tank)

    def reset(self, world: int, headings: np.ndarray) -> None:
        """World ``world``'s fish start afresh (calm, no intention), each swimming straight on
        along its ``headings`` (F, 3), level."""
        rows = np.arange(world * self.fish, (world + 1) * self.fish)
        lives = self.lives
        self.intentions.reset(rows)
        lives.mind.hunger[rows] = lives.mind.libido[rows] = lives.mind.fear[rows] = 0.0
        lives.wander[rows] = headings
        lives.wander[rows, 2] = 0.0
        lives.wander_due[rows] = np.inf

    def commands(self, heads: np.ndarray, kinematics, time: np.ndarray, dt: float,
                 rngs: Sequence[np.random.Generator]) -> np.ndarray:
        """(N F, 3) this step's navigation commands of every fish (the observers' rows to be
        replaced), from ``heads`` (N F, 3) m and the batch's ``kinematics``, each world at its
        ``time`` (N,) s, world w's wanderers drawing from ``rngs[w]``."""
        headings = kinematics.frames[:, 0]
        percepts = perceive(heads, headings, kinematics.com, kinematics.com_vel,
                            np.zeros((0, 3)), self.relations, Obstacles.none(), self.tank,
                            self.senses, AvoidParams(), exempt=self.apart, pairs=self.pairs)
        rows = len(heads)
        no_focus = np.full((rows, 3), np.nan)
        return self.lives.commands(percepts, heads, headings, kinematics.com,
                                   np.repeat(time, self.fish), dt, np.zeros(rows),
                                   np.zeros(rows, bool), list(rngs), lambda intention: no_focus)
