"""The one learner interface: every learner is run the same way, with an env id (and its
kwargs), a budget in env steps, a seed and a logger, and can be checkpointed and resumed.

Tags every learner logs, with the global step = env steps consumed: ``eval/return`` and the
task's summary metrics as ``eval/<name>`` (:class:`animat.envs.tasks.base.EpisodeSummary`); anything
else under ``train/``. Hyperparameters go in as text (``hparams``). What a learner checks before
it runs is :mod:`animat.learners.validation`; its files, :mod:`animat.learners.storage`.
"""

from __future__ import annotations

import json
import time
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

from animat.envs.registration import Timing, timing

from .logger import Logger
from .rollout import START_STATES, score_episode, spread
from .validation import check_scoring_budget


@dataclass
class LearnResult:
    """What a run produced: env steps consumed, wall seconds, final metrics (``eval/...``),
    and artefacts (e.g. the best controller as a dict)."""

    env_steps: int
    wall_seconds: float
    metrics: dict[str, float]
    artefacts: dict[str, Any] = field(default_factory=dict)


def episode_timing(env_id: str, env_kwargs: dict | None = None) -> Timing:
    """(dt s, env steps per episode) of the env, from its id and kwargs without building it
    (:func:`animat.envs.registration.timing`; a bad kwarg is the env's own error)."""
    return timing(env_id, env_kwargs)


def episode_steps(env_id: str, env_kwargs: dict | None = None) -> int:
    """Env steps in one episode of the env (its ``episode_steps``), without building it."""
    return timing(env_id, env_kwargs).episode_steps


class Learner(ABC):
    """Base class. Subclasses set ``name`` and implement :meth:`learn`.

    Args:
        env_id: a registered env id, e.g. ``Animat/FishSwim-v0``.
        env_kwargs: keyword arguments for the env.
        params: the learner's own parameters (validated by the subclass).
        seed: the run's seed; everything random derives from it.
        logger: where scalars go.

    ``path_params`` names the params that are file paths (:func:`animat.experiments.launch.config.
    load_config` resolves them against the config file's folder).
    """

    name: ClassVar[str] = "learner"
    # params that name files: a config's relative paths there are relative to its own folder
    path_params: ClassVar[tuple[str, ...]] = ()
    # whether a run folder's pickled checkpoint of an older version may be loaded (its writer's
    # code would run): set by the caller (animat eval/run --trust-pickles), never by a config
    trust_pickles: bool = False

    def __init__(self, env_id: str, env_kwargs: dict | None = None, params: dict | None = None,
                 seed: int = 0, logger: Logger | None = None) -> None:
        self.env_id = env_id
        self.env_kwargs = dict(env_kwargs or {})
        self.params = dict(params or {})
        self.seed = int(seed)
        self.logger = logger or Logger()

    @abstractmethod
    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        """Learn with at most ``budget_env_steps`` env steps. With ``checkpoint_dir``, save
        checkpoints there as it goes and resume from the last one if present."""

    def check_budget(self, budget_env_steps: int) -> None:
        """Raise :class:`~animat.learners.validation.BudgetError` if the learner cannot work
        with this budget (checked before any work or file; the default takes any)."""
        return None

    def scored_episodes(self) -> int:
        """How many seeded start states (seeds ``seed`` onward) the run's own scores are
        over."""
        return START_STATES

    def agent(self, artefacts: dict, folder: Path):
        """What the finished run in ``folder`` (its ``artefacts.json`` given) acts with: an
        agent of :mod:`animat.learners.agents`, built from this learner's config."""
        raise NotImplementedError(f"learner {self.name!r} cannot make an agent of its runs")

    def log_hparams(self) -> None:
        self.logger.text("hparams", json.dumps({"learner": self.name, "env_id": self.env_id,
                                                "env_kwargs": self.env_kwargs,
                                                "params": self.params, "seed": self.seed},
                                               indent=1, default=str))


class Scorer(Learner):
    """A learner that only scores a fixed controller over seeded episodes (learns nothing):
    its budget must hold those episodes, :meth:`scored_episodes` of the env's length."""

    def check_budget(self, budget_env_steps: int) -> None:
        check_scoring_budget(budget_env_steps, self.scored_episodes(),
                             episode_steps(self.env_id, self.env_kwargs))

    def score_policy(self, env, policy, episodes: int) -> LearnResult:
        """What this scorer's run gives: ``policy`` played on ``episodes`` seeded episodes of
        ``env`` (seeds from the learner's on), its hyperparameters and the ``eval/`` figures
        logged at the env steps played, the episodes' own figures kept as artefacts."""
        start = time.perf_counter()
        steps = env.unwrapped.episode_steps * episodes
        self.log_hparams()
        runs = [score_episode(env, policy, self.seed + k) for k in range(episodes)]
        metrics = spread(runs)
        self.logger.scalars(metrics, steps)
        return LearnResult(env_steps=steps, wall_seconds=time.perf_counter() - start,
                           metrics=metrics, artefacts={"episodes": runs})
