"""The paper's learners (simulated annealing, FFT abstraction, basic training, macro
controllers) and the baselines (CMA-ES, PPO), by name in :mod:`animat.learners.registry`.

Rooms: :mod:`.optimizers`, :mod:`.controllers`, :mod:`.ppo`, :mod:`.scorers`, :mod:`.storage`,
:mod:`.skills`; beside them the interface (:mod:`.base`), the black-box loop and the learners on
it. May import :mod:`animat.envs` (its public names); never :mod:`animat.experiments`.

:func:`register_learner` adds a user's learner by name from their own module
(docs/tutorials/extending.md); it, :data:`~animat.learners.registry.LEARNERS` and
:func:`~animat.learners.registry.make_learner` are imported from :mod:`.registry` when first
asked for, so that importing one learner's module does not import them all.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .registry import LEARNERS, make_learner, register_learner

__all__ = ["LEARNERS", "make_learner", "register_learner"]


def __getattr__(name: str) -> Any:
    """The names of ``__all__``, from :mod:`.registry` (imported when first asked for)."""
    if name in __all__:
        from . import registry

        return getattr(registry, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
