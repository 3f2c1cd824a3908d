"""artificial-animals environments: bodies, physics, motor controllers and Gymnasium tasks.

Importing ``animat`` (or ``animat.envs``) registers the Gymnasium environments under ``Animat``:
``Animat/FishSwim-v0``, ``Animat/FishTurn-v0`` and ``Animat/FishReach-v0``, each with a native
batched vector env (``gym.make_vec(id, num_envs=256)``), ``Animat/FishPursuit-v0``
(vision-guided pursuit; :mod:`animat.envs.pursuit`) and ``Animat/MarineWorld-v0`` (the living
world of 10 fishes; :mod:`animat.envs.world`); and the dolphin's tasks
(:mod:`animat.envs.dolphin_tasks`, :mod:`animat.envs.stunts`): ``Animat/DolphinForward-v0``,
``Animat/DolphinTurn-v0`` (up, down, left, right), ``Animat/DolphinArc-v0`` (a turn taken at
speed), ``Animat/DolphinSpin-v0`` (a pitch spin), ``Animat/DolphinLeap-v0``,
``Animat/DolphinNoseBall-v0``, ``Animat/DolphinTailBall-v0``, ``Animat/DolphinSomersault-v0``,
``Animat/DolphinBellyFlop-v0``, each with a native vector env.
"""

from __future__ import annotations

import gymnasium as gym

from animat.envs import stunts  # noqa: F401  (adds the dolphin's tasks to envs.tasks.TASKS)

ENV_IDS = ("Animat/FishSwim-v0", "Animat/FishTurn-v0", "Animat/FishReach-v0")
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


def _register() -> None:
    for env_id, task in zip(ENV_IDS, ("swim", "turn", "reach")):
        if env_id in gym.registry:
            continue
        gym.register(id=env_id, entry_point="animat.envs.fish_env:FishEnv",
                     vector_entry_point="animat.envs.fish_env:FishVectorEnv", kwargs={"task": task})
    for env_id, kwargs in DOLPHIN_ENVS.items():
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point="animat.envs.fish_env:FishEnv",
                         vector_entry_point="animat.envs.fish_env:FishVectorEnv",
                         kwargs={**DOLPHIN_KWARGS, **kwargs})
    if "Animat/FishPursuit-v0" not in gym.registry:
        gym.register(id="Animat/FishPursuit-v0", entry_point="animat.envs.pursuit:FishPursuitEnv")
    if "Animat/MarineWorld-v0" not in gym.registry:
        gym.register(id="Animat/MarineWorld-v0",
                     entry_point="animat.envs.world.marine_env:MarineWorldEnv")


_register()
