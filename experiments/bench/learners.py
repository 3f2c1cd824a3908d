"""Learner throughput: env steps per wall second of the learners as they learn, against the
native batch they step, measured in the same process and in interleaved rounds.

``animat bench --learners``: on ``Animat/FishSwim-v0`` (5 s episodes, the default water),

* the anchor: the native batch of 64 envs stepped with random actions, with nothing learned;
* annealing (the paper's learner), CMA-ES and PPO, each with its shipped swim config's params
  (``configs/fish_swim/{annealing,cmaes,ppo}.yaml``: 64 chains, a population of 64, 64 envs and
  rl-baselines3-zoo's settings), learning for a budget of about ``seconds`` of the anchor's
  steps (rounded to whole rounds or rollouts), their evaluations included;

each as the median over the rounds, and the ratio of each learner to the anchor: what of the
simulator's speed reaches a user's learning curve. Then, from the eyes, on
``Animat/FishPursuit-v0`` as ``configs/fish_pursuit/ppo_pixels_compact.yaml`` sets it (16
worlds, both eyes' periphery and fovea, grey, 32x32, two frames):

* the anchor: the native batch of 16 worlds with random actions, drawing those pictures;
* PPO from those pixels with its shipped params (RetinaCNN, rl-baselines3-zoo's PPO for
  CarRacing, torch on one thread while the worlds step and on both cores while it updates),
  learning :data:`PIXEL_ROLLOUTS` rollouts: env steps per wall second of its rollouts and
  updates together (the first rollout, which compiles, left out; no evaluation), and beside
  it what its updates take of that time (``time/update_seconds`` against
  ``time/rollout_seconds``, as the learner logs them).
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
    return stepped_rate(gym.make_vec(ENV_ID, num_envs=NUM_ENVS, **ENV_KWARGS), seconds, seed)


def stepped_rate(envs, seconds: float, seed: int) -> float:
    """Env steps per wall second of the vector env ``envs`` stepped for ``seconds`` with
    random actions (after one step, which compiles), then closed."""
    envs.reset(seed=seed)
    rng = np.random.default_rng(seed)
    actions = rng.uniform(-1, 1, (8,) + envs.action_space.shape).astype(np.float32)
    envs.step(actions[0])
    steps, start = 0, time.perf_counter()
    while (elapsed := time.perf_counter() - start) < seconds:
        envs.step(actions[steps % 8])
        steps += 1
    envs.close()
    return steps * envs.num_envs / elapsed


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


PIXEL_CONFIG = "fish_pursuit/ppo_pixels_compact.yaml"
PIXEL_ANCHOR = "pursuit: native batch of 16 worlds, compact pixels, random actions"
PIXEL_PPO, PIXEL_ROLLOUTS = "PPO from compact pixels, updates included", 6


def _pixel_config(budget: int | None = None):
    from ..launch.config import load_config
    from ..launch.shipped import find_config

    overrides = [] if budget is None else [f"budget.env_steps={budget}",
                                            f"learner.params.eval_every={10 * budget}"]
    return load_config(find_config(PIXEL_CONFIG), overrides)


def pixel_batch_rate(seconds: float, seed: int = 0) -> float:
    """Env steps per wall second of the pursuit's native batch as the pixel PPO config makes
    it, random actions."""
    config = _pixel_config()
    return stepped_rate(gym.make_vec(config.env.id, num_envs=int(config.learner.params["n_envs"]),
                                     **dict(config.env.kwargs)), seconds, seed)


def pixel_ppo_rate(seed: int = 0) -> tuple[float, float]:
    """(env steps per wall second of rollouts and updates, the updates' share of that time)
    of PPO from compact pixels learning :data:`PIXEL_ROLLOUTS` rollouts, the first left out."""
    from animat.learners.logger import Logger, MemorySink
    from animat.learners.registry import make_learner

    params = _pixel_config().learner.params
    rollout = int(params["n_envs"]) * int(params["n_steps"])
    config = _pixel_config(PIXEL_ROLLOUTS * rollout)
    sink = MemorySink()
    learner = make_learner(config.learner.name, config.env.id, dict(config.env.kwargs),
                           dict(config.learner.params), seed, Logger([sink]))
    learner.learn(config.budget.env_steps)
    rollouts = [value for _, value in sink.series("time/rollout_seconds")][1:]
    updates = [value for _, value in sink.series("time/update_seconds")]  # after the first
    spent = sum(rollouts) + sum(updates)
    return len(rollouts) * rollout / spent, sum(updates) / spent


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
    pixels: dict[str, list[float]] = {PIXEL_ANCHOR: [], PIXEL_PPO: [], UPDATE_SHARE: []}
    for k in range(rounds):
        pixels[PIXEL_ANCHOR].append(pixel_batch_rate(seconds / rounds, seed=k))
        rate, share = pixel_ppo_rate(seed=k)
        pixels[PIXEL_PPO].append(rate)
        pixels[UPDATE_SHARE].append(share)
    return {name: float(np.median(values)) for name, values in {**samples, **pixels}.items()}


UPDATE_SHARE = "its updates' share of that time"


def report(result: dict[str, float]) -> str:
    header = f"{'configuration':66s} {'env steps/s':>12s} {'x anchor':>9s}"
    lines = [header]
    for name in [name for name in (ANCHOR, *CONFIGS) if name in result]:
        lines.append(f"{name:66s} {result[name]:12.0f} {result[name] / result[ANCHOR]:9.2f}")
    lines.append("Animat/FishSwim-v0, 5 s episodes, the default water; each learner with its "
                 "shipped swim config's params, its evaluations included")
    if PIXEL_ANCHOR not in result:
        return "\n".join(lines)
    lines += ["", header]
    for name in [PIXEL_ANCHOR, PIXEL_PPO]:
        ratio = result[name] / result[PIXEL_ANCHOR]
        lines.append(f"{name:66s} {result[name]:12.0f} {ratio:9.2f}")
    lines.append(f"{UPDATE_SHARE:66s} {100 * result[UPDATE_SHARE]:11.0f}%")
    lines.append(f"Animat/FishPursuit-v0 as {PIXEL_CONFIG} sets it; PPO over "
                 f"{PIXEL_ROLLOUTS - 1} rollouts after the first, no evaluation")
    return "\n".join(lines)
