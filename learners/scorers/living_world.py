"""The world fish's own behaviours as a learner that learns nothing (as ``handmc`` is for the
motor controllers): it scores the living world with every fish on its behaviours over seeded
episodes, by the protocol of every learner, and logs the world's figures with the shared tags
(``eval/food_eaten``, ``eval/obstacle_collisions``, ``eval/fish_collisions``,
``eval/school_cohesion_bl``, ``eval/catches``, ``eval/matings``; means over the episodes
with ``_std`` beside each)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym
import numpy as np

from ..agents import PolicyAgent
from ..base import LearnResult, Scorer
from ..rollout import START_STATES
from ..validation import typed_params


@dataclass(frozen=True)
class BehavioursParams:
    """episodes: seeded episodes scored (seeds seed .. seed + episodes - 1)."""

    episodes: int = START_STATES

    def __post_init__(self) -> None:
        if self.episodes < 1:
            raise ValueError(f"episodes must be >= 1, got {self.episodes!r}")


class IdlePolicy:
    """An action of zeros: in a world whose fish live by their behaviours the action is not
    used, and the env still checks it."""

    def __init__(self, shape: tuple[int, ...]) -> None:
        self.shape = shape

    def predict(self, obs, state=None, episode_start=None, deterministic: bool = True):
        return np.zeros(self.shape, np.float32), None


class BehavioursLearner(Scorer):
    """Scores a world env (``Animat/MarineWorld-v0`` with ``control: behaviour``) over
    ``episodes`` seeds."""

    name = "behaviours"

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.own = typed_params(BehavioursParams, self.params, f"learner {self.name!r}")
        self._env().close()  # refuses, at construction, an env it cannot score

    def _env(self) -> gym.Env:
        env = gym.make(self.env_id, **self.env_kwargs)
        if getattr(env.unwrapped, "control", None) != "behaviour":
            env.close()
            raise ValueError(f"learner {self.name!r} needs a world whose fish all live by their "
                             f"behaviours (Animat/MarineWorld-v0 with control: behaviour), got "
                             f"{self.env_id}")
        return env

    def agent(self, artefacts: dict, folder) -> PolicyAgent:
        env = self._env()
        shape = env.action_space.shape
        env.close()
        return PolicyAgent(IdlePolicy(shape), self.env_id, self.env_kwargs)

    def scored_episodes(self) -> int:
        return int(self.own.episodes)

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        self.check_budget(budget_env_steps)
        env = self._env()
        try:
            return self.score_policy(env, IdlePolicy(env.action_space.shape),
                                self.own.episodes)
        finally:
            env.close()
