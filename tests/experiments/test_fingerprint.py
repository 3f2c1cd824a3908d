"""The fingerprint command (the before/after proof of a refactor) covers every registered env,
and a rollout's digest is the same twice and changes when a number does."""

import gymnasium as gym
import numpy as np

from animat.experiments import fingerprint


def test_every_env_is_fingerprinted_and_the_digest_is_stable(monkeypatch):
    names = [name for name, _ in fingerprint.rollouts()]
    ids = sorted(i for i in gym.registry if i.startswith("Animat/"))
    assert [n for n in names if n.endswith(" single")] == [f"rollout {i} single" for i in ids]
    assert "rollout Animat/FishSwim-v0 vector" in names
    first = fingerprint.rollout("Animat/FishTurn-v0", vector=True)
    assert fingerprint.rollout("Animat/FishTurn-v0", vector=True) == first
    monkeypatch.setattr(fingerprint, "STEPS", fingerprint.STEPS - 1)
    assert fingerprint.rollout("Animat/FishTurn-v0", vector=True) != first
    assert fingerprint._digest(np.float32(1.0)) != fingerprint._digest(np.float64(1.0))
