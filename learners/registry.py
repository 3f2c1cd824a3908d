"""Every learner by name: :data:`LEARNERS`, the package's and the registered ones;
``make_learner(name, env_id, env_kwargs, params, seed, logger)``, which refuses an env the
learner cannot drive (:data:`~animat.learners.validation.DRIVES`).

A new learner is a :class:`~animat.learners.base.Learner` subclass, in the package or in the
user's own module, registered by name with :func:`register_learner`
(``animat.learners.register_learner``): a config's ``learner.name`` then names it, in the
process that registered it (docs/tutorials/extending.md).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import TypeVar, overload

from animat.envs.checks import adopt_name, check_entry_name, is_new_entry, shown

from .base import Learner
from .blackbox import AnnealingLearner, CMAESLearner
from .logger import Logger
from .macro import MacroLearner
from .ppo.learner import PPOLearner
from .scorers.handmc import HandMCLearner
from .scorers.living_world import BehavioursLearner
from .scorers.pursuit import ActiveVisionLearner
from .scorers.steering import SteeringLearner
from .skills.basic_training import BasicTrainingLearner
from .skills.stunt_learner import CoordinateStuntTableLearner, StuntTableLearner
from .skills.stunt_trigger import TriggeredMacroLearner
from .stroke import StrokeCMAESLearner, StrokeLearner
from .switching import CoordinateSwitchingLearner, SwitchingLearner
from .validation import ALL_ENVS, DRIVES, check_drives

LEARNERS: dict[str, type[Learner]] = {
    cls.name: cls for cls in (AnnealingLearner, CMAESLearner, PPOLearner, HandMCLearner,
                              BasicTrainingLearner, MacroLearner, ActiveVisionLearner,
                              BehavioursLearner, StrokeLearner, StrokeCMAESLearner,
                              SteeringLearner, SwitchingLearner,
                              CoordinateSwitchingLearner, StuntTableLearner,
                              CoordinateStuntTableLearner, TriggeredMacroLearner)
}
L = TypeVar("L", bound=type[Learner])


def make_learner(name: str, env_id: str, env_kwargs: dict | None = None,
                 params: dict | None = None, seed: int = 0,
                 logger: Logger | None = None) -> Learner:
    """The learner called ``name``; ValueError naming the choices for an unknown one, or what
    it drives for an env it cannot (:func:`check_drives`)."""
    if name not in LEARNERS:
        raise ValueError(f"unknown learner {name!r}; choose one of {sorted(LEARNERS)}")
    check_drives(name, env_id)
    return LEARNERS[name](env_id, env_kwargs, params, seed, logger)


@overload
def register_learner(name: str, cls: None = None) -> Callable[[L], L]: ...
@overload
def register_learner(name: str, cls: L) -> L: ...
def register_learner(name: str, cls=None):
    """Register ``cls``, a subclass of :class:`~animat.learners.base.Learner`, as the learner
    ``name``: :func:`make_learner`, a config's ``learner.name`` and the launcher
    (``animat.experiments.run_experiment``) take it in this process from then on. It drives
    every env of :data:`animat.envs.registration.ENVS` (the package's and those registered with
    :func:`animat.envs.register_env`); its constructor may refuse others in one line.

    A plain call, ``register_learner("random_search", RandomSearch)``, or a decorator,
    ``@register_learner("random_search")`` over the class; either returns the class. A class
    that sets no ``name`` of its own is given this one (what its hyperparameters and messages
    say). Refused with a ValueError of one line: a name that is not a non-empty string, a name
    already taken by another class (the same class registered again is no change), an object
    that is not a ``Learner`` subclass, a class that does not implement ``learn``, a class
    whose own ``name`` is another.
    """
    check_entry_name("register_learner", name)
    if cls is None:
        return lambda given: register_learner(name, given)
    if not is_new_entry("register_learner", "learner", LEARNERS, name, cls):
        return cls
    if not (isinstance(cls, type) and issubclass(cls, Learner)):
        raise ValueError(f"register_learner({name!r}, ...): not a subclass of "
                         f"animat.learners.base.Learner: {shown(cls)}")
    if inspect.isabstract(cls):
        missing = sorted(getattr(cls, "__abstractmethods__", ()))
        raise ValueError(f"register_learner({name!r}, {cls.__name__}): it does not implement "
                         f"{', '.join(missing)}")
    adopt_name("register_learner", cls, name)
    LEARNERS[name] = cls
    DRIVES[name] = (ALL_ENVS, "this project's envs")
    return cls
