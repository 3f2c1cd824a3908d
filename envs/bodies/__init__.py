"""The bodies an env can be given by name: ``body="fish"`` or any
:class:`~animat.envs.bodies.spec.BodySpec` (a body is data: nodes, masses, elements, muscles,
faces, fins, in SI units).

A new animal is a function that builds a ``BodySpec`` (like :mod:`animat.envs.bodies.fish`),
in the package or in the user's own module, registered by name with :func:`register_body`
(``animat.envs.register_body``; the walk-through is docs/tutorials/extending.md); a body made
in a script or a test may also be passed as the spec itself. :data:`BODIES` is the table of
bodies by name, the package's and the registered ones.
May import :mod:`animat.envs.checks` only (level 1 of docs/architecture.md).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import overload

from ..checks import check_entry_name, is_new_entry, shown
from .dolphin import dolphin_body
from .fish import fish_body
from .spec import BodySpec

BodyFactory = Callable[[], BodySpec]
BODIES: dict[str, BodyFactory] = {"fish": fish_body, "dolphin": dolphin_body}


def make_body(body: str | BodySpec | None) -> BodySpec:
    """The body a name stands for (``None``: the fish), or ``body`` itself if it is a spec."""
    if isinstance(body, BodySpec):
        return body
    name = "fish" if body is None else body
    if not (isinstance(name, str) and name in BODIES):
        raise ValueError(f"unknown body {shown(name)}; choose one of {sorted(BODIES)} or pass "
                         "a BodySpec")
    spec = BODIES[name]()
    if not isinstance(spec, BodySpec):
        raise ValueError(f"body {name!r}: its factory returned {shown(spec)}, not a BodySpec")
    return spec


@overload
def register_body(name: str, factory: None = None) -> Callable[[BodyFactory], BodyFactory]: ...
@overload
def register_body(name: str, factory: BodyFactory) -> BodyFactory: ...
def register_body(name: str, factory: BodyFactory | None = None):
    """Register ``factory`` (a function of no arguments returning a
    :class:`~animat.envs.bodies.spec.BodySpec`) as the body ``name``, so that any env takes
    ``body=name`` (``gym.make("Animat/FishSwim-v0", body=name)``, a config's ``env.kwargs``).

    A plain call, ``register_body("eel", eel_body)``, or a decorator, ``@register_body("eel")``
    over the factory; either returns the factory. The factory is called once here, and each
    time an env is made of the name (a new spec each time). Refused with a ValueError of one
    line: a name that is not a non-empty string, a name already taken by another factory (the
    same factory registered again is no change), a factory that is not callable or does not
    return a ``BodySpec``.
    """
    check_entry_name("register_body", name)
    if factory is None:
        return lambda given: register_body(name, given)
    if not is_new_entry("register_body", "body", BODIES, name, factory):
        return factory
    if not callable(factory):
        raise ValueError(f"register_body({name!r}, ...): the factory must be a function "
                         f"returning a BodySpec, got {shown(factory)}")
    spec = factory()
    if not isinstance(spec, BodySpec):
        raise ValueError(f"register_body({name!r}, ...): the factory returned {shown(spec)}, "
                         "not a BodySpec")
    BODIES[name] = factory
    return factory
