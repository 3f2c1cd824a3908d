"""CMA-ES (pycma) behind the same ask/tell interface as :mod:`animat.learners.annealing` (and
the same ``population``/``metrics``/``fit_encoding``/``refine_options`` answers), over the same
controller parameters: the baseline that answers "was annealing a good choice?"."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class CMAESParams:
    """popsize: candidates per generation; sigma0: initial step (parameter units); lower,
    upper: box bounds (pycma's bound handling); tolfun: stop when the spread of E is below it."""

    popsize: int = 64
    sigma0: float = 0.25
    lower: float = 0.0
    upper: float = 1.0
    tolfun: float = 1e-8

    def __post_init__(self) -> None:
        if self.popsize < 2 or self.sigma0 <= 0 or self.lower >= self.upper:
            raise ValueError("CMAESParams: need popsize >= 2, sigma0 > 0, lower < upper")


@dataclass
class CMAESState:
    """The pycma strategy object (it holds its own generator; it pickles for checkpoints)."""

    es: object


MIN_POPULATION = 2


def with_population(params: CMAESParams, size: int) -> CMAESParams:
    """The same settings with ``size`` candidates per round (a smaller budget's)."""
    return replace(params, popsize=int(size))


def population(params: CMAESParams) -> int:
    return params.popsize


def metrics(params: CMAESParams, state: CMAESState) -> dict[str, float]:
    """``train/*`` scalars: the overall step size sigma."""
    return {"sigma": float(state.es.sigma)}


def fit_encoding(options: dict, block: int) -> dict:
    return options


def refine_options(options: dict) -> dict:
    return options


def _cma():
    with warnings.catch_warnings():  # pycma warns that matplotlib (plotting) is absent
        warnings.simplefilter("ignore")
        import cma
    return cma


def init(params: CMAESParams, x0: np.ndarray, seed: int) -> CMAESState:
    cma = _cma()
    options = {"popsize": params.popsize, "seed": int(seed) + 1, "verbose": -9,
               "bounds": [params.lower, params.upper], "tolfun": params.tolfun}
    return CMAESState(cma.CMAEvolutionStrategy(np.asarray(x0, dtype=float), params.sigma0,
                                               options))


def finished(params: CMAESParams, state: CMAESState) -> bool:
    return bool(state.es.stop())


def ask(params: CMAESParams, state: CMAESState) -> tuple[np.ndarray, CMAESState]:
    return np.asarray(state.es.ask()), state


def tell(params: CMAESParams, state: CMAESState, candidates: np.ndarray,
         energies: np.ndarray) -> CMAESState:
    state.es.tell(list(candidates), list(np.asarray(energies, dtype=float)))
    return state
