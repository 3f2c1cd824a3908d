"""What the two Gymnasium shells over a fish batch share (:class:`~animat.envs.core.env.BodyEnv`
and :class:`~animat.envs.core.env.BodyVectorEnv`): the batch they build from their arguments
(:func:`make_core`), their public surface (:class:`PublicSurface`), their action space, the
third-person renderer, and the checks of their render mode, autoreset mode, seeds and saved
random generators.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode

from ..bodies import make_body
from ..bodies.spec import BodySpec
from ..checks import shown
from ..physics.system import System
from ..render.camera import BodyRenderer
from ..render.seaworld import SeaWorldRenderer
from ..tasks import make_task
from ..tasks.base import Task
from .batch import BodyBatch
from .reward import RewardWeights


def merged_water(water: dict | None, base_water: dict | None) -> dict | None:
    """The Water fields an env of these arguments swims in: ``water``'s over ``base_water``'s
    (a registered world's, the dolphin's pool), or None (the default water); a ValueError of
    one line for either that is not a dict."""
    for name, value in (("water", water), ("base_water", base_water)):
        if value is not None and not isinstance(value, dict):
            raise ValueError(f"{name} must be a dict of Water fields, got {shown(value)}")
    return {**(base_water or {}), **(water or {})} or None


def make_core(num_envs: int, task: str, task_kwargs: dict, body: str | BodySpec | None,
              duration: float | None, physics_dt: float, frame_skip: int,
              reset_noise_scale: float, reward_weights: RewardWeights | dict | None,
              water: dict | None, fins: bool, base_water: dict | None = None,
              start_spread: dict | str | None = None, integrator: str = "explicit"
              ) -> BodyBatch:
    """The batch of an env's arguments: ``water`` changes fields of ``base_water``; the task
    by name with ``task_kwargs``; ``duration`` None is the task's; ``start_spread`` over the
    task's own."""
    water = merged_water(water, base_water)
    task_object = make_task(task, **task_kwargs)
    weights = RewardWeights.from_value(reward_weights)
    return BodyBatch(num_envs, task_object, body=make_body(body), water=water,
                     physics_dt=physics_dt, frame_skip=frame_skip,
                     reset_noise_scale=reset_noise_scale,
                     duration=task_object.default_duration if duration is None else duration,
                     weights=weights, fins=fins, start_spread=start_spread,
                     integrator=integrator)


class PublicSurface:
    """What learners, demos and tests may read of a fish env (both kinds share it)."""

    core: BodyBatch

    @property
    def task(self) -> Task:
        return self.core.task

    @property
    def body(self) -> BodySpec:
        return self.core.body

    @property
    def system(self) -> System:
        """The frozen physics of the bodies (their masses, elements and water, and the arguments
        its kernels take, ``kernel_args``), e.g. for timing those kernels."""
        return self.core.system

    @property
    def episode_steps(self) -> int:
        """Env steps per episode (``duration / dt``)."""
        return self.core.episode_steps


def check_render_mode(render_mode: str | None) -> None:
    """ValueError unless ``render_mode`` is None or ``"rgb_array"``."""
    if render_mode not in (None, "rgb_array"):
        raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")


def make_renderer(core: BodyBatch):
    """The third-person view: beside the pool, with sky and surface, for a world with a water
    surface (:class:`~envs.render.seaworld.SeaWorldRenderer`); else behind and above the body."""
    surface = core.system.water.surface_z
    if np.isfinite(surface):
        return SeaWorldRenderer(core.body, core.ball, surface_z=surface)
    return BodyRenderer(core.body)


def render_row(renderer, core: BodyBatch, row: int) -> np.ndarray:
    """The frame of fish ``row`` (with the ball, in a sea world) by :func:`make_renderer`'s."""
    if isinstance(renderer, SeaWorldRenderer):
        return renderer.render(core.state.x[row], core.state.ball[row])
    return renderer.render(core.state.x[row])


def action_space_of(core: BodyBatch) -> gym.spaces.Box:
    """One fish's action space: ``Box(-1, 1, (action_size,), float32)``."""
    return gym.spaces.Box(-1.0, 1.0, (core.action_size,), np.float32)


def generator_from_state(state: dict) -> np.random.Generator:
    """A random generator continuing from ``state`` (a ``PCG64`` ``bit_generator.state``, the
    kind Gymnasium's seeding makes); ValueError when it is not one."""
    generator = np.random.Generator(np.random.PCG64())
    try:
        generator.bit_generator.state = state
    except (TypeError, ValueError, KeyError) as error:
        raise ValueError(f"not a PCG64 random generator's state ({error})") from None
    return generator


def parse_autoreset_mode(value: str | AutoresetMode) -> AutoresetMode:
    """The vector env's autoreset mode of ``"next_step"``, ``"same_step"`` or one of those two
    modes; ValueError for anything else."""
    names = {"next_step": AutoresetMode.NEXT_STEP, "same_step": AutoresetMode.SAME_STEP}
    if isinstance(value, AutoresetMode) and value in names.values():
        return value
    if value not in names:
        raise ValueError(f"autoreset_mode must be 'next_step' or 'same_step', got {value!r}")
    return names[value]


def sub_env_seeds(seed, num_envs: int) -> list | None:
    """The seeds of a vector env's ``reset(seed=...)``: None (keep the generators), an integer
    (sub-env i gets ``seed + i``) or a list of ``num_envs`` seeds."""
    if seed is None:
        return None
    if isinstance(seed, (int, np.integer)):
        return [int(seed) + i for i in range(num_envs)]
    if len(seed) != num_envs:
        raise ValueError(f"seed list must have {num_envs} entries, got {len(seed)}")
    return list(seed)
