"""What SB3 is handed while a PPO run learns: a logger whose records go into the run's own
(:func:`sb3_logger`) and the callback that evaluates and checkpoints as the run goes
(:func:`progress_callback`).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from ..logger import Logger
from .threads import set_threads, update_threads


class LearningRun(Protocol):
    """What the callback reads of the learner it serves
    (:class:`~animat.learners.ppo.learner.PPOLearner`)."""

    hp: dict[str, Any]
    logger: Logger

    def evaluate(self, model, venv) -> dict[str, float]: ...

    def save_checkpoint(self, folder: Path, model, venv, state: dict, start: float) -> None: ...


def _next_multiple(step: int, every: int) -> int:
    """The first multiple of ``every`` after ``step``."""
    return (int(step) // int(every) + 1) * int(every)


# SB3's count of learn() iterations restarts at a resume; the env step (x) already says it
NOT_FORWARDED = {"time/iterations"}


def sb3_logger(logger):
    """An SB3 logger whose records (``train/*``, ``rollout/*``, ``time/*`` at the env step
    they were dumped) go into this run's logger, beside ``eval/*``."""
    from stable_baselines3.common.logger import KVWriter
    from stable_baselines3.common.logger import Logger as SB3Logger

    class Forward(KVWriter):
        def write(self, key_values: dict, key_excluded: dict, step: int = 0) -> None:
            for key, value in key_values.items():
                if key in NOT_FORWARDED:
                    continue
                if isinstance(value, int | float | np.number) and np.isfinite(value):
                    logger.scalar(key, float(value), step)

        def close(self) -> None:
            pass

    return SB3Logger(folder=None, output_formats=[Forward()])


def progress_callback(learner: LearningRun, model, venv, folder: Path | None, state: dict,
                      start: float, final: int):
    """SB3's callback for a run: an evaluation every ``eval_every`` env steps (but at the run's
    ``final`` step, where :meth:`~animat.learners.ppo.learner.PPOLearner.learn` evaluates the
    last policy: one value per step), a checkpoint every ``checkpoint_every`` between
    rollouts, and where the wall time goes: ``time/rollout_seconds`` (a rollout collected, its
    evaluations included) and ``time/update_seconds`` (the update on it, before the next).
    Torch runs on ``update_threads`` while the policy is updated and on ``torch_threads``
    while the envs step (:mod:`~animat.learners.ppo.threads`)."""
    from stable_baselines3.common.callbacks import BaseCallback

    every_eval, every_save = learner.hp["eval_every"], learner.hp["checkpoint_every"]
    rollout_threads, updating_threads = learner.hp["torch_threads"], update_threads(learner.hp)

    class Progress(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.next_eval = _next_multiple(model.num_timesteps, every_eval)
            self.next_save = _next_multiple(model.num_timesteps, every_save)
            self.began = time.perf_counter()
            self.ended: float | None = None

        def _on_step(self) -> bool:
            if self.next_eval <= self.num_timesteps < final:
                state["metrics"] = learner.evaluate(model, venv)
                learner.logger.scalars(state["metrics"], self.num_timesteps)
                self.next_eval = _next_multiple(self.num_timesteps, every_eval)
            return True

        def _on_rollout_end(self) -> None:
            set_threads(updating_threads)
            self.ended = time.perf_counter()
            learner.logger.scalar("time/rollout_seconds", self.ended - self.began,
                                  self.num_timesteps)

        def _on_rollout_start(self) -> None:
            set_threads(rollout_threads)
            if self.ended is not None:  # the update since the last rollout ended
                learner.logger.scalar("time/update_seconds", time.perf_counter() - self.ended,
                                      self.num_timesteps)
            # between rollouts (the last one trained on): a checkpoint at a whole number
            # of rollouts, so that a resumed run collects exactly what the whole one would
            if folder and self.num_timesteps >= self.next_save:
                learner.save_checkpoint(folder, model, venv, state, start)
                self.next_save = _next_multiple(self.num_timesteps, every_save)
            self.began = time.perf_counter()

    return Progress()
