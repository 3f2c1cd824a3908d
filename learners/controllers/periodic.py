"""The black-box learners' encoding of a tent controller: its settings
(:class:`ControllerParams`), the controller of a parameter vector
(:func:`controller_from_vector`) and the player that repeats it every period
(:class:`PeriodicPlayer`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..rollout import START_STATES, check_worst_share
from .tent import TentController, play


@dataclass(frozen=True)
class ControllerParams:
    """The tent-controller encoding and the loop's own settings (the rest of a black-box
    learner's params go to its optimiser's params class).

    Attributes:
        nodes: nodal values per actuator.
        period: s, the controller's period (None: it spans the episode).
        init: starting values: ``"random"``, ``"relaxed"`` (0) or ``"half"`` (0.5).
        abstraction_threshold: the FFT threshold of the abstraction kept (None: the most
            compact one within 10% of the learned objective).
        checkpoint_every: rounds between checkpoints.
        refine: the refinement phase's settings (see
            :func:`animat.learners.blackbox_run.refine_settings`).
        start_states: seeded start states every candidate is scored over.
        worst_share: the share of them its objective averages, its worst first (1: all;
            :func:`~animat.learners.rollout.worst_mean`).
    """

    nodes: int = 20
    period: float | None = 1.0
    init: str = "random"
    abstraction_threshold: float | None = None
    checkpoint_every: int = 10
    refine: dict | None = None
    start_states: int = START_STATES
    worst_share: float = 1.0

    def __post_init__(self) -> None:
        check_worst_share(self.worst_share)
        if self.nodes < 2 or self.init not in ("random", "relaxed", "half"):
            raise ValueError("nodes must be >= 2 and init one of random, relaxed, half")
        if self.checkpoint_every < 1 or self.start_states < 1:
            raise ValueError("checkpoint_every and start_states must be >= 1")
        if self.period is not None and not 0 < self.period < math.inf:
            raise ValueError(f"period must be a finite number of seconds > 0 (or null: the "
                             f"episode), got {self.period!r}")


def controller_from_vector(vector: np.ndarray, nodes: int, period: float | None,
                           duration: float) -> TentController:
    """The tent controller of a parameter vector (A * nodes,), A actuators (the env's action
    size). Periodic: ``nodes`` free values per actuator on [0, period), closed by repeating
    the first."""
    values = np.asarray(vector, dtype=float).reshape(-1, nodes)
    if period is None:
        return TentController(values, 0.0, duration)
    return TentController(np.concatenate([values, values[:, :1]], axis=1), 0.0, period)


class PeriodicPlayer:
    """Plays a (periodic) controller: u(t mod period)."""

    def __init__(self, controller, period: float | None) -> None:
        self.controller, self.period = controller, period

    def __call__(self, t: np.ndarray | float) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.controller(np.mod(t, self.period) if self.period else t)

    def actions(self, dt: float, steps: int) -> np.ndarray:
        return play(self, dt, steps)
