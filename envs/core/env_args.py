"""A fish env's arguments as one typed object (:class:`BodyArgs`): what
:class:`~animat.envs.core.env.BodyEnv` and :class:`~animat.envs.core.env.BodyVectorEnv` build
their batch from (:func:`make_core`), and what the registry reads an id's clock, body, task,
water and start spread from without building the env (:mod:`animat.envs.registration`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any

from ..bodies import make_body
from ..bodies.spec import BodySpec
from ..checks import shown
from ..physics.system import DEFAULT_DT, System, Water
from ..tasks import make_task
from ..tasks.base import Task
from .arguments import check_arguments
from .batch import DEFAULT_FRAME_SKIP, BodyBatch
from .reward import RewardWeights

# what the single env takes beside the batch's arguments (BodyEnv's own, not the task's)
SHELL_ARGUMENTS = frozenset({"render_mode", "sensors"})


@dataclass(frozen=True)
class BodyArgs:
    """A fish env's batch by the names of its arguments (the table of
    :mod:`animat.envs.core.env`), the task's own in ``task_kwargs``; each is checked where it
    is used (:func:`make_core`, :meth:`clock`), so that a bad one is one line naming it."""

    task: str = "swim"
    body: str | BodySpec | None = None
    duration: float | None = None  # s; None: the task's
    physics_dt: float = DEFAULT_DT  # s
    frame_skip: int = DEFAULT_FRAME_SKIP
    water: dict | None = None
    fins: bool = False
    reset_noise_scale: float = 0.005  # BL
    reward_weights: RewardWeights | dict | None = None
    base_water: dict | None = None
    start_spread: dict | str | None = None
    integrator: str = "explicit"
    task_kwargs: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def of(cls, kwargs: dict[str, Any]) -> BodyArgs:
        """The arguments of a batch made with ``kwargs``: every name this class does not have
        is the task's."""
        named = {f.name for f in fields(cls)} - {"task_kwargs"}
        return cls(**{k: v for k, v in kwargs.items() if k in named},
                   task_kwargs={k: v for k, v in kwargs.items() if k not in named})

    @classmethod
    def of_single_env(cls, kwargs: dict[str, Any]) -> BodyArgs:
        """The arguments of ``gym.make(id, **kwargs)`` of a fish id: ``kwargs`` without the
        single env's own (:data:`SHELL_ARGUMENTS`)."""
        return cls.of({k: v for k, v in kwargs.items() if k not in SHELL_ARGUMENTS})

    def make_task(self) -> Task:
        return make_task(self.task, **self.task_kwargs)

    def merged_water(self) -> dict | None:
        return merged_water(self.water, self.base_water)

    def duration_of(self, task: Task) -> float:
        """The episode's length, s: ``duration``, or the task's own where None."""
        return task.default_duration if self.duration is None else self.duration

    def clock(self) -> tuple[float, int, float]:
        """(``physics_dt`` s, ``frame_skip``, the duration s) of the env, checked as the env
        checks them and in its order (the water's type, the task, the reward weights, the
        batch's numbers, the start spread, then the physics: the water's fields, the step's
        bound for the body, the integrator), without building it."""
        water = self.merged_water()
        task = self.make_task()
        RewardWeights.from_value(self.reward_weights)
        duration = self.duration_of(task)
        check_arguments(1, self.physics_dt, self.frame_skip, duration, self.reset_noise_scale,
                        self.fins, 0.0)
        task.check_start_spread(task.start_spread.over(self.start_spread))
        System(make_body(self.body), Water.from_dict(water), dt=self.physics_dt,
               integrator=self.integrator)
        return self.physics_dt, self.frame_skip, duration


def merged_water(water: dict | None, base_water: dict | None) -> dict | None:
    """The Water fields an env of these arguments swims in: ``water``'s over ``base_water``'s
    (a registered world's, the dolphin's pool), or None (the default water); a ValueError of
    one line for either that is not a dict."""
    for name, value in (("water", water), ("base_water", base_water)):
        if value is not None and not isinstance(value, dict):
            raise ValueError(f"{name} must be a dict of Water fields, got {shown(value)}")
    return {**(base_water or {}), **(water or {})} or None


def make_core(num_envs: int, args: BodyArgs) -> BodyBatch:
    """The batch of ``num_envs`` fish of ``args``: ``water`` changes fields of
    ``base_water``; the task by name with its kwargs; ``duration`` None is the task's;
    ``start_spread`` over the task's own."""
    water = args.merged_water()
    task = args.make_task()
    weights = RewardWeights.from_value(args.reward_weights)
    return BodyBatch(num_envs, task, body=make_body(args.body), water=water,
                     physics_dt=args.physics_dt, frame_skip=args.frame_skip,
                     reset_noise_scale=args.reset_noise_scale,
                     duration=args.duration_of(task),
                     weights=weights, fins=args.fins, start_spread=args.start_spread,
                     integrator=args.integrator)
