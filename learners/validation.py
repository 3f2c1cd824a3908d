"""What a learner checks before any work, each refusal one line: the env, one it can drive
(:data:`DRIVES`, :func:`check_drives`), its params typed and finite (:func:`typed_params`,
:func:`unknown_params`, :func:`check_finite`), its budget (:class:`BudgetError`,
:func:`check_scoring_budget`) and the memory a size would take (:func:`check_memory`)."""

from __future__ import annotations

import math
import os
import types
import typing
from collections.abc import Iterator, Sequence
from dataclasses import fields
from pathlib import Path
from typing import Any, overload

from animat.envs.registration import CORE, ENVS, MARINE, PURSUIT


class EnvIds(Sequence[str]):
    """The ids of :data:`animat.envs.registration.ENVS` of the entry point ``entry_point``
    (None: every id), read from the table each time they are asked for, so that an id a user
    registers (:func:`animat.envs.register_env`) is among them from then on."""

    def __init__(self, entry_point: str | None = None) -> None:
        self.entry_point = entry_point

    def ids(self) -> tuple[str, ...]:
        return tuple(i for i, entry in ENVS.items()
                     if self.entry_point in (None, entry["entry_point"]))

    @overload
    def __getitem__(self, index: int) -> str: ...
    @overload
    def __getitem__(self, index: slice) -> Sequence[str]: ...
    def __getitem__(self, index):
        return self.ids()[index]

    def __len__(self) -> int:
        return len(self.ids())

    def __iter__(self) -> Iterator[str]:
        return iter(self.ids())

    def __contains__(self, env_id: object) -> bool:
        return env_id in self.ids()


# The envs of the core (the fish's and the dolphin's bodies, and those a user registers with
# animat.envs.register_env), which have a task and a native batch: what the black-box
# learners' batched scoring (a vector env's ``task``) and the hand-designed controllers need; a
# learner's own checks narrow them further (the reach task of the steering learners, the
# dolphin's actuators of the stroke learners).
CORE_ENVS = EnvIds(CORE["entry_point"])
PURSUIT_ENVS = EnvIds(PURSUIT["entry_point"])
MARINE_ENVS = EnvIds(MARINE)
ALL_ENVS = EnvIds()
# What each learner drives, and how its refusal says it: PPO steps any env of this project and
# scores it by the env's own episode summary; basic training drives its regimen's envs (the
# config's own is not stepped); the scorers of a policy made for one world drive that world; a
# learner a user registers (animat.learners.register_learner) drives any env of the table.
DRIVES: dict[str, tuple[Sequence[str], str]] = {
    **{name: (CORE_ENVS, "the envs of the fish's and the dolphin's bodies")
       for name in ("annealing", "cmaes", "handmc", "macro", "stroke", "stroke_cmaes",
                    "steering", "switching", "switching_coordinate", "stunt_table",
                    "stunt_table_coordinate", "macro_triggered")},
    "ppo": (ALL_ENVS, "this project's envs"),
    "basic_training": (ALL_ENVS, "this project's envs"),
    "active_vision": (PURSUIT_ENVS, "the pursuit"),
    "behaviours": (MARINE_ENVS, "the living world"),
}


def check_drives(name: str, env_id: str) -> None:
    """ValueError in one line, naming what the learner ``name`` drives, when it cannot drive
    the env ``env_id`` (e.g. a Gymnasium env of another project, which reports none of the
    episode metrics every learner logs)."""
    envs, what = DRIVES.get(name, (ALL_ENVS, "this project's envs"))
    if env_id not in envs:
        named = (", ".join(envs) if len(envs) <= 3 else
                 f"all {len(envs)} envs animat list names" if len(envs) == len(ENVS) else
                 f"{len(envs)} of the envs animat list names, e.g. {envs[0]}")
        raise ValueError(f"learner {name!r} drives {what} ({named}), not {env_id}")


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


def check_finite(name: str, value: Any, owner: str) -> None:
    """ValueError in one line naming ``owner`` and the param ``name`` (``name[k]`` within a
    list) when ``value``, or a number in the lists it holds, is a float that is not finite
    (``.inf``, ``.nan``): no learner param means infinity, and a NaN passes every range check
    written as a comparison."""
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{owner}: {name} must be a finite number, got {value!r}")
    if isinstance(value, list | tuple):
        for k, item in enumerate(value):
            check_finite(f"{name}[{k}]", item, owner)


def typed_params(cls: type, values: dict, owner: str):
    """A frozen params dataclass ``cls`` from a config mapping: unknown names, values of the
    wrong kind and numbers that are not finite (:func:`check_finite`) are refused in one line
    naming ``owner`` (e.g. ``learner 'annealing'``) and the field; integers given for floats
    become floats; ``cls.__post_init__`` then checks ranges."""
    if not isinstance(values, dict):
        raise ValueError(f"{owner}: params must be a mapping, got {values!r:.80}")
    unknown_params(values, {f.name for f in fields(cls)}, owner)
    hints = typing.get_type_hints(cls)
    converted = {}
    for name, value in values.items():
        if not _kind_ok(value, hints[name]):
            raise ValueError(f"{owner}: {name} must be {_kind_name(hints[name])}, got {value!r}")
        check_finite(name, value, owner)
        converted[name] = float(value) if hints[name] is float else value
    try:
        return cls(**converted)
    except ValueError as error:
        raise ValueError(f"{owner}: {error}") from None
