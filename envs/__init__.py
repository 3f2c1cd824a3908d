"""artificial-animals environments, in rooms: ``bodies`` (the animals), ``physics`` (the
solver), ``motor`` (the motor controllers), ``core`` (the batched bodies and the Gymnasium
envs), ``tasks``, ``render``, ``vision``, ``world`` (the living world), and ``registration``
(every id in one table). Dependencies run one way: registration -> world -> core, tasks ->
vision -> motor, render -> physics -> bodies -> checks (docs/architecture.md).

Importing ``animat`` (or ``animat.envs``) registers the Gymnasium environments under ``Animat``:
``Animat/FishSwim-v0``, ``Animat/FishTurn-v0`` and ``Animat/FishReach-v0``, each with a native
batched vector env (``gym.make_vec(id, num_envs=256)``), ``Animat/FishPursuit-v0``
(vision-guided pursuit; :mod:`animat.envs.world.pursuit`) and ``Animat/MarineWorld-v0`` (the
living world of 10 fishes; :mod:`animat.envs.world`); and the dolphin's tasks
(:mod:`animat.envs.tasks.dolphin`, :mod:`animat.envs.tasks.stunts`): ``Animat/DolphinForward-v0``,
``Animat/DolphinTurn-v0`` (up, down, left, right), ``Animat/DolphinArc-v0`` (a turn taken at
speed), ``Animat/DolphinSpin-v0`` (a pitch spin), ``Animat/DolphinLeap-v0``,
``Animat/DolphinNoseBall-v0``, ``Animat/DolphinTailBall-v0``, ``Animat/DolphinSomersault-v0``,
``Animat/DolphinBellyFlop-v0``, each with a native vector env.
"""

from __future__ import annotations

from .registration import register

register()
