"""The closed-loop maneuver (:mod:`animat.learners.skills.steering`) as a learner that learns
nothing (like ``handmc``): its rules are set in the config (by hand, or found by ``animat
tune``), and it is scored over seeded reach episodes, so that it stands beside the macro
learner, PPO and CMA-ES on ``Animat/FishReach-v0``."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym

import animat  # noqa: F401
from animat.envs.registration import timing

from ..base import LearnResult, Scorer
from ..controllers.repertoire import Repertoire, kept_in_run
from ..skills.steering import SkillSteering, SteeringAgent, SteeringParams, check_reach
from ..validation import typed_params


@dataclass(frozen=True)
class SteeringEvalParams:
    """repertoire: path of a repertoire JSON (required); episodes: seeded reach episodes
    scored (seeds seed .. seed + episodes - 1); steering: :class:`SteeringParams`' fields."""

    repertoire: str | None = None
    episodes: int = 16
    steering: dict | None = None

    def __post_init__(self) -> None:
        if self.repertoire is None:
            raise ValueError("needs params.repertoire (a repertoire file)")
        if type(self.episodes) is not int or self.episodes < 1:
            raise ValueError(f"episodes must be an integer >= 1, got {self.episodes!r}")


class SteeringLearner(Scorer):
    """Scores the steering over ``episodes`` seeded episodes of a reach env; logs
    ``eval/return``, ``eval/final_distance_bl`` and ``eval/reached`` (the share of episodes
    that end within the task's ``reached_bl``), means with ``_std`` over the episodes."""

    name = "steering"
    path_params = ("repertoire",)

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        owner = f"learner {self.name!r}"
        self.own = typed_params(SteeringEvalParams, self.params, owner)
        self.rules = typed_params(SteeringParams, self.own.steering or {}, f"{owner}.steering")
        check_reach(self.env_id, self.env_kwargs, f"learner {self.name!r}")
        self.repertoire = Repertoire.load(self.own.repertoire)
        self.dt = float(timing(self.env_id, self.env_kwargs).dt)
        SkillSteering(self.repertoire, self.rules, self.dt)  # a repertoire it cannot use

    def scored_episodes(self) -> int:
        return int(self.own.episodes)

    def agent(self, artefacts: dict, folder) -> SteeringAgent:
        return SteeringAgent(SkillSteering(self.repertoire, self.rules, self.dt), self.env_id,
                             self.env_kwargs)

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        self.check_budget(budget_env_steps)
        self.repertoire = kept_in_run(self.repertoire, checkpoint_dir)
        env = gym.make(self.env_id, **self.env_kwargs)
        try:
            return self.score_policy(env, self.agent({}, checkpoint_dir), self.own.episodes)
        finally:
            env.close()
