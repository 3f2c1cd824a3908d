"""Coordinate search over discrete genes, as an ask/tell optimiser with explicit params and state
(the interface of :mod:`animat.learners.optimizers.annealing`): ``init`` -> (``ask`` ->
evaluate -> ``tell``)*.

Each gene in [0, 1] is read as one of ``levels`` codes (``floor(x * levels)``, a cell of the
switching learner's table of moves). A round takes one gene and proposes every other code for
it (or ``candidates`` of them, drawn at random, when the budget affords fewer), the rest of the
incumbent unchanged; ``tell`` keeps the best proposal if its energy is lower than the
incumbent's. A sweep visits every gene once, in an order drawn afresh each sweep; a sweep that
changes nothing is a local optimum (no single gene can improve it) and ends the search
(``finished``), where the budget would otherwise re-score the same proposals. The first round
scores the starting point alone.

The energies must be deterministic for this to be a descent: every candidate is scored on the
same seeded start states (:class:`~animat.learners.rollout.BatchEvaluator`). A proposal whose
energy is not finite (a body that diverged) is never kept.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .energies import worst_if_diverged


@dataclass(frozen=True)
class CoordinateParams:
    """Attributes:
    levels: codes per gene (the learner sets it: e.g. the moves of a table).
    candidates: proposals per round (0: every other code, ``levels - 1``); fewer are drawn at
        random from them.
    """

    levels: int = 2
    candidates: int = 0

    def __post_init__(self) -> None:
        if self.levels < 2:
            raise ValueError(f"CoordinateParams: levels must be >= 2, got {self.levels}")
        if self.candidates < 0:
            raise ValueError(f"CoordinateParams: candidates must be >= 0, got {self.candidates}")


@dataclass(frozen=True)
class CoordinateState:
    """x (D,) the incumbent; energy its E (inf before the first tell); order (D,) the
    sweep's gene order; cursor: genes of the sweep told; sweep: sweeps begun; improved: whether
    this sweep has changed a gene; converged: a whole sweep changed none; round: rounds told;
    rng: the generator's state."""

    x: np.ndarray
    energy: float
    order: np.ndarray
    cursor: int
    sweep: int
    improved: bool
    converged: bool
    round: int
    rng: dict


MIN_POPULATION = 1


def population(params: CoordinateParams) -> int:
    """Proposals per round: every other code of one gene, or ``candidates`` of them."""
    every = params.levels - 1
    return min(params.candidates, every) if params.candidates else every


def with_population(params: CoordinateParams, size: int) -> CoordinateParams:
    """The same search with at most ``size`` proposals a round (a smaller budget's)."""
    return replace(params, candidates=int(min(size, params.levels - 1)))


def with_budget(params: CoordinateParams, state: CoordinateState, rounds: int
                ) -> CoordinateParams:
    """The search has no schedule: it runs until the budget ends or a sweep changes nothing."""
    return params


def same_schedule(params: CoordinateParams, learned: CoordinateParams) -> CoordinateParams:
    return params


def state_bytes(params: CoordinateParams, dims: int) -> int:
    """Memory a round takes over ``dims`` genes, about: the proposals, float64."""
    return 8 * (population(params) + 2) * int(dims)


def metrics(params: CoordinateParams, state: CoordinateState) -> dict[str, float]:
    """``train/*`` scalars: the sweep under way and the incumbent's energy."""
    return {"sweep": float(state.sweep), "incumbent_energy": float(state.energy)}


def fit_encoding(options: dict, block: int) -> dict:
    return options


def refine_options(options: dict) -> dict:
    return options


def with_levels(options: dict, levels: int, owner: str, what: str) -> dict:
    """``options`` with ``levels`` set to the encoding's own codes (``what`` they are, e.g. a
    table's moves); a ValueError naming ``owner`` if a config gave them."""
    if "levels" in options:
        raise ValueError(f"{owner}: levels is {what} ({levels}), not a parameter")
    return {**options, "levels": levels}


def code_of(x: np.ndarray, levels: int) -> np.ndarray:
    """The codes (D,) of genes ``x`` in [0, 1]: ``floor(x * levels)``, 1 read as the last."""
    return np.minimum((np.asarray(x) * levels).astype(int), levels - 1)


def init(params: CoordinateParams, x0: np.ndarray, seed: int) -> CoordinateState:
    """Start at ``x0`` (D,) snapped to its codes' centres."""
    x0 = (code_of(x0, params.levels) + 0.5) / params.levels
    rng = np.random.Generator(np.random.PCG64(seed))
    order = rng.permutation(len(x0))
    return CoordinateState(x=x0, energy=np.inf, order=order, cursor=0, sweep=1, improved=False,
                           converged=False, round=0, rng=rng.bit_generator.state)


def finished(params: CoordinateParams, state: CoordinateState) -> bool:
    """A whole sweep changed no gene: no single gene can improve the incumbent."""
    return state.converged


def ask(params: CoordinateParams, state: CoordinateState
        ) -> tuple[np.ndarray, CoordinateState]:
    """Proposals (N, D): the incumbent alone first (to learn its energy), then the next gene of
    the sweep set to each other code."""
    if not np.isfinite(state.energy):
        return state.x[None].copy(), state
    rng = np.random.Generator(np.random.PCG64())
    rng.bit_generator.state = state.rng
    gene = int(state.order[state.cursor])
    others = np.delete(np.arange(params.levels), code_of(state.x[gene], params.levels))
    if population(params) < len(others):
        others = np.sort(rng.choice(others, population(params), replace=False))
    proposals = np.repeat(state.x[None], len(others), axis=0)
    proposals[:, gene] = (others + 0.5) / params.levels
    return proposals, replace(state, rng=rng.bit_generator.state)


def tell(params: CoordinateParams, state: CoordinateState, proposals: np.ndarray,
         energies: np.ndarray) -> CoordinateState:
    """Keep the best proposal if it beats the incumbent; after the sweep's last gene, begin
    another in a new order (or stop: :func:`finished`)."""
    energies = worst_if_diverged(energies)
    if not np.isfinite(state.energy):  # the starting point's score
        if not np.isfinite(energies[0]):
            raise ValueError("the starting point's energy is not finite")
        return replace(state, energy=float(energies[0]))
    best = int(np.argmin(energies))
    better = energies[best] < state.energy
    x = proposals[best].copy() if better else state.x
    energy = float(energies[best]) if better else state.energy
    improved, cursor = state.improved or bool(better), state.cursor + 1
    told = replace(state, x=x, energy=energy, cursor=cursor, improved=improved,
                   round=state.round + 1)
    if cursor < len(state.order):
        return told
    if not improved:
        return replace(told, converged=True)
    rng = np.random.Generator(np.random.PCG64())
    rng.bit_generator.state = state.rng
    order = rng.permutation(len(state.order))
    return replace(told, order=order, cursor=0, sweep=state.sweep + 1, improved=False,
                   rng=rng.bit_generator.state)
