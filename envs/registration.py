"""Every env id, in one table: :data:`ENVS` maps each ``Animat/...`` id to its entry points
and registered keyword arguments, and :func:`register` gives them to Gymnasium (called once,
by importing :mod:`animat.envs`).

The fish's locomotion ids and the dolphin's tasks run on the batched core
(:mod:`animat.envs.core`, a native vector env each); the pursuit and the living world are
single envs.
"""

from __future__ import annotations

import gymnasium as gym

CORE = {"entry_point": "animat.envs.core.env:BodyEnv",
        "vector_entry_point": "animat.envs.core.env:BodyVectorEnv"}
FISH_ENVS = {"Animat/FishSwim-v0": {"task": "swim"}, "Animat/FishTurn-v0": {"task": "turn"},
             "Animat/FishReach-v0": {"task": "reach"}}
# The dolphin's world: a water surface at z = 0, skin friction for its Reynolds number (C_f
# 0.0028 at Re 1e7: 0.5 rho C_f = 1.4 kg/m^3), and a step within its stability bound. The pool
# is the base water: a user's water={...} changes its fields, it does not replace the pool.
DOLPHIN_KWARGS = {"body": "dolphin",
                  "base_water": {"surface_z": 0.0, "friction_coefficient": 1.4},
                  "physics_dt": 0.05 / 80, "frame_skip": 80}
# The stunts weigh the controller's effort (mu1) a tenth of the fish's: a 5 Hz fluke stroke
# costs ten times a 3 Hz fish's tail beat in E_u, which would otherwise outweigh the stunt.
STUNT_WEIGHTS = {"mu1": 1e-5}
DOLPHIN_ENVS = {
    "Animat/DolphinForward-v0": {"task": "dolphin_forward"},
    "Animat/DolphinTurn-v0": {"task": "dolphin_turn"},
    "Animat/DolphinArc-v0": {"task": "dolphin_arc"},
    "Animat/DolphinSpin-v0": {"task": "dolphin_spin"},
    "Animat/DolphinLeap-v0": {"task": "leap", "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinNoseBall-v0": {"task": "ball", "part": "nose",
                                  "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinTailBall-v0": {"task": "ball", "part": "tail",
                                  "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinSomersault-v0": {"task": "somersault", "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinBellyFlop-v0": {"task": "belly_flop", "reward_weights": STUNT_WEIGHTS},
}
ENVS: dict[str, dict] = {
    **{env_id: {**CORE, "kwargs": kwargs} for env_id, kwargs in FISH_ENVS.items()},
    **{env_id: {**CORE, "kwargs": {**DOLPHIN_KWARGS, **kwargs}}
       for env_id, kwargs in DOLPHIN_ENVS.items()},
    "Animat/FishPursuit-v0": {"entry_point": "animat.envs.world.pursuit.env:FishPursuitEnv"},
    "Animat/MarineWorld-v0": {"entry_point": "animat.envs.world.marine_env:MarineWorldEnv"},
}


def register() -> None:
    """Give Gymnasium every id of :data:`ENVS` it does not have yet."""
    for env_id, entry in ENVS.items():
        if env_id not in gym.registry:
            gym.register(id=env_id, **entry)
