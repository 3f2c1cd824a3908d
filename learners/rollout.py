"""Evaluating open-loop controllers by simulation, many at once on the native vector env.

Every candidate is played from the same ``num_starts`` seeded start states (seeds ``seed``,
``seed + 1``, ...; default :data:`START_STATES`), each drawn from the task's start distribution
(:mod:`animat.envs.tasks.start`: headings, bends and velocities that differ), and its return and
metrics are the means over them, with the spread (``<metric>_std``) beside each: the objective
E = -return is a deterministic function of the controller (simulated annealing and CMA-ES need
that), and no controller is scored on one lucky start. The native batch gives every row the
numbers a single env would, so batching never changes E. Every learner, PPO and the hand MC
included, is scored by this protocol. A finished run is scored afresh on start states it never
saw (:func:`unseen_seeds`, what ``animat eval`` plays by default).
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)
from animat.envs.tasks.base import EpisodeSummary

START_STATES = 4  # start states every candidate and every final result is scored over
# The first seed of the start states a run never saw: a run of seed s learns from seeds s, s + 1,
# ... (fewer than a million of them), and is scored afresh from seeds UNSEEN_SEEDS_FROM + s, ...
UNSEEN_SEEDS_FROM = 1_000_000


def unseen_seeds(seed: int, count: int) -> list[int]:
    """``count`` start-state seeds that the run of ``seed`` never learned from (its own are
    ``seed .. seed + start_states - 1``): ``UNSEEN_SEEDS_FROM + seed`` on."""
    return [UNSEEN_SEEDS_FROM + int(seed) + k for k in range(int(count))]


def check_worst_share(worst_share: float) -> None:
    """ValueError in one line unless ``worst_share`` (the share of start states a candidate's
    objective averages over, its worst first) is a number in (0, 1]."""
    if type(worst_share) not in (int, float) or not 0 < worst_share <= 1:
        raise ValueError(f"worst_share must be a number in (0, 1] (1: the mean over every "
                         f"start state), got {worst_share!r}")


def worst_mean(returns: np.ndarray, worst_share: float) -> np.ndarray:
    """(P,) the mean of each row's lowest ``ceil(worst_share * S)`` returns of (P, S): with
    ``worst_share`` 1 the plain mean; below 1, the lower tail's mean (the conditional value at
    risk that EPOpt, Rajeswaran et al. 2017, trains on), which a candidate raises only by
    doing better on the starts it does worst on, not by excelling on a few."""
    if worst_share >= 1:
        return returns.mean(axis=1)
    kept = max(1, int(np.ceil(worst_share * returns.shape[1] - 1e-9)))
    return np.sort(returns, axis=1)[:, :kept].mean(axis=1)


NARROW = 32  # rows: a part-filled chunk plays on a batch of the next multiple of this


class BatchEvaluator:
    """Plays action sequences (P, T, A) on a native vector env.

    Args:
        env_id: a registered ``Animat/*`` id; env_kwargs: its keyword arguments.
        num_envs: candidates per batch (P is split into chunks of it; the vector env is
            ``num_envs * num_starts`` wide).
        seed: the first start-state seed (candidates share seeds ``seed .. seed + num_starts - 1``).
        num_starts: start states per candidate.
        worst_share: the share of a candidate's start states its return averages, its
            worst first (:func:`worst_mean`; 1: all of them). Its metrics are always the
            means over every start.
    """

    def __init__(self, env_id: str, env_kwargs: dict | None = None, num_envs: int = 64,
                 seed: int = 0, num_starts: int = START_STATES,
                 worst_share: float = 1.0) -> None:
        if type(num_starts) is not int or num_starts < 1:
            raise ValueError(f"start_states must be an integer >= 1, got {num_starts!r}")
        check_worst_share(worst_share)
        self.num_starts, self.worst_share = num_starts, float(worst_share)
        self.env_id, self.env_kwargs = env_id, dict(env_kwargs or {})
        self.env = gym.make_vec(env_id, num_envs=int(num_envs) * num_starts,
                                **self.env_kwargs)
        self._narrow: dict[int, gym.vector.VectorEnv] = {}  # batches for part-filled chunks
        self.seed = int(seed)
        self.dt = float(self.env.dt)
        self.steps = int(self.env.episode_steps)
        self.duration = self.steps * self.dt
        self.task = self.env.task  # the envs.tasks.base.Task
        self.action_size = int(self.env.single_action_space.shape[0])
        self.env_steps = 0

    @property
    def episode_cost(self) -> int:
        """Env steps it takes to score one candidate (an episode from every start state)."""
        return self.steps * self.num_starts

    def evaluate(self, actions: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Returns (P,) mean episode returns over the start states (over the worst
        ``worst_share`` of them), and the task's summary
        metrics (P,) each, as means with their standard deviations over the start states
        (``<metric>_std``); adds the env steps simulated (P * num_starts * T) to
        ``env_steps``."""
        actions = np.asarray(actions, dtype=np.float32)
        size = self.env.single_action_space.shape[0]
        if actions.ndim != 3 or actions.shape[1:] != (self.steps, size):
            raise ValueError(f"actions must have shape (P, {self.steps}, {size}), got "
                             f"{actions.shape}")
        return self.evaluate_rows(np.repeat(actions, self.num_starts, axis=0))

    def evaluate_rows(self, rows: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """:meth:`evaluate` of P candidates' ``rows`` (P * S, ...), row p * S + s played
        from start s by :meth:`_evaluate_chunk`, ``num_envs`` rows at a time."""
        returns, metrics = [], []
        for start in range(0, len(rows), self.env.num_envs):
            ret, met = self._evaluate_chunk(rows[start:start + self.env.num_envs])
            returns.append(ret)
            metrics.append(met)
        per_start = (len(rows) // self.num_starts, self.num_starts)
        merged = {}
        for k in metrics[0]:
            values = np.concatenate([m[k] for m in metrics]).reshape(per_start)
            merged[k], merged[f"{k}_std"] = values.mean(axis=1), values.std(axis=1)
        return worst_mean(np.concatenate(returns).reshape(per_start), self.worst_share), merged

    def evaluate_players(self, players) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """:meth:`evaluate` the action sequences of ``players`` (anything with
        ``actions(dt, steps)``: controllers, macro sequences)."""
        return self.evaluate(np.stack([p.actions(self.dt, self.steps) for p in players]))

    def _batch_for(self, count: int):
        """The vector env a chunk of ``count`` rows is played on: the full batch, or for a
        chunk that fills less of it (a single candidate's starts, a last part-filled
        round), one of the next multiple of :data:`NARROW` rows, made once. A row plays the
        same, bit for bit, whatever batch it is in (the bodies are independent, each row
        seeded alone)."""
        full = self.env.num_envs
        width = min(full, -(-count // NARROW) * NARROW)
        if width == full:
            return self.env
        if width not in self._narrow:
            self._narrow[width] = gym.make_vec(self.env_id, num_envs=width, **self.env_kwargs)
        return self._narrow[width]

    def _evaluate_chunk(self, chunk: np.ndarray):
        """Play up to ``num_envs`` rows (padded to the batch :meth:`_batch_for` gives) from
        their start states: (rows,) returns and the task's summary metrics (rows,) each."""
        env = self._batch_for(len(chunk))
        count, width = len(chunk), env.num_envs
        padded = np.zeros((width,) + chunk.shape[1:], dtype=chunk.dtype)
        padded[:count] = chunk
        act = self._player(padded)
        obs, _ = env.reset(seed=[self.seed + r % self.num_starts for r in range(width)])
        total = np.zeros(width)
        summary = EpisodeSummary(self.task, width)
        for k in range(self.steps):
            obs, reward, _, _, info = env.step(act(k, obs))
            total += reward
            summary.update(info)
        self.env_steps += count * self.steps
        return total[:count], {k: v[:count] for k, v in summary.summary().items()}

    def _player(self, rows: np.ndarray):
        """``act(k, obs) -> (num_envs, A)`` actions of env step k for the batch's rows: here
        their action sequences (num_envs, T, A), played open loop."""
        actions = rows.astype(np.float32)
        return lambda k, obs: actions[:, k]


def score_episode(env: gym.Env, policy, seed: int) -> dict[str, float]:
    """One seeded episode of ``policy`` (anything with ``predict(obs) -> (action, state)``;
    ``reset()`` called first if it has one) in a single env that sums its own episodes up
    (``env.unwrapped.episode_summary()``, e.g. the pursuit): the summary's figures and the
    ``return``."""
    obs, _ = env.reset(seed=seed)
    if hasattr(policy, "reset"):
        policy.reset()
    summary, total = env.unwrapped.episode_summary(), 0.0
    while True:
        action, _ = policy.predict(obs)
        obs, reward, _, truncated, info = env.step(action)
        total += reward
        summary.update(info)
        if truncated:
            return {**summary.summary(), "return": total}


def spread(runs: list[dict[str, float]]) -> dict[str, float]:
    """``eval/<key>`` means over episodes, with ``eval/<key>_std`` beside each. A figure that
    is undefined (NaN) in an episode (e.g. the vergence of a pursuit that never foveated) is
    averaged over the episodes that have it, and left out if none has."""
    out = {}
    for key in runs[0]:
        values = np.array([r[key] for r in runs], dtype=float)
        values = values[~np.isnan(values)]
        if len(values):
            out[f"eval/{key}"], out[f"eval/{key}_std"] = float(values.mean()), float(values.std())
    return out
