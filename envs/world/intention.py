"""The intention generator of world fish (the paper's Section 2, after Tu and Terzopoulos): one
intention per fish per step, by priority, with a focus on one target and persistence.

Priorities, highest first: ``AVOID`` a collision that is imminent; ``FLEE`` a perceived
predator while fear is high; ``EAT`` the nearest perceived food while hungry (a fish that eats
food) or ``HUNT`` the nearest perceived prey (a predator); ``MATE`` with the nearest perceived
partner while libido is high; ``SCHOOL`` with perceived kin (a schooling species); otherwise
``WANDER``.

Persistence: each drive has a start and a lower stop threshold (hysteresis: a fish that began
to eat eats on until its hunger is low), a motivated intention is held for at least
``hold`` s once chosen unless avoidance or flight pre-empts it, and its focus (the target's
index) stays on the same target while that is still perceived. Avoidance pre-empts without
forgetting: when the danger is past, the fish takes up what it was doing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .percepts import Percepts

AVOID, FLEE, EAT, HUNT, MATE, SCHOOL, WANDER = range(7)
NAMES = ("avoid", "flee", "eat", "hunt", "mate", "school", "wander")


@dataclass(frozen=True)
class IntentionParams:
    """(start, stop) thresholds of fear, hunger and libido (a species' ``appetite``, when
    given to :meth:`IntentionGenerator.decide`, is its hunger's start); hold: s a motivated
    intention is kept once chosen."""

    fear: tuple[float, float] = (0.5, 0.2)
    hunger: tuple[float, float] = (0.4, 0.05)
    libido: tuple[float, float] = (0.5, 0.1)
    hold: float = 1.0

    def __post_init__(self) -> None:
        for name in ("fear", "hunger", "libido"):
            start, stop = getattr(self, name)
            if not 0.0 <= stop <= start <= 1.0:
                raise ValueError(f"intention: {name} needs 0 <= stop <= start <= 1, got "
                                 f"{(start, stop)!r}")


class IntentionGenerator:
    """Intentions of F fish: ``intention`` (F,) (the codes above), ``focus`` (F,) the target
    index of EAT, HUNT, MATE (food or fish index; -1 none), ``since`` (F,) s when it was
    chosen."""

    def __init__(self, count: int, params: IntentionParams = IntentionParams()) -> None:
        self.params = params
        self.intention = np.full(count, WANDER)
        self.focus = np.full(count, -1)
        self.since = np.zeros(count)
        self._resume = np.full(count, WANDER)  # the intention an avoidance interrupted

    def reset(self, rows: np.ndarray | None = None) -> None:
        """Forget the intentions of ``rows`` (default: every fish)."""
        rows = slice(None) if rows is None else rows
        self.intention[rows], self.focus[rows], self.since[rows] = WANDER, -1, 0.0
        self._resume[rows] = WANDER

    @property
    def resumed(self) -> np.ndarray:
        """(F,) the intention each fish is on, or will take up again after an avoidance."""
        return np.where(self.intention == AVOID, self._resume, self.intention)

    def _drives(self, p: Percepts, mind, eats_food, predator, schooling, mates, appetite=None):
        """(F, 7) bool: which intentions are wanted, a drive already on (or interrupted by an
        avoidance) using its stop threshold."""
        on = self.resumed
        q = self.params
        start = appetite if appetite is not None else q.hunger[0]
        hungry = mind.hunger > np.where((on == EAT) | (on == HUNT), q.hunger[1], start)
        afraid = mind.fear > np.where(on == FLEE, q.fear[1], q.fear[0])
        keen = mind.libido > np.where(on == MATE, q.libido[1], q.libido[0])
        return np.stack([p.danger, afraid & (p.predator >= 0),
                         hungry & eats_food & (p.food >= 0),
                         hungry & predator & (p.prey >= 0),
                         keen & mates & (p.mate >= 0),
                         schooling & (p.school_count > 0),
                         np.ones_like(p.danger)], axis=1)

    def decide(self, p: Percepts, mind, habits_arrays: dict, time: float) -> np.ndarray:
        """(F,) this step's intentions from the percepts, the mental state and the habits
        (``habits_arrays``: (F,) bool ``eats_food``, ``predator``, ``schooling``, ``mates``,
        optionally (F,) float ``appetite``)."""
        h = habits_arrays
        wanted = self._drives(p, mind, h["eats_food"], h["predator"], h["schooling"],
                              h["mates"], h.get("appetite"))
        best = np.argmax(wanted, axis=1)  # the first wanted in priority order
        current = self.resumed
        rows = np.arange(len(best))
        holding = ((time - self.since < self.params.hold) & (current >= EAT)
                   & (current < WANDER) & wanted[rows, current] & (best > FLEE))
        chosen = np.where(holding, current, best)
        started = chosen != current
        self._resume = np.where(chosen == AVOID, current, chosen)
        self.since = np.where(started & (chosen != AVOID), time, self.since)
        targets = {EAT: (p.food, p.food_seen), HUNT: (p.prey, p.fish_seen),
                   MATE: (p.mate, p.fish_seen)}
        focus = np.full(len(chosen), -1)
        for code, (nearest_one, seen) in targets.items():
            if seen.shape[1] == 0:  # nothing of the kind in the world
                continue
            index = np.clip(self.focus, 0, seen.shape[1] - 1)
            kept = (self.focus >= 0) & (current == code) & ~started & seen[rows, index]
            focus = np.where(chosen == code, np.where(kept, self.focus, nearest_one), focus)
        self.focus = np.where(chosen == AVOID, self.focus, focus)  # avoiding keeps its focus
        self.intention = chosen
        return chosen
