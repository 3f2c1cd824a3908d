"""Simulated annealing (the paper's optimiser) as an ask/tell optimiser with explicit params
and state (after evosax): ``init`` -> (``ask`` -> evaluate -> ``tell``)* .

C chains run in parallel (one proposal each per round, evaluated together on the native batch). A
proposal perturbs a random subset of a chain's parameters with Gaussian steps whose size shrinks
with the temperature, and is accepted with the Metropolis rule ``min(1, exp(-(E_new - E) / T))``.
The temperature falls geometrically. With ``schedule`` "budget" (the default) it falls every round,
``T_k = T0 (T_min / T0)^(k / (R - 1))`` after move round k, from ``initial_temperature`` for the
first move round to ``min_temperature`` for the last, R, that the run's budget affords
(:func:`with_budget`, which the shared loop calls each time it runs a phase: a second phase, the
refinement, anneals again from ``initial_temperature`` over its own share; a run resumed with a
larger budget re-plans R, the temperature rising to the longer schedule's and cooling to
``min_temperature`` again at its end), so that the search ends cold whatever the budget; with
"stages" it falls by ``cooling`` after every ``moves_per_temperature`` rounds and stops at
``min_temperature`` or when the caller's budget runs out. The state holds the generator's state, so
a run is reproducible bit for bit and can be checkpointed and resumed anywhere.

Besides ``init``/``ask``/``tell``/``finished``, the module answers what the shared loop
(:mod:`animat.learners.blackbox`) asks of every optimiser: ``population`` (candidates per round),
``with_budget`` (the schedule for the rounds a phase can afford), ``metrics`` (its ``train/*``
scalars), ``fit_encoding`` (options for an encoding of blocks of ``block`` parameters) and
``refine_options`` (options for searching frequency parameters). The caller keeps the best
candidate (with its metrics); the optimiser does not.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from math import inf

import numpy as np

from ..storage.migration import fields_written_before
from .energies import worst_if_diverged

SCHEDULES = ("budget", "stages")


@dataclass(frozen=True)
class AnnealingParams:
    """Schedule and moves.

    Attributes:
        schedule: "budget" (the default): the temperature follows the rounds the budget
            affords (``rounds``, :func:`with_budget`), cooling and moves_per_temperature unused;
            "stages": the fixed schedule they give.
        rounds: the move rounds of a budget's schedule (the learner plans it from the run's
            budget: :func:`with_budget`; 0, not yet planned, holds the temperature).
        chains: parallel chains (proposals per round).
        initial_temperature: T0, in units of E.
        cooling: T <- cooling * T after each temperature stage (0 < cooling < 1).
        moves_per_temperature: rounds per temperature stage.
        min_temperature: stopping rule: stop once T falls below it.
        step_size: Gaussian step (parameter units) at T0; it scales with sqrt(T / T0), floored
            at ``min_step_size``.
        min_step_size: the smallest step.
        mutation_rate: probability that a parameter is perturbed in a proposal (at least one).
        lower, upper: parameter bounds (proposals are clipped).
        smoothing: if > 0, each perturbation is a smooth bump rather than a spike: the steps
            of each run of ``block`` consecutive parameters (one actuator's nodal values) are
            convolved, circularly, with a Gaussian of this width (in nodes, peak 1).
        block: the run length for ``smoothing`` (0: the whole vector).
    """

    schedule: str = "budget"
    rounds: int = 0
    chains: int = 64
    initial_temperature: float = 0.1
    cooling: float = 0.95
    moves_per_temperature: int = 4
    min_temperature: float = 1e-4
    step_size: float = 0.3
    min_step_size: float = 0.02
    mutation_rate: float = 0.2
    lower: float = 0.0
    upper: float = 1.0
    smoothing: float = 0.0
    block: int = 0

    def __post_init__(self) -> None:
        checks = [(self.schedule in SCHEDULES, f"schedule must be one of {SCHEDULES}, got "
                   f"{self.schedule!r}"),
                  (self.schedule != "budget" or self.min_temperature < self.initial_temperature,
                   f"the budget's schedule cools to min_temperature ({self.min_temperature:g}): "
                   f"it must be below initial_temperature ({self.initial_temperature:g})"),
                  (self.rounds >= 0, "rounds must be >= 0"),
                  (self.chains >= 1, "chains must be >= 1"),
                  (0 < self.initial_temperature < inf, "initial_temperature must be finite, > 0"),
                  (0 < self.cooling < 1, "cooling must be in (0, 1)"),
                  (self.moves_per_temperature >= 1, "moves_per_temperature must be >= 1"),
                  (0 < self.min_temperature < inf, "min_temperature must be finite, > 0"),
                  (0 < self.step_size < inf and 0 < self.min_step_size < inf,
                   "step sizes must be finite, > 0"),
                  (0 < self.mutation_rate <= 1, "mutation_rate must be in (0, 1]"),
                  (-inf < self.lower < self.upper < inf, "lower must be < upper, both finite"),
                  (0 <= self.smoothing < inf and self.block >= 0,
                   "smoothing (finite) and block must be >= 0")]
        for ok, message in checks:
            if not ok:
                raise ValueError(f"AnnealingParams: {message}")

    def __setstate__(self, state: dict) -> None:
        """Unpickled from an older version's checkpoint, params written before schedules
        existed keep the schedule their run had
        (:data:`animat.learners.storage.migration.BEFORE_FIELDS`: stages)."""
        for name, value in fields_written_before(type(self).__name__, state).items():
            object.__setattr__(self, name, value)


@dataclass(frozen=True)
class AnnealingState:
    """x (C, D) chain positions; energy (C,) their E (inf before the first tell);
    temperature; round (proposal rounds told); rng: the generator's state."""

    x: np.ndarray
    energy: np.ndarray
    temperature: float
    round: int
    rng: dict


MIN_POPULATION = 1


def with_population(params: AnnealingParams, size: int) -> AnnealingParams:
    """The same settings with ``size`` candidates per round (a smaller budget's)."""
    return replace(params, chains=int(size))


def with_budget(params: AnnealingParams, state: AnnealingState, rounds: int
                ) -> AnnealingParams:
    """The schedule for a phase that can afford ``rounds`` more rounds from ``state``: with
    ``schedule`` "budget", its last move round (``params.rounds``) is the last of them (the
    round that scores the starting points, if still to come, moves nothing); "stages" is kept
    as given. The same budget gives the same plan at any point of the run, so a killed run
    resumed goes on bit for bit."""
    if params.schedule != "budget":
        return params
    scoring = 0 if np.all(np.isfinite(state.energy)) else 1
    return replace(params, rounds=max(int(state.round + rounds - scoring), 1))


def same_schedule(params: AnnealingParams, learned: AnnealingParams) -> AnnealingParams:
    """``params`` (a refinement's) with the schedule of the phase it follows (``learned``:
    a run resumed from a checkpoint written before schedules keeps stages in both)."""
    return replace(params, schedule=learned.schedule)


def budget_temperature(params: AnnealingParams, round_: int) -> float:
    """The temperature move round ``round_ + 1`` runs at in a budget's schedule of R rounds:
    ``T0 (T_min / T0)^(k / (R - 1))`` after k move rounds, so that the first runs at T0 and
    the last at ``min_temperature`` (T0 throughout a schedule of one round, or before it is
    planned)."""
    if params.rounds <= 1:
        return params.initial_temperature
    share = min(round_, params.rounds - 1) / (params.rounds - 1)
    return params.initial_temperature * (params.min_temperature
                                         / params.initial_temperature) ** share


def current_temperature(params: AnnealingParams, state: AnnealingState) -> float:
    """The temperature the next round runs at: the budget's schedule's for the round it is at
    (so that a re-planned schedule takes hold at once), or the stages' held in ``state``."""
    if params.schedule == "budget":
        return budget_temperature(params, state.round)
    return state.temperature


def population(params: AnnealingParams) -> int:
    """Candidates per round: one proposal per chain."""
    return params.chains


def state_bytes(params: AnnealingParams, dims: int) -> int:
    """Memory a round takes over ``dims`` parameters, about: the chains, and the proposal's
    random numbers, mask, steps and proposals, each (C, D) float64."""
    return 6 * 8 * params.chains * int(dims)


def metrics(params: AnnealingParams, state: AnnealingState) -> dict[str, float]:
    """``train/*`` scalars: the temperature the next round runs at."""
    return {"temperature": float(current_temperature(params, state))}


def fit_encoding(options: dict, block: int) -> dict:
    """Smoothing acts along each actuator's ``block`` nodal values unless told otherwise."""
    if options.get("smoothing") and "block" not in options:
        return {**options, "block": block}
    return options


def refine_options(options: dict) -> dict:
    """Frequency parameters are not a nodal sequence: no smoothing there (unless asked)."""
    return {"smoothing": 0.0, "block": 0, **options}


def init(params: AnnealingParams, x0: np.ndarray, seed: int) -> AnnealingState:
    """Start every chain at ``x0`` (D,) or at its own row of ``x0`` (C, D)."""
    x0 = np.asarray(x0, dtype=float)
    x = np.broadcast_to(x0, (params.chains, x0.shape[-1])).copy()
    rng = np.random.Generator(np.random.PCG64(seed))
    return AnnealingState(x=x, energy=np.full(params.chains, np.inf),
                          temperature=params.initial_temperature, round=0,
                          rng=rng.bit_generator.state)


def finished(params: AnnealingParams, state: AnnealingState) -> bool:
    """The stopping rule: the temperature has fallen below ``min_temperature`` (stages), or
    the budget's schedule has run its rounds."""
    if params.schedule == "budget":
        return 0 < params.rounds <= state.round
    return state.temperature < params.min_temperature


def ask(params: AnnealingParams, state: AnnealingState) -> tuple[np.ndarray, AnnealingState]:
    """Proposals (C, D): the chains themselves first (to learn their energies), then moves."""
    if not np.all(np.isfinite(state.energy)):
        return state.x.copy(), state
    rng = np.random.Generator(np.random.PCG64())
    rng.bit_generator.state = state.rng
    scale = max(params.min_step_size, params.step_size * np.sqrt(
        current_temperature(params, state) / params.initial_temperature))
    chains, dims = state.x.shape
    mask = rng.random((chains, dims)) < params.mutation_rate
    mask[np.arange(chains), rng.integers(0, dims, chains)] = True
    steps = rng.normal(0.0, scale, (chains, dims)) * mask
    if params.smoothing > 0:
        steps = smooth_blocks(steps, params.smoothing, params.block or dims)
    proposals = np.clip(state.x + steps, params.lower, params.upper)
    return proposals, replace(state, rng=rng.bit_generator.state)


def smooth_blocks(steps: np.ndarray, width: float, block: int) -> np.ndarray:
    """Circular convolution of each run of ``block`` values (C, D) with exp(-d^2 / 2 w^2)."""
    chains, dims = steps.shape
    if dims % block:
        raise ValueError(f"block {block} does not divide the {dims} parameters")
    distance = np.minimum(np.arange(block), block - np.arange(block))
    kernel = np.fft.rfft(np.exp(-0.5 * (distance / width) ** 2))
    runs = steps.reshape(chains, dims // block, block)
    return np.fft.irfft(np.fft.rfft(runs, axis=-1) * kernel, n=block, axis=-1).reshape(
        chains, dims)


def tell(params: AnnealingParams, state: AnnealingState, proposals: np.ndarray,
         energies: np.ndarray) -> AnnealingState:
    """Metropolis acceptance per chain and the cooling schedule. A move whose energy is not
    finite (a body that diverged) is rejected; the starting points' energies must be finite."""
    energies = np.asarray(energies, dtype=float)
    if not np.all(np.isfinite(state.energy)):  # first evaluation of the starting points
        if not np.all(np.isfinite(energies)):
            raise ValueError("the starting points' energies must be finite")
        x, energy = proposals.copy(), energies.copy()
        rng_state, told = state.rng, state.round
    else:
        rng = np.random.Generator(np.random.PCG64())
        rng.bit_generator.state = state.rng
        energies = worst_if_diverged(energies)
        delta = energies - state.energy
        accept = (delta <= 0) | (rng.random(len(delta)) < np.exp(
            -np.maximum(delta, 0) / current_temperature(params, state)))
        x = np.where(accept[:, None], proposals, state.x)
        energy = np.where(accept, energies, state.energy)
        rng_state, told = rng.bit_generator.state, state.round + 1
    temperature = state.temperature
    if params.schedule == "budget":
        temperature = budget_temperature(params, told)
    elif told > state.round and told % params.moves_per_temperature == 0:
        temperature *= params.cooling
    return AnnealingState(x=x, energy=energy, temperature=temperature, round=told,
                          rng=rng_state)
