"""The interface every optimiser module implements (:class:`Optimizer`)."""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np


class Optimizer(Protocol):
    """What the black-box loop calls of an optimiser module (``params``: its frozen params
    dataclass; ``state``: its state dataclass, all the optimiser keeps, checkpointed as data).

    * ``init(params, x0, seed) -> state``: a search from ``x0`` (D,).
    * ``ask(params, state) -> (candidates (P, D), state)``; ``tell(params, state,
      candidates, energies (P,)) -> state``: one round (energy E = -return, to lower).
    * ``finished(params, state)``: its own stopping rule (the budget is the loop's).
    * ``population(params)``, ``with_population(params, size)`` and :data:`MIN_POPULATION`:
      candidates per round, fitted to a small budget.
    * ``with_budget(params, state, rounds)``: the schedule for ``rounds`` more rounds (params
      unchanged where there is none); ``same_schedule(params, learned)``: a refinement's
      params keeping the schedule of the phase it follows.
    * ``state_bytes(params, dims)``: the state's memory, checked before a run;
      ``metrics(params, state)``: its ``train/`` scalars.
    * ``fit_encoding(options, block)``, ``refine_options(options)``: the options it takes for
      a tent encoding of ``block`` nodes, and in the frequency space of a refinement.
    """

    MIN_POPULATION: int

    def init(self, params: Any, x0: np.ndarray, seed: int) -> Any: ...

    def ask(self, params: Any, state: Any) -> tuple[np.ndarray, Any]: ...

    def tell(self, params: Any, state: Any, candidates: np.ndarray, energies: np.ndarray
             ) -> Any: ...

    def finished(self, params: Any, state: Any) -> bool: ...

    def population(self, params: Any) -> int: ...

    def with_population(self, params: Any, size: int) -> Any: ...

    def with_budget(self, params: Any, state: Any, rounds: int) -> Any: ...

    def same_schedule(self, params: Any, learned: Any) -> Any: ...

    def state_bytes(self, params: Any, dims: int) -> int: ...

    def metrics(self, params: Any, state: Any) -> dict[str, float]: ...

    def fit_encoding(self, options: dict, block: int) -> dict: ...

    def refine_options(self, options: dict) -> dict: ...
