"""Fingerprints of what the code computes: one SHA-256 a line, to show that a change of layout
or names changed no number.

``python -m animat.experiments.fingerprint [--out DIR] [--only rollout|run|figure]`` prints

- ``rollout <id> single`` and ``rollout <id> vector`` (ids with a native vector env): every
  registered ``Animat/`` env reset with seed 0 (the vector env, 3 sub-envs, seeds 0-2) and
  stepped 25 times (past an episode end: 0.5 s episodes where the env takes ``duration``) with
  seeded uniform actions; hashed: observations, rewards, ends and every numeric ``info`` entry;
- ``run <learner>``: the result metrics and artefacts of a tiny run of annealing, CMA-ES,
  macro, PPO, stroke and behaviours (in this process, no run folder);
- ``figure <file>``: each PNG of ``animat figures --frames 16`` (written to ``--out``).

It uses only public names (env ids, ``make_learner``, ``make_figures``), so the same command
runs before and after a refactor; a figure's PNG also depends on the installed matplotlib and
OpenCV, so compare fingerprints made on one machine.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import tempfile
from collections.abc import Iterator
from pathlib import Path

import gymnasium as gym
import numpy as np

import animat  # noqa: F401

from .launch.shipped import REPERTOIRES

STEPS = 25
SHORT = {"duration": 0.5}  # envs that take a duration: 10 env steps an episode
RUNS = {  # learner: (env id, env kwargs, params, budget)
    "annealing": ("Animat/FishSwim-v0", SHORT, {"chains": 8, "nodes": 4}, 960),
    "cmaes": ("Animat/FishSwim-v0", SHORT, {"popsize": 8, "nodes": 4}, 960),
    "macro": ("Animat/FishReach-v0", SHORT, {"chains": 8, "slots": 2, "repertoire": "fish"},
              960),
    "ppo": ("Animat/FishSwim-v0", SHORT, {"n_envs": 4, "n_steps": 16, "batch_size": 32,
                                          "n_epochs": 1, "eval_every": 64,
                                          "policy_kwargs": "dict(net_arch=[16])"}, 128),
    "stroke": ("Animat/DolphinSomersault-v0", SHORT, {
        "chains": 8, "repertoire": "dolphin",
        "prefix": [{"skill": "move_forward", "duration": 0.2}]}, 960),
    "behaviours": ("Animat/MarineWorld-v0", SHORT, {"episodes": 2}, 20),
}


def _digest(*parts) -> str:
    """SHA-256 over arrays (their dtype, shape and bytes), dicts (by sorted key) and plain
    values (as JSON)."""
    digest = hashlib.sha256()

    def feed(value) -> None:
        if isinstance(value, dict):
            for key in sorted(value, key=str):
                digest.update(str(key).encode())
                feed(value[key])
        elif isinstance(value, np.ndarray | np.generic | float | int | bool):
            array = np.ascontiguousarray(value)
            digest.update(f"{array.dtype.str}{array.shape}".encode())
            digest.update(array.tobytes())
        else:
            digest.update(json.dumps(value, sort_keys=True, default=str).encode())

    for part in parts:
        feed(part)
    return digest.hexdigest()


def _numeric(info: dict) -> dict:
    return {k: np.asarray(v) for k, v in info.items()
            if np.asarray(v).dtype.kind in "biuf"}


def _kwargs(env_id: str) -> dict:
    """A short episode where the env takes ``duration``."""
    try:
        gym.make(env_id, **SHORT).close()
    except (TypeError, ValueError):
        return {}
    return dict(SHORT)


def rollout(env_id: str, vector: bool) -> str:
    """The digest of a seeded rollout of ``env_id`` (single, or a native vector of 3)."""
    kwargs = _kwargs(env_id)
    env = gym.make_vec(env_id, num_envs=3, **kwargs) if vector else gym.make(env_id, **kwargs)
    rng = np.random.default_rng(0)
    obs, info = env.reset(seed=0)
    parts = [obs, _numeric(info)]
    for _ in range(STEPS):
        action = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        obs, reward, terminated, truncated, info = env.step(action)
        parts += [obs, np.asarray(reward), np.asarray(terminated), np.asarray(truncated),
                  _numeric(info)]
        if not vector and (terminated or truncated):
            obs, info = env.reset()
            parts += [obs, _numeric(info)]
    env.close()
    return _digest(*parts)


def rollouts() -> Iterator[tuple[str, str]]:
    for env_id in sorted(i for i in gym.registry if i.startswith("Animat/")):
        yield f"rollout {env_id} single", rollout(env_id, False)
        if gym.spec(env_id).vector_entry_point is not None:
            yield f"rollout {env_id} vector", rollout(env_id, True)


def runs() -> Iterator[tuple[str, str]]:
    from animat.learners.registry import make_learner

    for name, (env_id, kwargs, params, budget) in RUNS.items():
        if "repertoire" in params:
            params = {**params, "repertoire": str(REPERTOIRES /
                                                  f"{params['repertoire']}.json")}
        result = make_learner(name, env_id, kwargs, params, seed=0).learn(budget)
        artefacts = {k: v for k, v in result.artefacts.items() if k != "repertoire"}
        yield f"run {name}", _digest(result.metrics, result.env_steps, artefacts)


def figures(out: Path) -> Iterator[tuple[str, str]]:
    from .figures.vision import make_figures

    make_figures(out, 0, 16)
    for path in sorted(out.glob("*.png")):
        yield f"figure {path.name}", hashlib.sha256(path.read_bytes()).hexdigest()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m animat.experiments.fingerprint",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help="where the figures go (default: a temporary "
                        "folder)")
    parser.add_argument("--only", choices=("rollout", "run", "figure"))
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        out = args.out or Path(scratch)
        kinds = {"rollout": rollouts, "run": runs, "figure": lambda: figures(out)}
        for kind, lines in kinds.items():
            if args.only in (None, kind):
                for name, digest in lines():
                    print(f"{digest}  {name}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
