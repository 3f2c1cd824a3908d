"""The paper's vision-guided pursuit controller (:class:`ActiveVisionPolicy`,
:mod:`animat.envs.world.pursuit.policy`) as a learner that learns nothing (like ``handmc``), so
that it stands in comparisons on ``Animat/FishPursuit-v0``; with ``blind``, the same policy
with both retinas blanked (every pixel 0), the baseline that shows what sight adds; with
``oracle``, :class:`OraclePolicy`, its navigation steered by the prey's true position (the env
must give it: ``oracle: true`` in its kwargs), the baseline of what sight could give."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.envs.world.pursuit.policy import ActiveVisionParams, ActiveVisionPolicy, OraclePolicy

from ..agents import PolicyAgent
from ..base import LearnResult, Scorer
from ..validation import typed_params


@dataclass(frozen=True)
class PursuitEvalParams:
    """episodes: seeded pursuit episodes scored (seeds seed .. seed + episodes - 1);
    policy: the ActiveVisionPolicy's params; blind: blank both retinas before the policy
    sees them; oracle: steer by the prey's true position (:class:`OraclePolicy`)."""

    episodes: int = 5
    policy: dict | None = None
    blind: bool = False
    oracle: bool = False


def blindfolded(obs: dict) -> dict:
    """The observation with both eyes' images black (their shape and dtype kept)."""
    return {**obs, "left_eye": np.zeros_like(obs["left_eye"]),
            "right_eye": np.zeros_like(obs["right_eye"])}


class ActiveVisionLearner(Scorer):
    """Scores :class:`ActiveVisionPolicy` on the pursuit env over ``episodes`` seeds (learns
    nothing); logs ``eval/return``, ``eval/fovea_fraction``, ``eval/distance_closed_bl``
    (means, with ``_std`` over the episodes) and ``eval/passer_fraction``."""

    name = "active_vision"

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.own = typed_params(PursuitEvalParams, self.params, f"learner {self.name!r}")
        self.policy_params = typed_params(ActiveVisionParams, self.own.policy or {},
                                          f"learner {self.name!r}.policy")
        if self.own.oracle and (self.own.blind or not self.env_kwargs.get("oracle")):
            raise ValueError(f"learner {self.name!r}: oracle needs env.kwargs.oracle: true "
                             f"(the prey's true position) and is not blind")

    def agent(self, artefacts: dict, folder) -> PolicyAgent:
        if self.own.oracle:
            return PolicyAgent(OraclePolicy(self.policy_params), self.env_id, self.env_kwargs)
        return PolicyAgent(ActiveVisionPolicy(self.policy_params), self.env_id, self.env_kwargs,
                           normalize=blindfolded if self.own.blind else None)

    def scored_episodes(self) -> int:
        return int(self.own.episodes)

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        self.check_budget(budget_env_steps)
        env = gym.make(self.env_id, **self.env_kwargs)
        return self.score_policy(env, self.agent({}, None), self.own.episodes)
