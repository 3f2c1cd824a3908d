"""Learner throughput: env steps per wall second of the learners as they learn, against the
native batch they step, measured in the same process and in interleaved rounds.

``animat bench --learners``: on ``Animat/FishSwim-v0`` (5 s episodes, the default water),

* the anchor: the native batch of 64 envs stepped with random actions, with nothing learned;
* annealing (the paper's learner), CMA-ES and PPO, each with its shipped swim config's params
  (``configs/fish_swim/{annealing,cmaes,ppo}.yaml``: 64 chains, a population of 64, 64 envs and
  rl-baselines3-zoo's settings), learning for a budget of about ``seconds`` of the anchor's
  steps (rounded to whole rounds or rollouts), their evaluations included;

each as the median over the rounds, and the ratio of each learner to the anchor: what of the
simulator's speed reaches a user's learning curve.
"""

from __future__ import annotations

import time

import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)

ENV_ID, ENV_KWARGS, NUM_ENVS = "Animat/FishSwim-v0", {"duration": 5.0}, 64
CONFIGS = {"annealing": "fish_swim/annealing.yaml", "CMA-ES": "fish_swim/cmaes.yaml",
           "PPO": "fish_swim/ppo.yaml"}
ANCHOR = f"native batch of {NUM_ENVS}, random actions (anchor)"


def batch_rate(seconds: float, seed: int = 0) -> float:
    """Env steps per wall second of the native batch of :data:`NUM_ENVS` with random actions
    (episodes end and restart as they do for the learners)."""
    envs = gym.make_vec(ENV_ID, num_envs=NUM_ENVS, **ENV_KWARGS)
    envs.reset(seed=seed)
    rng = np.random.default_rng(seed)
    actions = rng.uniform(-1, 1, (8,) + envs.action_space.shape).astype(np.float32)
    envs.step(actions[0])
    steps, start = 0, time.perf_counter()
    while (elapsed := time.perf_counter() - start) < seconds:
        envs.step(actions[steps % 8])
        steps += 1
    envs.close()
    return steps * NUM_ENVS / elapsed


def learner_rate(label: str, budget: int, seed: int = 0) -> float:
    """Env steps per wall second of the learner of ``CONFIGS[label]`` learning for ``budget``
    env steps (its shipped params, this benchmark's env), from its learn call's start to its
    end."""
    from animat.learners.logger import Logger
    from animat.learners.registry import make_learner

    from ..launch.config import load_config
    from ..launch.shipped import find_config

    config = load_config(find_config(CONFIGS[label]), [f"budget.env_steps={budget}"])
    learner = make_learner(config.learner.name, ENV_ID, dict(ENV_KWARGS),
                           dict(config.learner.params), seed, Logger([]))
    start = time.perf_counter()
    result = learner.learn(budget)
    return result.env_steps / (time.perf_counter() - start)


MIN_BUDGET = 100_000  # env steps a learner learns for at least (PPO: 24 rollouts of 64 x 64)


def run(seconds: float = 6.0, rounds: int = 3) -> dict[str, float]:
    """{configuration: median env steps/s over ``rounds`` interleaved rounds}: the anchor
    stepped ``seconds / rounds`` a round, each learner for the steps the anchor made in its
    first round (at least :data:`MIN_BUDGET`)."""
    samples: dict[str, list[float]] = {ANCHOR: [], **{label: [] for label in CONFIGS}}
    budget = None
    for k in range(rounds):
        samples[ANCHOR].append(batch_rate(seconds / rounds, seed=k))
        budget = budget or max(int(samples[ANCHOR][0] * seconds / rounds), MIN_BUDGET)
        for label in CONFIGS:
            samples[label].append(learner_rate(label, budget, seed=k))
    return {name: float(np.median(values)) for name, values in samples.items()}


def report(result: dict[str, float]) -> str:
    anchor = result[ANCHOR]
    lines = [f"{'configuration':48s} {'env steps/s':>12s} {'x anchor':>9s}"]
    for name, rate in result.items():
        lines.append(f"{name:48s} {rate:12.0f} {rate / anchor:9.2f}")
    lines.append("Animat/FishSwim-v0, 5 s episodes, the default water; each learner with its "
                 "shipped swim config's params, its evaluations included")
    return "\n".join(lines)
