"""Golden per-step digests of the physics as it is: every env below, stepped from a seeded
reset under seeded actions, must give the stored digest at every step, so that "the ``-v0``
physics did not move" is a test. A digest covers the observation (pictures included), the
reward and the episode's ends, bit for bit.

A change that moves them is a change of an env's dynamics: its id's version goes up and the
old version keeps these digests. Regenerate only for a new case:
``ANIMAT_GOLDEN=write python -m pytest tests/envs/test_golden.py``.
"""

import hashlib
import json
import os
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401  (registers Animat/*)

GOLDEN = Path(__file__).with_name("golden_digests.json")
STEPS = 20
RESISTIVE = {"water": {"model": "resistive"}}
CASES = {  # name: (env id, kwargs, batch size or None for a single env)
    "FishSwim-v0 single": ("Animat/FishSwim-v0", {}, None),
    "FishSwim-v0 single resistive": ("Animat/FishSwim-v0", RESISTIVE, None),
    "FishTurn-v0 single": ("Animat/FishTurn-v0", {}, None),
    "FishReach-v0 single": ("Animat/FishReach-v0", {}, None),
    "DolphinLeap-v0 single": ("Animat/DolphinLeap-v0", {}, None),
    "DolphinLeap-v0 single resistive": ("Animat/DolphinLeap-v0", RESISTIVE, None),
    "DolphinForward-v0 single": ("Animat/DolphinForward-v0", {}, None),
    "FishSwim-v0 batch of 20": ("Animat/FishSwim-v0", {}, 20),
    "FishSwim-v0 batch of 20 resistive": ("Animat/FishSwim-v0", RESISTIVE, 20),
    "DolphinLeap-v0 batch of 20": ("Animat/DolphinLeap-v0", {}, 20),
    "FishPursuit-v0 single": ("Animat/FishPursuit-v0", {}, None),
}


def _digest(*arrays) -> str:
    digest = hashlib.sha256()
    for value in arrays:
        named = value if isinstance(value, dict) else {"": value}
        for key in sorted(named):
            array = np.ascontiguousarray(named[key])
            digest.update(f"{key}{array.dtype.str}{array.shape}".encode())
            digest.update(array.tobytes())
    return digest.hexdigest()[:16]


def step_digests(env_id: str, kwargs: dict, batch: int | None) -> list[str]:
    """The reset's digest, then each step's, of ``env_id`` under seeded uniform actions."""
    env = (gym.make_vec(env_id, num_envs=batch, **kwargs) if batch
           else gym.make(env_id, **kwargs))
    rng = np.random.default_rng(0)
    try:
        obs, _ = env.reset(seed=0)
        digests = [_digest(obs)]
        for _ in range(STEPS):
            action = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
            obs, reward, terminated, truncated, _ = env.step(action)
            digests.append(_digest(obs, np.asarray(reward), np.asarray(terminated),
                                   np.asarray(truncated)))
    finally:
        env.close()
    return digests


def _stored() -> dict:
    return json.loads(GOLDEN.read_text()) if GOLDEN.exists() else {}


@pytest.mark.parametrize("name", sorted(CASES))
def test_every_step_gives_its_stored_digest(name):
    digests = step_digests(*CASES[name])
    if os.environ.get("ANIMAT_GOLDEN") == "write":
        GOLDEN.write_text(json.dumps({**_stored(), name: digests}, indent=1, sort_keys=True)
                          + "\n")
    stored = _stored()[name]
    moved = next((k for k, (a, b) in enumerate(zip(digests, stored)) if a != b), None)
    assert moved is None and len(digests) == len(stored), (
        f"{name}: the dynamics moved at step {moved} (0: the reset)")
