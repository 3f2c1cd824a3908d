"""What the two Gymnasium shells over a fish batch share (:class:`~animat.envs.core.env.BodyEnv`
and :class:`~animat.envs.core.env.BodyVectorEnv`) beside the batch they build from their
arguments (:mod:`animat.envs.core.env_args`): their public surface (:class:`PublicSurface`),
their action space, the third-person renderer, and the checks of their render mode, autoreset
mode, seeds and saved random generators.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode

from ..bodies.spec import BodySpec
from ..physics.system import System
from ..render.camera import BodyRenderer
from ..render.seaworld import SeaWorldRenderer
from ..tasks.base import Task
from .batch import BodyBatch


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
