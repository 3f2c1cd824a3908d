"""The user's own modules, named on the command line: ``animat --import my_animals run eel.yaml``
imports ``my_animals`` before the command runs, so that the bodies, tasks, sensors, env ids and
learners it registers (``animat.envs.register_*``, ``animat.learners.register_learner``) are
there when the config is read, as RL-Baselines3-Zoo's ``--gym-packages`` imports the packages
that register a user's Gymnasium ids.

Only a module the user names is imported: a config or a run folder never names code to run, so
resuming or re-scoring someone else's folder runs none of theirs. The module is found as
``import`` finds it: installed, or on ``PYTHONPATH`` (``animat`` itself does not put the
working directory on the path; ``python -m animat.experiments``, which a sweep's processes run,
does, as ``python -m`` always does). The processes a command starts (``animat sweep --jobs
N``'s runs, a tune's workers, Ray's tasks) import the same modules first (:func:`import_flags`,
:func:`with_imports`).
"""

from __future__ import annotations

import importlib
import re
from collections.abc import Callable, Iterable
from typing import Any

from animat.learners.ppo.threads import load_torch_first

MODULE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*")
_imported: list[str] = []  # this process's --import modules, in order


class ImportRefused(ValueError):
    """A module named by ``--import`` that is not a module name or does not import."""


def import_modules(names: Iterable[str]) -> None:
    """Import each of ``names`` (dotted module names), in order, and remember them for the
    processes this one starts; :class:`ImportRefused` in one line naming the first that is not
    a module name or cannot be found. An error raised by the module's own code is its own
    (with its traceback under ``--debug``)."""
    for name in names:
        if not MODULE_NAME.fullmatch(name):
            raise ImportRefused(f"--import {name!r}: not a module name (dotted, like "
                                "my_package.animals)")
        try:
            importlib.import_module(name)
        except ModuleNotFoundError as error:
            if error.name is None or not (name == error.name
                                          or name.startswith(f"{error.name}.")):
                raise  # a module it imports is missing: the module's own error
            raise ImportRefused(f"--import {name}: no module named {error.name!r} (install "
                                "it, or put its folder on PYTHONPATH)") from None
        if name not in _imported:
            _imported.append(name)


def imported() -> tuple[str, ...]:
    """The modules this process imported by ``--import``, in order."""
    return tuple(_imported)


def import_flags() -> list[str]:
    """``animat``'s options that import the same modules in a command this process starts."""
    return [flag for name in _imported for flag in ("--import", name)]


def with_imports(names: tuple[str, ...], function: Callable, *args: Any) -> Any:
    """``function(*args)`` after importing ``names`` (:func:`imported` where the call was
    made): what a spawned process or a Ray task runs, so that it knows the same
    registrations (``function`` module-level, so it pickles by reference), with torch loaded
    before any env step (:func:`~animat.learners.ppo.threads.load_torch_first`)."""
    load_torch_first()
    import_modules(names)
    return function(*args)
