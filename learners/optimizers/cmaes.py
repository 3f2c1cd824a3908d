"""CMA-ES (pycma) behind the same ask/tell interface as :mod:`animat.learners.optimizers.annealing`
(and
the same ``population``/``metrics``/``fit_encoding``/``refine_options`` answers), over the same
controller parameters: the baseline that answers "was annealing a good choice?"."""

from __future__ import annotations

import hashlib
import warnings
from dataclasses import dataclass, field, replace
from math import inf

import numpy as np

from .energies import worst_if_diverged


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
        if not (self.popsize >= 2 and 0 < self.sigma0 < inf and -inf < self.lower < self.upper
                < inf and -inf < self.tolfun < inf):
            raise ValueError("CMAESParams: need popsize >= 2, sigma0 > 0, lower < upper, each "
                             "finite, and a finite tolfun")


@dataclass
class CMAESState:
    """What pycma's strategy is made of: its start (``x0``, ``sigma0``, pycma's ``options``,
    the seed among them), the energies told so far, one (popsize,) array a round, and a digest
    of each round's candidates. The strategy object itself, ``es``, is not kept in a
    checkpoint: :func:`strategy` rebuilds it by replaying the rounds. pycma seeds and draws
    from NumPy's global generator, so the replay asks what the run asked only if nothing else
    drew from it meanwhile (nothing here does) and pycma is the same; each replayed round is
    checked against its digest, and a replay that differs is refused, not told to the wrong
    candidates."""

    x0: np.ndarray
    sigma0: float
    options: dict
    told: list = field(default_factory=list)
    asked: list = field(default_factory=list)
    es: object = field(default=None, compare=False, repr=False, metadata={"checkpoint": False})


MIN_POPULATION = 2


def with_population(params: CMAESParams, size: int) -> CMAESParams:
    """The same settings with ``size`` candidates per round (a smaller budget's)."""
    return replace(params, popsize=int(size))


def with_budget(params: CMAESParams, state, rounds: int) -> CMAESParams:
    """CMA-ES adapts its own step size: the budget's rounds change nothing."""
    return params


def same_schedule(params: CMAESParams, learned: CMAESParams) -> CMAESParams:
    """CMA-ES has no schedule to keep."""
    return params


def population(params: CMAESParams) -> int:
    return params.popsize


def state_bytes(params: CMAESParams, dims: int) -> int:
    """Memory pycma takes over ``dims`` parameters, about: its full covariance, its
    eigenvectors and their updates, four (D, D) float64, and a few copies of the population
    (lambda, D)."""
    dims = int(dims)
    return 8 * (4 * dims * dims + 4 * params.popsize * dims)


def metrics(params: CMAESParams, state: CMAESState) -> dict[str, float]:
    """``train/*`` scalars: the overall step size sigma."""
    return {"sigma": float(strategy(state).sigma)}


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
    options = {"popsize": params.popsize, "seed": int(seed) + 1, "verbose": -9,
               "bounds": [params.lower, params.upper], "tolfun": params.tolfun}
    state = CMAESState(np.asarray(x0, dtype=float).copy(), float(params.sigma0), options)
    strategy(state)
    return state


def strategy(state: CMAESState):
    """The pycma strategy of ``state``, rebuilt from its start and told energies when the
    state was read from a checkpoint (each round asked again, then told what it was told)."""
    if state.es is None:
        cma = _cma()
        es = cma.CMAEvolutionStrategy(np.asarray(state.x0, dtype=float), state.sigma0,
                                      dict(state.options))
        for k, energies in enumerate(state.told):
            candidates = np.asarray(es.ask())
            if k < len(state.asked) and _digest(candidates) != state.asked[k]:
                raise ValueError(f"CMA-ES round {k + 1} of the checkpoint does not replay: pycma "
                                 f"asked other candidates than the run did (another pycma, or "
                                 f"NumPy's global generator drawn from meanwhile)")
            es.tell(list(candidates), list(np.asarray(energies, dtype=float)))
        state.es = es
    return state.es


def finished(params: CMAESParams, state: CMAESState) -> bool:
    return bool(strategy(state).stop())


def ask(params: CMAESParams, state: CMAESState) -> tuple[np.ndarray, CMAESState]:
    return np.asarray(strategy(state).ask()), state


def tell(params: CMAESParams, state: CMAESState, candidates: np.ndarray,
         energies: np.ndarray) -> CMAESState:
    """Rank the round's candidates by energy; one whose energy is not finite (a body that
    diverged) ranks last."""
    energies = worst_if_diverged(energies)
    strategy(state).tell(list(candidates), list(energies))
    if hasattr(state, "told"):  # an older version's pickled state has only ``es``
        state.told.append(energies.copy())
        state.asked.append(_digest(np.asarray(candidates)))
    return state


def _digest(candidates: np.ndarray) -> str:
    """A short digest of a round's candidates (float64 bytes), to check a replay by."""
    return hashlib.sha256(np.ascontiguousarray(candidates, dtype=float).tobytes()).hexdigest()[:16]
