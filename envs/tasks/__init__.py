"""Tasks: what a body is asked to do (locomotion, the dolphin's tasks and stunts), each a
:class:`~animat.envs.tasks.base.Task` whose terms are pure functions of the core's ``World``.
:data:`TASKS` is the one table of tasks by name (a new task: its class, and one line here).

May import core (its peer), vision, motor, render, physics, bodies and checks.
"""

from __future__ import annotations

from dataclasses import fields, is_dataclass

from ..checks import shown
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

def make_task(name: str, **kwargs) -> Task:
    """The task ``name`` with its keyword arguments; a ValueError of one line for an unknown
    name or argument (each task checks its arguments' values)."""
    if not (isinstance(name, str) and name in TASKS):
        raise ValueError(f"unknown task {shown(name)}; choose one of {sorted(TASKS)}")
    known = sorted(f.name for f in fields(TASKS[name])) if is_dataclass(TASKS[name]) else []
    unknown = sorted(map(str, set(kwargs) - set(known)))
    if known and unknown:
        raise ValueError(f"task {name!r} has no argument(s) {unknown}; its arguments: {known}")
    return TASKS[name](**kwargs)
