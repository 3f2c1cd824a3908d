"""Evaluating open-loop controllers by simulation, many at once on the native vector env.

Every candidate starts from the same seeded start state, so the objective E = -return is a
deterministic function of the controller (simulated annealing and CMA-ES need that; the
native batch gives every row the numbers a single env would, so batching never changes E).
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import envs  # noqa: F401  (registers Animat/*)


class EpisodeSummary:
    """Accumulates a task's summary metrics over an episode, from each step's info: swim
    ``speed_bl_per_s`` (mean swimming speed over the episode), reach ``final_distance_bl``,
    turn ``final_heading_error_deg`` (absolute, at the end)."""

    def __init__(self, task: str, num_envs: int) -> None:
        if task not in ("swim", "reach", "turn"):
            raise ValueError(f"no summary metrics for task {task!r}")
        self.task, self.steps = task, 0
        self.speed_sum = np.zeros(num_envs)
        self.last: dict[str, np.ndarray] = {}

    def update(self, info: dict[str, np.ndarray]) -> None:
        self.steps += 1
        self.last = info
        if self.task == "swim":
            self.speed_sum = self.speed_sum + info["speed_bl_per_s"]

    def summary(self) -> dict[str, np.ndarray]:
        if self.task == "swim":
            return {"speed_bl_per_s": self.speed_sum / max(self.steps, 1)}
        if self.task == "reach":
            return {"final_distance_bl": np.asarray(self.last["distance_bl"])}
        return {"final_heading_error_deg": np.abs(self.last["heading_error_deg"])}


class BatchEvaluator:
    """Plays action sequences (P, T, 6) on ``num_envs``-wide native vector envs.

    Args:
        env_id: a registered ``Animat/*`` id; env_kwargs: its keyword arguments.
        num_envs: batch width (P is split into chunks of it).
        seed: the start-state seed every candidate shares.
    """

    def __init__(self, env_id: str, env_kwargs: dict | None = None, num_envs: int = 64,
                 seed: int = 0) -> None:
        self.env = gym.make_vec(env_id, num_envs=num_envs, **(env_kwargs or {}))
        self.seed = int(seed)
        self.dt = float(self.env.dt)
        self.steps = int(self.env.core.episode_steps)
        self.duration = self.steps * self.dt
        self.task = self.env.core.task.name
        self.env_steps = 0

    @property
    def num_envs(self) -> int:
        return self.env.num_envs

    def evaluate(self, actions: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Returns (P,) episode returns and the task's summary metrics (P,) each; adds the
        env steps simulated (P * T) to ``env_steps``."""
        actions = np.asarray(actions, dtype=np.float32)
        if actions.ndim != 3 or actions.shape[1] != self.steps:
            raise ValueError(f"actions must have shape (P, {self.steps}, 6), got {actions.shape}")
        returns, metrics = [], []
        for start in range(0, len(actions), self.num_envs):
            chunk = actions[start:start + self.num_envs]
            ret, met = self._evaluate_chunk(chunk)
            returns.append(ret)
            metrics.append(met)
        merged = {k: np.concatenate([m[k] for m in metrics]) for k in metrics[0]}
        return np.concatenate(returns), merged

    def evaluate_players(self, players) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """:meth:`evaluate` the action sequences of ``players`` (anything with
        ``actions(dt, steps)``: controllers, macro sequences)."""
        return self.evaluate(np.stack([p.actions(self.dt, self.steps) for p in players]))

    def _evaluate_chunk(self, chunk: np.ndarray):
        count = len(chunk)
        padded = np.zeros((self.num_envs,) + chunk.shape[1:], dtype=np.float32)
        padded[:count] = chunk
        self.env.reset(seed=[self.seed] * self.num_envs)  # every row: the same start
        total = np.zeros(self.num_envs)
        summary = EpisodeSummary(self.task, self.num_envs)
        for k in range(self.steps):
            _, reward, _, _, info = self.env.step(padded[:, k])
            total += reward
            summary.update(info)
        self.env_steps += count * self.steps
        return total[:count], {k: v[:count] for k, v in summary.summary().items()}
