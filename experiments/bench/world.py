"""Benchmark of the living world: env steps per wall second of the paper's 10-fish scenario
(``Animat/MarineWorld-v0``), without retinas and with one fish that sees by its real eyes
and active vision, each beside the single fish env (``Animat/FishSwim-v0``) as the reference,
in the same process and in interleaved rounds (the median of each), as ratios to it; printed
beside the paper's 4 frames/s of 1995 (10 fishes, wireframe rendering, no vision; an SGI
R4400 Indigo2 Extreme). Run ``animat world-bench``.
"""

from __future__ import annotations

import time

import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)

PAPER_FPS = 4.0
TARGETS = {"10 fishes, oracle perception": 100.0, "10 fishes, one with eyes": 30.0}


def steps_per_second(env, seconds: float, seed: int = 0) -> float:
    """Env steps per wall second of ``env`` over about ``seconds`` (after a warm-up), with
    zero actions (the world's fish live by their behaviours); resets when an episode ends."""
    env.reset(seed=seed)
    action = np.zeros(env.action_space.shape, np.float32)
    for _ in range(3):
        env.step(action)
    steps, start = 0, time.perf_counter()
    while (elapsed := time.perf_counter() - start) < seconds:
        _, _, terminated, truncated, _ = env.step(action)
        steps += 1
        if terminated or truncated:
            env.reset()
    return steps / elapsed


def configurations() -> dict[str, gym.Env]:
    return {"1 fish (FishSwim-v0, reference)": gym.make("Animat/FishSwim-v0"),
            "10 fishes, oracle perception": gym.make("Animat/MarineWorld-v0"),
            "10 fishes, one with eyes": gym.make("Animat/MarineWorld-v0", vision=0)}


def run(seconds: float = 3.0, rounds: int = 3) -> dict[str, float]:
    """{configuration: median env steps/s over ``rounds`` interleaved rounds of ``seconds``}."""
    envs = configurations()
    samples: dict[str, list[float]] = {name: [] for name in envs}
    for k in range(rounds):
        for name, env in envs.items():
            samples[name].append(steps_per_second(env, seconds, seed=k))
    return {name: float(np.median(values)) for name, values in samples.items()}


def report(result: dict[str, float]) -> str:
    reference = result["1 fish (FishSwim-v0, reference)"]
    lines = [f"{'configuration':36s} {'env steps/s':>12s} {'x reference':>12s} "
             f"{'x paper':>8s}  target"]
    for name, rate in result.items():
        target = TARGETS.get(name)
        met = "" if target is None else ("met" if rate >= target else "MISSED")
        verdict = "" if target is None else f">= {target:g}: {met}"
        lines.append(f"{name:36s} {rate:12.1f} {rate / reference:12.3f} "
                     f"{rate / PAPER_FPS:8.1f}  {verdict}")
    lines.append(f"the paper (1995): {PAPER_FPS:g} frames/s for 10 fishes, 15 food particles and "
                 "5 obstacles, wireframe, without vision")
    return "\n".join(lines)
