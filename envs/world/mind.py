"""The mind of a world fish (the paper's Section 2, after Tu and Terzopoulos 1994): innate
habits per species and the mental variables hunger, libido and fear, for many fish at once.

Mental variables are in [0, 1], one per fish, advanced once per env step of ``dt`` s:

* **hunger** grows linearly to 1 over ``hunger_time`` s and falls by ``meal`` for every food
  particle eaten (a satiated fish is 0);
* **libido** grows over ``libido_time`` s, the faster the less hungry the fish is (its rate
  times 1 - hunger), and is spent (0) by mating;
* **fear** follows the nearest predator it perceives: the stimulus ``min(1, fear_distance /
  d)`` (d the distance, m) raises it at once, and it decays with time constant
  ``fear_decay`` s once the predator is gone or far.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Habits:
    """A species' innate character: ``name``; ``colour`` (RGB) of its skin; ``predator``
    (hunts the ``prey`` species by name) or not; ``schooling`` (keeps with its kind);
    ``eats_food`` (forages food particles); ``mates`` (courts the other sex of its kind);
    ``fears`` (the species names it flees); ``speed`` in [0, 1] of its cruise and ``sprint``
    of its flight or chase (a predator outswims its prey); ``appetite``:
    the hunger above which it starts to forage or hunt (a schooling fish keeps with its
    school until it is hungrier)."""

    name: str
    colour: tuple[int, int, int]
    predator: bool = False
    prey: tuple[str, ...] = ()
    schooling: bool = False
    eats_food: bool = True
    mates: bool = False
    fears: tuple[str, ...] = ()
    speed: float = 0.6
    sprint: float = 1.0
    appetite: float = 0.4

    def __post_init__(self) -> None:
        if not 0.0 <= self.speed <= self.sprint <= 1.0:
            raise ValueError(f"habits {self.name!r}: need 0 <= speed <= sprint <= 1, got "
                             f"{self.speed!r}, {self.sprint!r}")
        if not 0.0 <= self.appetite <= 1.0:
            raise ValueError(f"habits {self.name!r}: appetite must be in [0, 1], got "
                             f"{self.appetite!r}")
        if self.predator and not self.prey:
            raise ValueError(f"habits {self.name!r}: a predator needs the prey it hunts")


@dataclass(frozen=True)
class MindParams:
    """hunger_time, libido_time: s from 0 to 1; meal: the hunger one food particle removes;
    fear_distance: m at which a perceived predator's stimulus is 1; fear_decay: s, the time
    constant of fear's decay."""

    hunger_time: float = 120.0
    libido_time: float = 40.0
    meal: float = 0.3
    fear_distance: float = 0.3
    fear_decay: float = 2.0

    def __post_init__(self) -> None:
        for name in ("hunger_time", "libido_time", "fear_distance", "fear_decay"):
            if not getattr(self, name) > 0:
                raise ValueError(f"mind: {name} must be > 0, got {getattr(self, name)!r}")
        if not 0.0 < self.meal <= 1.0:
            raise ValueError(f"mind: meal must be in (0, 1], got {self.meal!r}")


@dataclass
class MentalState:
    """(F,) hunger, libido and fear of F fish, each in [0, 1]."""

    hunger: np.ndarray
    libido: np.ndarray
    fear: np.ndarray

    @classmethod
    def start(cls, hunger: np.ndarray, libido: np.ndarray) -> MentalState:
        hunger, libido = np.asarray(hunger, float).copy(), np.asarray(libido, float).copy()
        return cls(hunger, libido, np.zeros_like(hunger))


def fear_stimulus(predator_distance: np.ndarray, params: MindParams) -> np.ndarray:
    """(F,) in [0, 1] from the distance (m) to the nearest perceived predator (inf: none)."""
    with np.errstate(divide="ignore"):
        return np.minimum(1.0, params.fear_distance / np.maximum(predator_distance, 1e-9))


def advance(mind: MentalState, dt: float, meals: np.ndarray, mated: np.ndarray,
            predator_distance: np.ndarray, params: MindParams) -> None:
    """Advance ``mind`` in place by ``dt`` s: ``meals`` (F,) food particles eaten this step,
    ``mated`` (F,) bool, ``predator_distance`` (F,) m to the nearest perceived predator."""
    mind.hunger[:] = np.clip(mind.hunger + dt / params.hunger_time - params.meal * meals,
                             0.0, 1.0)
    rate = (1.0 - mind.hunger) / params.libido_time
    mind.libido[:] = np.where(mated, 0.0, np.clip(mind.libido + dt * rate, 0.0, 1.0))
    decayed = mind.fear * np.exp(-dt / params.fear_decay)
    mind.fear[:] = np.maximum(decayed, fear_stimulus(predator_distance, params))
