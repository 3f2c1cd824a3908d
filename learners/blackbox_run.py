"""A black-box learner's run: the refinement phase's settings (:func:`refine_settings`), its
progress (:class:`Run`, its :class:`Phase` s, each keeping its best candidate), what a round
logs (:func:`log_round`), and its checkpoint: where it goes, what is saved there
(:func:`saved_run`) and how it is written (:func:`save_run`): data
(:mod:`animat.learners.storage.checkpoint_data`), or a pickle for a trusted run of an older
version."""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from .controllers.abstraction import AbstractController
from .logger import Logger
from .optimizers import Optimizer, annealing, cmaes, coordinate
from .storage import checkpoint_data, migration
from .storage.pickles import UntrustedPickle, load_checkpoint, save_checkpoint
from .validation import check_finite, unknown_params

REFINE_KEYS = {"share", "threshold", "max_parameters"}


def refine_settings(refine: dict | None, learner: str, optimizer: Optimizer,
                    opt_params: Any) -> dict | None:
    """The refinement phase's settings of learner ``learner`` (its optimiser module and
    params ``opt_params``) from ``refine``: {``share`` (the fraction of the run's budget it
    gets, in (0, 1)), ``threshold`` (the FFT threshold of the abstraction refined, default
    0.5), ``max_parameters`` (an integer: keep only the largest harmonics whose parameters,
    with the means, fit in it; default none), and optimiser parameters that differ in the
    frequency space (e.g. ``step_size``)}; smoothing is off there."""
    if refine is None:
        return None
    if not isinstance(refine, dict):
        raise ValueError(f"learner {learner!r}: refine must be a mapping, got {refine!r}")
    if "env_steps" in refine:
        raise ValueError(f"learner {learner!r}: refine.env_steps is gone: give "
                         "refine.share, the fraction of budget.env_steps it gets (e.g. 0.25)")
    option_names = {f.name for f in fields(opt_params)}
    unknown_params(refine, REFINE_KEYS | option_names, f"{learner}.refine")
    for name, value in refine.items():
        check_finite(f"refine.{name}", value, f"learner {learner!r}")
    share: Any = refine.get("share")  # checked here, whatever the config held
    threshold: Any = refine.get("threshold", 0.5)
    if not (type(share) in (float, int) and 0.0 < share < 1.0
            and type(threshold) in (float, int) and 0.0 <= threshold < 1.0):
        raise ValueError(f"learner {learner!r}: refine needs share in (0, 1) and "
                         f"threshold in [0, 1); got {share!r}, {threshold!r}")
    most = refine.get("max_parameters")
    if most is not None and not (type(most) is int and 1 <= most <= 100_000):
        raise ValueError(f"learner {learner!r}: refine.max_parameters must be an integer in "
                         f"[1, 100000], got {most!r}")
    options = optimizer.refine_options({k: v for k, v in refine.items() if k not in REFINE_KEYS})
    params = replace(opt_params, **options)
    # the population stays: one batch width for both phases, every row a candidate
    population = int(optimizer.population(opt_params))
    if optimizer.population(params) != population:
        raise ValueError(f"learner {learner!r}: refine cannot change the population "
                         f"({population})")
    return {"share": float(share), "threshold": threshold, "max_parameters": most,
            "params": params}


def round_best(returns: np.ndarray) -> int | None:
    """The index of the round's highest finite return (None when every candidate's body
    diverged)."""
    finite = np.isfinite(returns)
    return int(np.argmax(np.where(finite, returns, -np.inf))) if finite.any() else None


@dataclass
class Phase:
    """One optimisation: its optimiser params and state, the best candidate so far
    ({``x``, ``return``, ``metrics``}), the abstraction whose frequency parameters it searches
    (refining; None for the nodal search) and, refining, the metrics it started from."""

    params: Any
    state: Any
    best: dict | None = None
    support: Any = None
    start: dict | None = None

    def track(self, candidates, returns: np.ndarray, metrics: dict) -> None:
        """The one place the best candidate is kept: its vector, return and metrics."""
        k = round_best(returns)
        if k is None:
            return
        if self.best is None or returns[k] > self.best["return"]:
            self.best = {"x": np.array(candidates[k]), "return": float(returns[k]),
                         "metrics": {name: float(v[k]) for name, v in metrics.items()}}


@dataclass
class Run:
    """A learner's progress (what a checkpoint holds): its phases and the counters."""

    phases: list[Phase] = field(default_factory=list)
    env_steps: int = 0
    wall: float = 0.0
    rounds: int = 0

    @classmethod
    def from_checkpoint(cls, saved) -> Run:
        """A saved run; checkpoints from before these dataclasses were dicts
        (:func:`~animat.learners.storage.migration.run_fields`)."""
        if isinstance(saved, Run):
            return saved
        fields = migration.run_fields(saved)
        return cls([Phase(**phase) for phase in fields["phases"]], fields["env_steps"],
                   fields["wall"], fields["rounds"])

    def overall_best(self) -> dict | None:
        """The best candidate of either phase (None before the first round)."""
        bests = [p.best for p in self.phases if p.best is not None]
        return max(bests, key=lambda b: b["return"]) if bests else None


# the classes a black-box checkpoint may hold (checkpoint_data builds no other)
CHECKPOINT_TYPES: dict[str, type] = {cls.__name__: cls for cls in (
    Run, Phase, AbstractController, annealing.AnnealingParams, annealing.AnnealingState,
    cmaes.CMAESParams, cmaes.CMAESState, coordinate.CoordinateParams, coordinate.CoordinateState)}


def log_round(logger: Logger, run: Run, returns: np.ndarray, metrics: dict,
              train: dict[str, float]) -> None:
    """Like every learner, ``eval/*``: the current incumbent (the best candidate of this
    round, scored over the evaluation start states), as PPO logs its current policy;
    ``best/*``: the best so far (of either phase), which is what the run returns; and the
    optimiser's own ``train/*`` scalars (``train``), with ``train/diverged``, the round's
    candidates whose return is not finite (a body that blew up: never the incumbent, and the
    optimisers never keep them); and ``time/fps``, the run's env steps per wall second so far
    (SB3's tag for PPO's)."""
    k, best, step = round_best(returns), run.overall_best(), run.env_steps
    if k is not None:
        logger.scalar("eval/return", float(returns[k]), step)
        for name, values in metrics.items():
            logger.scalar(f"eval/{name}", float(values[k]), step)
    if best is not None:
        logger.scalar("best/return", best["return"], step)
        for name, value in best["metrics"].items():
            logger.scalar(f"best/{name}", value, step)
    logger.scalar("train/diverged", float((~np.isfinite(returns)).sum()), step)
    for name, value in train.items():
        logger.scalar(f"train/{name}", value, step)
    if run.wall > 0.0:
        logger.scalar("time/fps", run.env_steps / run.wall, step)


def saved_run(checkpoint_dir: str | Path | None, trust_pickles: bool
              ) -> tuple[Path | None, object]:
    """Where the run's checkpoint goes, and what is saved there (None: nothing yet).
    ``checkpoint.json`` is data (:mod:`animat.learners.storage.checkpoint_data`); an older
    version's ``checkpoint.pkl`` is read (and the run goes on pickling) only when the
    caller trusts the folder (``trust_pickles``): unpickling runs whatever its writer put in
    it."""
    if not checkpoint_dir:
        return None, None
    folder = Path(checkpoint_dir)
    legacy, path = folder / "checkpoint.pkl", folder / "checkpoint.json"
    if path.exists() or not legacy.exists():
        return path, checkpoint_data.load(path, CHECKPOINT_TYPES)
    if not trust_pickles:
        raise UntrustedPickle(legacy)
    return legacy, load_checkpoint(legacy)


def save_run(path: Path, run: Run) -> None:
    """Write ``run`` to the checkpoint ``path`` :func:`saved_run` chose."""
    if path.suffix == ".pkl":  # a trusted older run goes on as it was saved
        save_checkpoint(path, run)
    else:
        checkpoint_data.save(path, run)
