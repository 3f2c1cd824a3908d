"""Pursuit benchmark: full ``Animat/FishPursuit-v0`` steps per second, what they are made of, and
the native vector env against the single env.

``python -m animat.experiments.bench.vision``: in the same rounds,

* the physics alone (the pursuit's fish in one batched step: a ``BodyBatch`` of as many
  swimming fish with fins, six by default, driven through the pursuit's navigator);
* an env step (physics, then both retinas rendered: 8 cameras over the scene with its
  scenery), with a fixed action;
* a full step with the vision: the :class:`~animat.envs.world.pursuit.policy.ActiveVisionPolicy`
  reading the observation (detection in both eyes, saccades) and the env stepping; and the
  same with the paper's loop (``configs/fish_pursuit/paper_loop.yaml``: flow stabilisation
  and vergence by correlation on, the reflex and the scan off), on an env of its own;
* both retinas over the paper's 10-fish scene (:mod:`animat.experiments.bench.retina`);
* the native vector env of ``--worlds`` worlds (16), in env steps per second (worlds times
  its steps), with the same fixed action, and the ratio to the single env's step measured in
  the same rounds;
* the vector env's step taken apart, per world: the physics, the minds and motor controllers,
  the eyes' poses and the triangles, the cameras (raster), and the rest (sensors, info);

each as a median over rounds, with the ratios, and the paper's 1995 figure beside them.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.envs.core.batch import BodyBatch
from animat.envs.tasks import make_task
from animat.envs.vision.retina import RetinaParams
from animat.envs.world.pursuit.policy import ActiveVisionParams, ActiveVisionPolicy

from .retina import eyes_once, paper_scene, rate


def _pursuit(seed: int = 0):
    env = gym.make("Animat/FishPursuit-v0", duration=10_000.0).unwrapped
    obs, _ = env.reset(seed=seed)
    return env, obs


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=12.0)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--worlds", type=int, default=16)
    args = parser.parse_args(argv)
    env, obs = _pursuit()
    policy, still = ActiveVisionPolicy(), np.zeros(7, np.float32)
    paper_env, paper_obs = _pursuit()
    paper = ActiveVisionPolicy(paper_loop_params())
    n = env.fish
    moves = env.worlds.navigator.actions(np.array([[0.6, 0.0, 0.0]] * n), 0.0).astype(np.float64)
    scene, retina = paper_scene(), RetinaParams()
    state = {"obs": obs, "paper": paper_obs}
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

    def paper_step() -> None:
        action, _ = paper.predict(state["paper"])
        state["paper"] = paper_env.step(action)[0]

    physics_name = f"physics of {n} fish (one env step)"
    worlds, parts = _vector(args.worlds)
    vector_name = f"vector env, {args.worlds} worlds (env steps)"
    tasks = {physics_name: physics,
             "env step: physics + both retinas": env_step,
             "full step: + active vision policy": full_step,
             "full step: + the paper's loop": paper_step,
             "both retinas, 10-fish scene": lambda: eyes_once(scene, retina),
             vector_name: parts.pop("vector step")}
    tasks.update(parts)
    rates: dict[str, list[float]] = {name: [] for name in tasks}
    share = args.seconds / args.rounds / len(tasks)
    for _ in range(args.rounds):
        for name, fn in tasks.items():
            rates[name].append(rate(fn, share))
    medians = {name: float(np.median(values)) for name, values in rates.items()}
    medians[vector_name] *= worlds
    reference = medians[physics_name]
    for name in list(tasks)[:5]:
        value = medians[name]
        unit = "frame-sets/s" if "10-fish" in name else "steps/s"
        print(f"{name:38s} {value:8.1f} {unit:12s} ({value / reference:.2f} x the physics)")
    single = medians["env step: physics + both retinas"]
    print(f"{vector_name:38s} {medians[vector_name]:8.1f} {'steps/s':12s} "
          f"({medians[vector_name] / single:.2f} x one env's step)")
    whole = 1e6 / medians[vector_name]
    micro = {name: 1e6 / medians[name] / worlds for name in parts}
    micro["cameras (raster)"] = micro.pop(EYES) - micro[GEOMETRY]
    micro["the rest: sensors, info, stepping"] = whole - sum(micro.values())
    print(f"its step per world: {whole:.0f} us, of which")
    for name, value in micro.items():
        print(f"  {name:36s} {value:8.0f} us  ({value / whole:.0%})")
    print("the paper (1995, SGI): about 4 frames/s for the 10-fish scene, without vision")


GEOMETRY, EYES = "eye poses and triangles", "eye poses, triangles and cameras"


def paper_loop_params() -> ActiveVisionParams:
    """The policy's params as ``configs/fish_pursuit/paper_loop.yaml`` sets them."""
    from ..launch.config import load_config
    from ..launch.shipped import find_config

    config = load_config(find_config("fish_pursuit/paper_loop.yaml"))
    return replace(ActiveVisionParams(), **config.learner.params["policy"])


def _vector(worlds: int):
    """The vector env's step, and its parts (name -> a function doing that part once for the
    whole batch), on its own copy of the batch (the vector env's state is not disturbed)."""
    vec = gym.make_vec("Animat/FishPursuit-v0", num_envs=worlds, duration=10_000.0)
    vec.reset(seed=0)
    still = np.zeros((worlds, 7), np.float32)
    core = vec.unwrapped.worlds
    rngs = [np.random.default_rng(k) for k in range(worlds)]
    kinematics = core.core.kinematics()
    moves = core.navigator.actions(np.tile([0.6, 0.0, 0.0], (len(core.core.state.x), 1)), 0.0)
    physics = BodyBatch(len(core.core.state.x), make_task("swim"), duration=10_000.0,
                        fins=True, start_spread="point")
    physics.reset_rows(np.arange(len(moves)), [np.random.default_rng(0)] * len(moves))
    params = core.retina

    def minds() -> None:
        commands = core.others.commands(core.core.state.x[:, 0], kinematics, core.time,
                                        core.dt, rngs)
        core.navigator.actions(commands, np.repeat(core.time, core.fish))

    def geometry() -> None:
        core.eye_poses(kinematics, fresh=True)
        core.triangles()

    def raster() -> None:
        core.eye_images(params, kinematics)

    parts = {"vector step": lambda: vec.step(still),
             "physics": lambda: physics.step(moves.astype(np.float64)),
             "minds and motor controllers": minds,
             GEOMETRY: geometry, EYES: raster}
    return worlds, parts


if __name__ == "__main__":
    main()
