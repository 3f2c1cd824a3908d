"""What a finished run acts with: agents made from its artefacts (see ``Learner.agent``).

Every agent has SB3's ``predict(obs, state=None, episode_start=None, deterministic=True) ->
(action, state)`` for one (unbatched) observation of one env, and ``reset()`` to begin an
episode; ``env_id`` and ``env_kwargs`` name the env it was learned in.

* :class:`OpenLoopAgent`: a motor controller played open loop (the learned tent controller or
  its FFT abstraction, a macro sequence of skills, a hand-designed MC), the action of step k
  being the activation it asks for at the step's end
  (:func:`animat.learners.controllers.tent.play`).
* :class:`PolicyAgent`: a closed-loop policy (PPO's network with its observation
  normalisation, the active-vision controller).
* :class:`BatchPolicyAgent`: a batched closed-loop policy played for one body (the dolphin's
  stunt table, its triggered macro).
* :class:`SkillSet`: a repertoire, one open-loop agent per skill, each in its own env.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .controllers.tent import play


class OpenLoopAgent:
    """Plays ``actuation(t) -> u (..., A)`` from t = 0 at the env's ``dt`` (s) for ``steps``
    steps (then holds the last action)."""

    def __init__(self, actuation, dt: float, steps: int, env_id: str = "",
                 env_kwargs: dict | None = None) -> None:
        self.actions = play(actuation, dt, steps)
        self.env_id, self.env_kwargs = env_id, dict(env_kwargs or {})
        self.reset()

    def reset(self) -> None:
        self.step = 0

    def predict(self, obs, state=None, episode_start=None, deterministic: bool = True):
        action = self.actions[min(self.step, len(self.actions) - 1)]
        self.step += 1
        return action, None


class PolicyAgent:
    """A closed-loop ``policy`` (with ``predict``), its observations first passed through
    ``normalize`` (e.g. a VecNormalize's ``normalize_obs``) when given."""

    def __init__(self, policy, env_id: str = "", env_kwargs: dict | None = None,
                 normalize=None) -> None:
        self.policy, self.normalize = policy, normalize
        self.env_id, self.env_kwargs = env_id, dict(env_kwargs or {})

    def reset(self) -> None:
        if hasattr(self.policy, "reset"):
            self.policy.reset()

    def predict(self, obs, state=None, episode_start=None, deterministic: bool = True):
        seen = self.normalize(obs) if self.normalize is not None else obs
        action, _ = self.policy.predict(seen, deterministic=deterministic)
        return np.asarray(action), None


class BatchPolicyAgent:
    """One body played by a batched closed-loop ``policy``: ``reset(batch)`` begins episodes
    of ``batch`` bodies, ``act(obs (B, O)) -> (B, A)`` gives their env actions."""

    def __init__(self, policy, env_id: str = "", env_kwargs: dict | None = None) -> None:
        self.policy, self.env_id, self.env_kwargs = policy, env_id, dict(env_kwargs or {})
        self.reset()

    def reset(self) -> None:
        self.policy.reset(1)

    def predict(self, obs, state=None, episode_start=None, deterministic: bool = True):
        return self.policy.act(np.asarray(obs)[None])[0], None


@dataclass
class SkillSet:
    """A repertoire's skills as agents: ``agents`` {skill name: agent in its own env}."""

    agents: dict[str, OpenLoopAgent] = field(default_factory=dict)
