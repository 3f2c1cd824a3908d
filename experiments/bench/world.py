"""Benchmark of the living world: env steps per wall second of the paper's 10-fish scenario
(``Animat/MarineWorld-v0``), without retinas and with one fish that sees by its real eyes
and active vision, each beside the single fish env (``Animat/FishSwim-v0``) as the reference,
in the same process and in interleaved rounds (the median of each), as ratios to it; printed
beside the paper's 4 frames/s of 1995 (10 fishes, wireframe rendering, no vision; an SGI
R4400 Indigo2 Extreme). Run ``animat world-bench``.

``animat world-bench --fish 10,100,1000 [--plot FILE]`` measures how the cost grows with the
population instead (:func:`run_sizes`): worlds at the paper's density (its 1 : 6 : 3 sharks,
minnows and angelfish, 1.5 food particles and half an obstacle a fish, the tank's side
6 m times sqrt(fish / 10)), every fish perceiving by the oracle; a table of env steps/s, ms
per step, us per fish-step and the growth exponent between sizes (1: the cost grows with the
fish, 2: with their square), and a log-log plot.
"""

from __future__ import annotations

import time

import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)

PAPER_FPS = 4.0
TARGETS = {"10 fishes, oracle perception": 100.0, "10 fishes, one with eyes": 30.0}
SIZE_TARGETS = {100: 30.0}  # env steps/s with the oracle, for a world of 100 fishes
PAPER_DENSITY = 10 / 36.0  # fish per m^2: 10 fishes in the 6 m x 6 m tank


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


def median_rates(envs: dict, seconds: float, rounds: int) -> dict:
    """{key: median env steps/s of ``envs[key]`` over ``rounds`` interleaved rounds of
    ``seconds``} (round k seeds every env with k)."""
    samples: dict = {key: [] for key in envs}
    for k in range(rounds):
        for key, env in envs.items():
            samples[key].append(steps_per_second(env, seconds, seed=k))
    return {key: float(np.median(values)) for key, values in samples.items()}


def run(seconds: float = 3.0, rounds: int = 3) -> dict[str, float]:
    """{configuration: median env steps/s over ``rounds`` interleaved rounds of ``seconds``}."""
    return median_rates(configurations(), seconds, rounds)


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


def population_world(fish: int) -> gym.Env:
    """``Animat/MarineWorld-v0`` of ``fish`` fish at the paper's density (see the module
    docstring)."""
    sharks = max(1, round(0.1 * fish))
    minnows = min(round(0.6 * fish), fish - sharks)
    species = {"shark": sharks, "minnow": minnows, "angelfish": fish - sharks - minnows}
    return gym.make("Animat/MarineWorld-v0", species=species, food=round(1.5 * fish),
                    obstacles=fish // 2, tank_size=float(np.sqrt(fish / PAPER_DENSITY)))


def run_sizes(sizes: list[int], seconds: float = 3.0, rounds: int = 3) -> dict[int, float]:
    """{fish: median env steps/s over ``rounds`` interleaved rounds of ``seconds``} of
    :func:`population_world` at each size."""
    return median_rates({n: population_world(n) for n in sizes}, seconds, rounds)


def report_sizes(result: dict[int, float]) -> str:
    """The growth table of :func:`run_sizes`: per size its rate, ms per step, us per
    fish-step, and the exponent of the cost's growth from the size before."""
    lines = [f"{'fish':>6s} {'env steps/s':>12s} {'ms/step':>9s} {'us/fish-step':>13s} "
             f"{'growth':>7s}  target"]
    before = None
    for n, rate in sorted(result.items()):
        growth = "" if before is None else f"{np.log(before[1] / rate) / np.log(n / before[0]):.2f}"
        target = SIZE_TARGETS.get(n)
        verdict = "" if target is None else (
            f">= {target:g}: " + ("met" if rate >= target else "MISSED"))
        lines.append(f"{n:6d} {rate:12.1f} {1e3 / rate:9.2f} {1e6 / rate / n:13.1f} "
                     f"{growth:>7s}  {verdict}")
        before = (n, rate)
    lines.append("growth: d log(time per step) / d log(fish) from the size before (1: the cost "
                 "grows with the fish, 2: with their square)")
    return "\n".join(lines)


def plot_sizes(result: dict[int, float], path) -> None:
    """A log-log plot of ms per env step against the fish, with slopes 1 and 2 for scale."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sizes = np.array(sorted(result), float)
    ms = np.array([1e3 / result[int(n)] for n in sizes])
    figure, axes = plt.subplots(figsize=(5, 4))
    axes.loglog(sizes, ms, "o-", label="MarineWorld-v0, oracle perception")
    for slope, style in ((1, ":"), (2, "--")):
        axes.loglog(sizes, ms[0] * (sizes / sizes[0]) ** slope, style, color="grey",
                    label=f"slope {slope}")
    axes.set_xlabel("fish (the paper's density)")
    axes.set_ylabel("ms per env step")
    axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
