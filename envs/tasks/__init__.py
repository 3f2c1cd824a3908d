"""Tasks: what a body is asked to do (locomotion, the dolphin's tasks and stunts), each a
:class:`~animat.envs.tasks.base.Task` whose terms are pure functions of the core's ``World``.
:data:`TASKS` is the one table of tasks by name, the package's and the registered ones. A new
task is its class, in the package or in the user's own module, registered by name with
:func:`register_task` (``animat.envs.register_task``), and an env id of it with
:func:`animat.envs.registration.register_env` (the walk-through is
docs/tutorials/extending.md).

May import core (its peer), vision, motor, render, physics, bodies and checks.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields, is_dataclass
from typing import Any, TypeVar, overload

from ..checks import adopt_name, check_entry_name, is_new_entry, shown
from .base import Task
from .dolphin import (
    DolphinArcTask,
    DolphinForwardTask,
    DolphinSpinTask,
    DolphinTurnTask,
)
from .locomotion import ReachTask, SwimTask, TurnTask
from .stunts import BallTask, BellyFlopTask, LeapTask, SomersaultTask

TASKS: dict[str, type[Task]] = {
    "swim": SwimTask, "turn": TurnTask, "reach": ReachTask,
    "dolphin_forward": DolphinForwardTask, "dolphin_turn": DolphinTurnTask,
    "dolphin_arc": DolphinArcTask, "dolphin_spin": DolphinSpinTask, "leap": LeapTask,
    "ball": BallTask, "somersault": SomersaultTask, "belly_flop": BellyFlopTask,
}
T = TypeVar("T", bound=type[Task])


def make_task(name: str, **kwargs) -> Task:
    """The task ``name`` with its keyword arguments; a ValueError of one line for an unknown
    name or argument (each task checks its arguments' values)."""
    if not (isinstance(name, str) and name in TASKS):
        raise ValueError(f"unknown task {shown(name)}; choose one of {sorted(TASKS)}")
    cls: Any = TASKS[name]  # a dataclass, most tasks; fields() reads its arguments' names
    known = sorted(f.name for f in fields(cls)) if is_dataclass(cls) else []
    unknown = sorted(map(str, set(kwargs) - set(known)))
    if known and unknown:
        raise ValueError(f"task {name!r} has no argument(s) {unknown}; its arguments: {known}")
    return TASKS[name](**kwargs)


@overload
def register_task(name: str, cls: None = None) -> Callable[[T], T]: ...
@overload
def register_task(name: str, cls: T) -> T: ...
def register_task(name: str, cls=None):
    """Register ``cls``, a subclass of :class:`~animat.envs.tasks.base.Task`, as the task
    ``name``, so that the body envs take ``task=name`` (``gym.make("Animat/FishSwim-v0",
    task=name)``) and :func:`animat.envs.registration.register_env` gives it an env id.

    A plain call, ``register_task("sprint", SprintTask)``, or a decorator,
    ``@register_task("sprint")`` over the class; either returns the class. A class that sets no
    ``name`` of its own is given this one (``Task.name`` is what its messages say). Refused
    with a ValueError of one line: a name that is not a non-empty string, a name already taken
    by another class (the same class registered again is no change), an object that is not a
    ``Task`` subclass, a class whose own ``name`` is another.
    """
    check_entry_name("register_task", name)
    if cls is None:
        return lambda given: register_task(name, given)
    if not is_new_entry("register_task", "task", TASKS, name, cls):
        return cls
    if not (isinstance(cls, type) and issubclass(cls, Task)):
        raise ValueError(f"register_task({name!r}, ...): not a subclass of "
                         f"animat.envs.tasks.base.Task: {shown(cls)}")
    adopt_name("register_task", cls, name)
    TASKS[name] = cls
    return cls
