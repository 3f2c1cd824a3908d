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

A user adds to them from their own module, without editing the package
(docs/tutorials/extending.md): :func:`register_body` (a body by name), :func:`register_task` (a
task by name), :func:`register_sensor` (a sensor by name, so that a config's ``sensors`` list
may name it; a sensor object is taken as it is, too) and :func:`register_env` (an env id of a
task and a body, with the native vector env). The first three are imported when first asked
for, so that ``import animat`` stays light.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .registration import register, register_env

if TYPE_CHECKING:
    from .bodies import register_body
    from .core.sensors import register_sensor
    from .tasks import register_task

__all__ = ["register", "register_body", "register_env", "register_sensor", "register_task"]


def __getattr__(name: str) -> Any:
    """:func:`register_body`, :func:`register_sensor` and :func:`register_task`, their rooms
    imported when first asked for (the tasks import the physics)."""
    if name == "register_body":
        from .bodies import register_body

        return register_body
    if name == "register_task":
        from .tasks import register_task

        return register_task
    if name == "register_sensor":
        from .core.sensors import register_sensor

        return register_sensor
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


register()
