"""Pursuit benchmark: full ``Animat/FishPursuit-v0`` steps per second, and what they are made of.

``python -m animat.experiments.bench.vision``: in the same rounds, on one core,

* the physics alone (the pursuit's fish in one batched step: a ``BodyBatch`` of as many
  swimming fish with fins, six by default, driven through the pursuit's navigator);
* an env step (physics, then both retinas rendered: 8 cameras over the scene with its
  scenery), with a fixed action;
* a full step with the vision: the :class:`~animat.envs.world.pursuit.policy.ActiveVisionPolicy`
  reading the observation (detection in both eyes, saccades) and the env stepping;
* both retinas over the paper's 10-fish scene (:mod:`animat.experiments.bench.retina`);

each as a median over rounds, with the ratios, and the paper's 1995 figure beside them.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.envs.core.batch import BodyBatch
from animat.envs.tasks import make_task
from animat.envs.vision.retina import RetinaParams
from animat.envs.world.pursuit.policy import ActiveVisionPolicy

from .retina import eyes_once, paper_scene, rate


def _pursuit(seed: int = 0):
    env = gym.make("Animat/FishPursuit-v0", duration=10_000.0).unwrapped
    obs, _ = env.reset(seed=seed)
    return env, obs


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=12.0)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    env, obs = _pursuit()
    policy, still = ActiveVisionPolicy(), np.zeros(7, np.float32)
    n = env.fish
    moves = env.navigator.actions(np.array([[0.6, 0.0, 0.0]] * n), 0.0).astype(np.float64)
    scene, retina = paper_scene(), RetinaParams()
    state = {"obs": obs}
    fish = BodyBatch(n, make_task("swim"), duration=10_000.0, fins=True,
                     start_spread="point")  # as the pursuit's
    fish.reset_rows(np.arange(n), [np.random.default_rng(seed) for seed in range(n)])

    def physics() -> None:
        fish.step(moves)

    def env_step() -> None:
        env.step(still)

    def full_step() -> None:
        action, _ = policy.predict(state["obs"])
        state["obs"] = env.step(action)[0]

    physics_name = f"physics of {n} fish (one env step)"
    tasks = {physics_name: physics,
             "env step: physics + both retinas": env_step,
             "full step: + active vision policy": full_step,
             "both retinas, 10-fish scene": lambda: eyes_once(scene, retina)}
    rates: dict[str, list[float]] = {name: [] for name in tasks}
    share = args.seconds / args.rounds / len(tasks)
    for _ in range(args.rounds):
        for name, fn in tasks.items():
            rates[name].append(rate(fn, share))
    medians = {name: float(np.median(values)) for name, values in rates.items()}
    reference = medians[physics_name]
    for name, value in medians.items():
        unit = "frame-sets/s" if "10-fish" in name else "steps/s"
        print(f"{name:38s} {value:8.1f} {unit:12s} ({value / reference:.2f} x the physics)")
    print("the paper (1995, SGI): about 4 frames/s for the 10-fish scene, without vision")


if __name__ == "__main__":
    main()
