"""What every task is: :class:`Task` (its terms as pure functions on batched arrays), the
:class:`World` it reads, how an episode is summed up (:class:`EpisodeSummary`), and the
geometry helpers the tasks share.

A task supplies the paper's trajectory term E_v (Eq. 1), its own metrics and its part of the
observation, each a function of the :class:`World` of B bodies (the one API, the same for every
task): ``terms(world, last) -> (e_v (B,), metrics {name: (B,)}, memory (B, M))`` and
``observe(world) -> (B, obs_size)``; and its default episode length, how an episode is summed
up (:class:`EpisodeSummary`) and the hand-designed motor controller that solves it. A new task
is one class (e.g. :mod:`animat.envs.tasks.locomotion`) and one line in
:data:`animat.envs.tasks.TASKS`. Distances and speeds are reported in body lengths (BL) and
BL/s, angles in degrees.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .start import POINT_START, StartSpread


def heading_yaw(frames: np.ndarray) -> np.ndarray:
    """(B,) yaw of the forward vector about +z, rad (0: +x, positive: to the left)."""
    return np.arctan2(frames[:, 0, 1], frames[:, 0, 0])


def wrap_angle(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped to [-pi, pi)."""
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


def along_start_heading(vectors: np.ndarray, start_yaw: np.ndarray) -> np.ndarray:
    """(B,) the component of world-frame ``vectors`` (B, 3) along each episode's start heading,
    the horizontal unit vector at yaw ``start_yaw`` (B,) rad (``World.start_yaw``)."""
    return vectors[:, 0] * np.cos(start_yaw) + vectors[:, 1] * np.sin(start_yaw)


def from_start_frame(vectors: np.ndarray, start_yaw: np.ndarray) -> np.ndarray:
    """(B, 3) vectors given in each episode's start frame (x along its start heading, y to its
    left, z up) in the world frame: turned by ``start_yaw`` (B,) rad about +z."""
    c, s = np.cos(start_yaw), np.sin(start_yaw)
    x, y = vectors[:, 0], vectors[:, 1]
    return np.stack([x * c - y * s, x * s + y * c, vectors[:, 2]], axis=1)


def world_to_body(vectors: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """(B, 3) world-frame vectors expressed in each body frame (forward, left, up)."""
    return np.einsum("bij,bj->bi", frames, vectors)


@dataclass(frozen=True, slots=True, kw_only=True)
class World:
    """Everything a task may read of B bodies' current state, built by keyword
    (:meth:`animat.envs.core.batch.BodyBatch.world`); the arrays are the core's own: a task
    reads them, and changes only the copy of ``memory`` it returns.

    ``com`` (B, 3) the centre of mass relative to each episode's start, m; ``com_vel`` (B, 3)
    m/s; ``frames`` (B, 3, 3) rows forward, left, up; ``targets`` (B, T) the episode's
    parameters (:meth:`Task.sample`); ``length`` the body length, m; ``position`` (B, 3) the
    centre of mass in the world frame, m; ``x``, ``v`` (B, N, 3) the nodes, m and m/s;
    ``splash`` (B,) the last env step's splash, kg m/s; ``memory`` (B, M) the task's episode
    memory; ``ball`` (B, 6) and ``touch`` (B, 3) (:class:`animat.envs.core.state.BodyState`);
    ``surface_z`` m; ``body`` the ``BodySpec``; ``dt`` the env step, s; ``start_yaw`` (B,)
    the yaw of each episode's start heading, rad (:mod:`animat.envs.tasks.start`: the tasks
    measure headings, speeds and goals from it).
    """

    com: np.ndarray
    com_vel: np.ndarray
    frames: np.ndarray
    targets: np.ndarray
    length: float
    position: np.ndarray
    x: np.ndarray
    v: np.ndarray
    splash: np.ndarray
    memory: np.ndarray
    ball: np.ndarray
    touch: np.ndarray
    surface_z: float
    body: Any
    dt: float
    start_yaw: np.ndarray


Terms = tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]
"""What :meth:`Task.terms` returns: E_v (B,), the metrics (B,) each by name, the memory (B, M)."""


class Task:
    """Base class: a task has ``target_size`` parameters per episode, ``obs_size`` extra
    observation entries, a ``default_duration`` (s) and episode metrics: the per-step metrics
    named in ``mean_metrics`` averaged over the episode, and what :meth:`final_metrics` reads
    off its last step.

    Every task implements :meth:`terms` (E_v, metrics and memory from the :class:`World`) and,
    if ``obs_size`` > 0, :meth:`observe`. A task may keep ``memory_size`` numbers per episode
    (from :meth:`initial_memory`, updated by :meth:`terms`; the stunts,
    :mod:`animat.envs.tasks.stunts`), start the body elsewhere (:meth:`place`) and put a beach
    ball in the world (``ball``, a :class:`animat.envs.physics.ball.BallParams`). Its episodes
    start from ``start_spread`` about the placement (:mod:`animat.envs.tasks.start`)."""

    name = "task"
    target_size = 0
    obs_size = 0
    memory_size = 0
    default_duration = 10.0
    mean_metrics: tuple[str, ...] = ()
    ball = None
    # the documented spread of its episodes' starts (:mod:`animat.envs.tasks.start`)
    start_spread: ClassVar[StartSpread] = POINT_START

    def __post_init__(self) -> None:
        """Checks of the task's arguments: none here. Every task's ``__post_init__`` calls
        its parent's first (``super().__post_init__()``), so that a task adds to the checks
        it inherits and never drops one; each refusal is a ValueError of one line naming the
        argument (:mod:`animat.envs.checks`)."""
        return None

    def check_start_spread(self, spread: StartSpread) -> None:
        """A ValueError of one line if this task cannot start from ``spread`` (the default
        takes any)."""
        return None

    def place(self, body) -> np.ndarray:
        """(N, 3) the body's start (``body`` a ``BodySpec``), before the reset noise: the rest
        shape where it lies."""
        return body.rest_positions

    def start_velocity(self, body) -> np.ndarray:
        """(N, 3) the nodes' velocity at the start, m/s (``body`` a ``BodySpec``): at rest."""
        return np.zeros_like(body.rest_positions)

    def initial_memory(self) -> np.ndarray:
        """(memory_size,) the episode memory at a reset."""
        return np.zeros(self.memory_size)

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """(target_size,) parameters of a new episode."""
        return np.zeros(self.target_size)

    def observe(self, world: World) -> np.ndarray:
        """(B, obs_size) the task's part of the observation (none by default)."""
        return np.zeros((world.frames.shape[0], self.obs_size))

    def terms(self, world: World, last: np.ndarray) -> Terms:
        """E_v (B,) (its unit the task's), the metrics (B,) each by name, and the episode
        memory (B, M) after this step (``world.memory`` itself for a task without memory, else
        an updated copy); ``last`` (B,) bool marks an episode's last step."""
        raise NotImplementedError

    def final_metrics(self, last: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Episode metrics (B,) each read off the info of the episode's last step."""
        return {}

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"
                        ) -> Callable[[np.ndarray], np.ndarray]:
        """The hand-designed motor controller for this task, calibrated for the water's
        ``model`` (``Water.model``; :func:`animat.envs.registration.water_of` reads an env's):
        ``t (s) -> u (..., 6)``."""
        raise ValueError(f"no hand-designed motor controller for task {self.name!r}")


class EpisodeSummary:
    """Accumulates a task's episode metrics over the steps of B episodes run in lockstep:
    the means of ``task.mean_metrics`` (prefixed by nothing: ``speed_bl_per_s`` is the mean
    swimming speed) and ``task.final_metrics`` of the last step."""

    def __init__(self, task: Task, num_envs: int) -> None:
        self.task, self.steps = task, 0
        self.sums = {k: np.zeros(num_envs) for k in task.mean_metrics}
        self.last: dict[str, np.ndarray] = {}

    def update(self, info: dict[str, np.ndarray]) -> None:
        self.steps += 1
        self.last = info
        for key in self.sums:
            self.sums[key] = self.sums[key] + info[key]

    def summary(self) -> dict[str, np.ndarray]:
        means = {k: v / max(self.steps, 1) for k, v in self.sums.items()}
        return {**means, **self.task.final_metrics(self.last)}


class SingleEpisodeSummary:
    """:class:`EpisodeSummary` of one episode in a single env (``info`` of scalars): the
    summary as floats (the interface of
    :class:`animat.envs.world.pursuit.summary.PursuitSummary`)."""

    def __init__(self, task: Task) -> None:
        self.batch = EpisodeSummary(task, 1)

    def update(self, info: dict[str, Any]) -> None:
        self.batch.update(info)

    def summary(self) -> dict[str, float]:
        return {k: float(np.asarray(v).reshape(-1)[0]) for k, v in self.batch.summary().items()}
