"""Every learner by name: ``make_learner(name, env_id, env_kwargs, params, seed, logger)``,
which refuses an env the learner cannot drive (:data:`~animat.learners.validation.DRIVES`)."""

from __future__ import annotations

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
from .stroke import StrokeCMAESLearner, StrokeLearner
from .switching import CoordinateSwitchingLearner, SwitchingLearner
from .validation import check_drives

LEARNERS: dict[str, type[Learner]] = {
    cls.name: cls for cls in (AnnealingLearner, CMAESLearner, PPOLearner, HandMCLearner,
                              BasicTrainingLearner, MacroLearner, ActiveVisionLearner,
                              BehavioursLearner, StrokeLearner, StrokeCMAESLearner,
                              SteeringLearner, SwitchingLearner,
                              CoordinateSwitchingLearner)
}


def make_learner(name: str, env_id: str, env_kwargs: dict | None = None,
                 params: dict | None = None, seed: int = 0,
                 logger: Logger | None = None) -> Learner:
    """The learner called ``name``; ValueError naming the choices for an unknown one, or what
    it drives for an env it cannot (:func:`check_drives`)."""
    if name not in LEARNERS:
        raise ValueError(f"unknown learner {name!r}; choose one of {sorted(LEARNERS)}")
    check_drives(name, env_id)
    return LEARNERS[name](env_id, env_kwargs, params, seed, logger)
