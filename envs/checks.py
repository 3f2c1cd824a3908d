"""One-line checks of the values that enter the envs: every keyword argument of an env, a task,
the water and the reward weights is checked where it enters, for its type, finiteness and a
physically sensible range, and a bad one is a ``ValueError`` of one line naming the argument
and the value, e.g. ``reset_noise_scale must be a finite number in [0, 0.01] BL, got nan``.

The ranges themselves live with what they bound (:mod:`animat.envs.core.arguments` for the episode's
cost, :class:`animat.envs.physics.system.Water` for the water, each task for its arguments);
here are only the checks, so that every message reads the same.
"""

from __future__ import annotations

import math
import reprlib
from collections.abc import Sequence
from numbers import Integral, Real
from typing import Any

import numpy as np

MAX_SHOWN = 80  # characters of a bad value shown in a message (a huge value is cut)
_REPR = reprlib.Repr()  # (Python 3.11's Repr takes no arguments)
_REPR.maxlevel, _REPR.maxstring, _REPR.maxlong, _REPR.maxother = 3, 60, 40, 60


def shown(value: Any) -> str:
    """``repr(value)`` on one line, cut to :data:`MAX_SHOWN` characters (containers are cut
    while they are written, so that a huge nested value costs no more than a small one)."""
    text = " ".join(_REPR.repr(value).split())
    return text if len(text) <= MAX_SHOWN else text[:MAX_SHOWN - 3] + "..."


def _interval(low: float, high: float, low_open: bool, unit: str) -> str:
    text = f"{'(' if low_open else '['}{low:g}, {high:g}]"
    return f"{text} {unit}" if unit else text


def is_real(value: Any) -> bool:
    """Whether ``value`` is a real number (Python's or NumPy's), a bool not counted."""
    return isinstance(value, Real) and not isinstance(value, bool)


def check_number(name: str, value: Any, low: float, high: float, unit: str = "", *,
                 low_open: bool = False, note: str = "") -> float:
    """``value`` as a float if it is a finite real number in [low, high] (``low_open``: in
    (low, high]), in ``unit``; else ValueError, one line: ``{name} must be a finite number in
    [low, high] unit ({note}), got {value}``."""
    number = float(value) if is_real(value) else math.nan
    above_low = number > low if low_open else number >= low
    if not (math.isfinite(number) and above_low and number <= high):
        extra = f" ({note})" if note else ""
        raise ValueError(f"{name} must be a finite number in "
                         f"{_interval(low, high, low_open, unit)}{extra}, got {shown(value)}")
    return number


def check_integer(name: str, value: Any, low: int, high: int, unit: str = "") -> int:
    """``value`` as an int if it is a whole number (an int, or a float of a whole value, as
    YAML may give) in [low, high]; else ValueError, one line naming ``name`` and the value."""
    whole = (isinstance(value, Integral) and not isinstance(value, bool)) or (
        is_real(value) and float(value).is_integer())
    if not (whole and low <= int(value) <= high):
        raise ValueError(f"{name} must be an integer in {_interval(low, high, False, unit)}, "
                         f"got {shown(value)}")
    return int(value)


def check_flag(name: str, value: Any) -> bool:
    """``value`` if it is a bool (Python's or NumPy's); else ValueError naming ``name``."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be true or false, got {shown(value)}")
    return bool(value)


def check_vector(name: str, value: Any, size: int, low: float, high: float,
                 unit: str = "") -> tuple[float, ...]:
    """``value`` as a tuple of ``size`` floats, each finite in [low, high] ``unit``; else
    ValueError, one line naming ``name`` and the value."""
    entries = tuple(value) if isinstance(value, Sequence) and not isinstance(value, str) else ()
    if hasattr(value, "shape") and getattr(value, "ndim", 0) == 1:
        entries = tuple(value.tolist())
    if len(entries) != size or not all(is_real(v) and math.isfinite(float(v))
                                       and low <= float(v) <= high for v in entries):
        raise ValueError(f"{name} must be {size} finite numbers in "
                         f"{_interval(low, high, False, unit)}, got {shown(value)}")
    return tuple(float(v) for v in entries)


def check_range(name: str, value: Any, low: float, high: float, unit: str = ""
                ) -> tuple[float, float]:
    """``value`` as a (low, high) pair of floats within [low, high] ``unit``, the first not
    above the second (a range to draw from); else ValueError naming ``name`` and the value."""
    try:
        first, second = check_vector(name, value, 2, low, high, unit)
    except ValueError:
        first, second = math.nan, math.nan
    if not first <= second:
        raise ValueError(f"{name} must be a (low, high) range within "
                         f"{_interval(low, high, False, unit)}, got {shown(value)}")
    return first, second


def check_entry_name(caller: str, name: Any) -> str:
    """``name`` for a registry entry: a non-empty string; else a ValueError of one line naming
    ``caller`` (``register_task``, ...)."""
    if not (isinstance(name, str) and name):
        raise ValueError(f"{caller}: the name must be a non-empty string, got {shown(name)}")
    return name


def is_new_entry(caller: str, kind: str, table: dict, name: str, entry: Any) -> bool:
    """Whether ``entry`` is still to be put in ``table`` under ``name``: False where it is there
    already (registering it again is no change); a ValueError of one line where the name is
    taken by another entry (``kind``: what the table holds, for the message)."""
    if table.get(name) is entry:
        return False
    if name in table:
        taken = getattr(table[name], "__name__", shown(table[name]))
        raise ValueError(f"{caller}: {kind} name {name!r} is taken (by {taken}); choose "
                         "another name")
    return True


def adopt_name(caller: str, cls: Any, name: str) -> None:
    """Give ``cls`` the registered ``name`` as its ``name`` attribute (what its messages say),
    unless it sets another of its own: then a ValueError of one line."""
    if "name" in vars(cls) and cls.name != name:
        raise ValueError(f"{caller}({name!r}, {cls.__name__}): the class is named "
                         f"{cls.name!r}; register it under that name or drop its own")
    cls.name = name
