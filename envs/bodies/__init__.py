"""The bodies an env can be given by name: ``body="fish"`` or any
:class:`~animat.envs.bodies.spec.BodySpec` (a body is data: nodes, masses, elements, muscles,
faces, fins, in SI units).

A new animal is its own module that builds a ``BodySpec`` (like :mod:`animat.envs.bodies.fish`)
and one line in :data:`BODIES`; a body made in a script or a test is passed as the spec itself.
May import :mod:`animat.envs.checks` only (level 1 of docs/architecture.md).
"""

from __future__ import annotations

from collections.abc import Callable

from ..checks import shown
from .dolphin import dolphin_body
from .fish import fish_body
from .spec import BodySpec

BODIES: dict[str, Callable[[], BodySpec]] = {"fish": fish_body, "dolphin": dolphin_body}


def make_body(body: str | BodySpec | None) -> BodySpec:
    """The body a name stands for (``None``: the fish), or ``body`` itself if it is a spec."""
    if isinstance(body, BodySpec):
        return body
    name = "fish" if body is None else body
    if not (isinstance(name, str) and name in BODIES):
        raise ValueError(f"unknown body {shown(name)}; choose one of {sorted(BODIES)} or pass "
                         "a BodySpec")
    return BODIES[name]()
