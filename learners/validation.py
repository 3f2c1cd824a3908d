"""What a learner checks before any work, each refusal one line: its params typed
(:func:`typed_params`, :func:`unknown_params`), its budget (:class:`BudgetError`,
:func:`check_scoring_budget`) and the memory a size would take (:func:`check_memory`)."""

from __future__ import annotations

import os
import types
import typing
from dataclasses import fields
from pathlib import Path
from typing import Any


class BudgetError(ValueError):
    """The run's budget cannot work for this learner (e.g. less than one round): said in one
    line, before anything runs."""


def check_scoring_budget(budget_env_steps: int, episodes: int, steps: int) -> None:
    """Raise :class:`BudgetError` if ``episodes`` scored episodes of ``steps`` env steps do
    not fit the budget."""
    if budget_env_steps < episodes * steps:
        raise BudgetError(f"{budget_env_steps} is less than the {episodes * steps} env steps "
                          f"scoring takes ({episodes} episodes of {steps})")


def machine_memory() -> int | None:
    """Bytes of memory this process may use: the machine's, or its cgroup's limit where that
    is lower; None where it cannot be read."""
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
    except OSError:
        return total
    return min(total, int(limit)) if limit.isdigit() else total


def check_memory(need: int, what: str) -> None:
    """ValueError in one line when ``what`` (e.g. ``nodes 100000000 x 6 actuators``) would
    take more memory (``need`` bytes) than this machine has: a size refused before any work,
    not a MemoryError (or the kernel's OOM killer) in the middle of the run."""
    total = machine_memory()
    if total is not None and need > total:
        raise ValueError(f"{what} would take {need / 2**30:.3g} GiB of memory, more than this "
                         f"machine's {total / 2**30:.3g} GiB")


def unknown_params(params: dict, allowed: set[str], learner: str) -> None:
    """Raise ValueError naming parameters a learner does not take (``learner``: its name, or
    a description such as ``learner 'annealing'``)."""
    extra = sorted(set(params) - allowed)
    if extra:
        who = learner if learner.startswith("learner ") else f"learner {learner!r}"
        raise ValueError(f"{who} does not take parameter(s) {extra}; "
                         f"it takes {sorted(allowed)}")


def _kind_ok(value, kind) -> bool:
    """Whether ``value`` fits the annotation ``kind`` (int, float, bool, str, dict, list,
    tuple, Any, and unions with None of these)."""
    if kind is Any:
        return True
    if typing.get_origin(kind) in (typing.Union, types.UnionType):
        return any(_kind_ok(value, k) for k in typing.get_args(kind))
    if kind is type(None):
        return value is None
    if kind is bool:
        return isinstance(value, bool)
    if kind is int:
        return isinstance(value, int) and not isinstance(value, bool)
    if kind is float:
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    origin = typing.get_origin(kind) or kind
    if origin in (list, tuple):
        return isinstance(value, (list, tuple))
    return isinstance(value, origin)


_KIND_NAMES = {int: "an integer", float: "a number", bool: "true or false", str: "a string",
               dict: "a mapping", list: "a list", tuple: "a list"}


def _kind_name(kind) -> str:
    if typing.get_origin(kind) in (typing.Union, types.UnionType):
        return " or ".join("null" if k is type(None) else _kind_name(k)
                           for k in typing.get_args(kind))
    return _KIND_NAMES.get(typing.get_origin(kind) or kind, getattr(kind, "__name__", str(kind)))


def typed_params(cls: type, values: dict, owner: str):
    """A frozen params dataclass ``cls`` from a config mapping: unknown names and values of
    the wrong kind are refused in one line naming ``owner`` (e.g. ``learner 'annealing'``) and
    the field; integers given for floats become floats; ``cls.__post_init__`` then checks
    ranges."""
    unknown_params(values, {f.name for f in fields(cls)}, owner)
    hints = typing.get_type_hints(cls)
    converted = {}
    for name, value in values.items():
        if not _kind_ok(value, hints[name]):
            raise ValueError(f"{owner}: {name} must be {_kind_name(hints[name])}, got {value!r}")
        converted[name] = float(value) if hints[name] is float else value
    try:
        return cls(**converted)
    except ValueError as error:
        raise ValueError(f"{owner}: {error}") from None
