"""artificial-animals environments: bodies, physics, motor controllers and Gymnasium tasks.

Importing ``envs`` registers the Gymnasium environments under the ``Animat`` namespace:
``Animat/FishSwim-v0``, ``Animat/FishTurn-v0`` and ``Animat/FishReach-v0``, each with a native
batched vector env (``gym.make_vec(id, num_envs=256)``).
"""

from __future__ import annotations

import gymnasium as gym

ENV_IDS = ("Animat/FishSwim-v0", "Animat/FishTurn-v0", "Animat/FishReach-v0")


def _register() -> None:
    for env_id, name in zip(ENV_IDS, ("Swim", "Turn", "Reach")):
        if env_id in gym.registry:
            continue
        gym.register(
            id=env_id,
            entry_point=f"envs.fish_env:Fish{name}Env",
            vector_entry_point=f"envs.fish_env:make_{name.lower()}_vector",
        )


_register()
