"""artificial-animals environments: bodies, physics, motor controllers and Gymnasium tasks.

Importing ``animat`` (or ``animat.envs``) registers the Gymnasium environments under ``Animat``:
``Animat/FishSwim-v0``, ``Animat/FishTurn-v0`` and ``Animat/FishReach-v0``, each with a native
batched vector env (``gym.make_vec(id, num_envs=256)``), and ``Animat/FishPursuit-v0``
(vision-guided pursuit; :mod:`animat.envs.pursuit`).
"""

from __future__ import annotations

import gymnasium as gym

ENV_IDS = ("Animat/FishSwim-v0", "Animat/FishTurn-v0", "Animat/FishReach-v0")


def _register() -> None:
    for env_id, task in zip(ENV_IDS, ("swim", "turn", "reach")):
        if env_id in gym.registry:
            continue
        gym.register(id=env_id, entry_point="animat.envs.fish_env:FishEnv",
                     vector_entry_point="animat.envs.fish_env:FishVectorEnv", kwargs={"task": task})
    if "Animat/FishPursuit-v0" not in gym.registry:
        gym.register(id="Animat/FishPursuit-v0", entry_point="animat.envs.pursuit:FishPursuitEnv")


_register()
