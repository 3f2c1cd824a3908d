"""Locomotion tasks: what a fish is asked to do, as pure functions on batched arrays.

A task supplies the paper's trajectory term E_v (Eq. 1) and its own metrics, from the body's
centre of mass, its velocity and its frame; its default episode length; how an episode
is summed up (:class:`EpisodeSummary`); and the hand-designed motor controller that solves
it. A new task is one class here and one line in :data:`TASKS`. Shapes: ``com`` (B, 3) the
centre of mass relative to where the episode started, m; ``com_vel`` (B, 3) m/s;
``frames`` (B, 3, 3) rows forward, left, up; ``targets`` (B, T) the task's per-episode
parameters drawn by :meth:`Task.sample`; ``length`` the body length (m). Distances and speeds
are reported in body lengths (BL) and BL/s, angles in degrees.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields, is_dataclass
from typing import Any, NamedTuple

import numpy as np

from animat.envs.checks import check_number, check_range, shown
from animat.envs.motor import swim_mc, turn_mc


def heading_yaw(frames: np.ndarray) -> np.ndarray:
    """(B,) yaw of the forward vector about +z, rad (0: +x, positive: to the left)."""
    return np.arctan2(frames[:, 0, 1], frames[:, 0, 0])


def wrap_angle(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped to [-pi, pi)."""
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


def world_to_body(vectors: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """(B, 3) world-frame vectors expressed in each body frame (forward, left, up)."""
    return np.einsum("bij,bj->bi", frames, vectors)


class World(NamedTuple):
    """Everything a task may read of B bodies' current state (the arrays are the core's own:
    a task reads them, and changes only the copy of ``memory`` it returns).

    ``com`` (B, 3) relative to each episode's start, m; ``com_vel`` (B, 3) m/s; ``frames``
    (B, 3, 3); ``targets`` (B, T); ``length`` m; ``position`` (B, 3) the centre of mass in the
    world frame, m; ``x``, ``v`` (B, N, 3) the nodes; ``splash`` (B,) the last env step's
    splash, kg m/s; ``memory`` (B, M) the task's episode memory; ``ball`` (B, 6) and
    ``touch`` (B, 3) (:class:`animat.envs.fish_core.FishState`); ``surface_z`` m; ``body`` the
    ``BodySpec``; ``dt`` the env step, s.
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


class Task:
    """Base class: a task has ``target_size`` parameters per episode, ``obs_size`` extra
    observation entries, a ``default_duration`` (s) and episode metrics: the per-step metrics
    named in ``mean_metrics`` averaged over the episode, and what :meth:`final_metrics` reads
    off its last step.

    Tasks that need more than the centre of mass and the frame (the dolphin's stunts,
    :mod:`animat.envs.stunts`) override :meth:`world_terms` and :meth:`world_observe`, which
    see the whole :class:`World`, keep ``memory_size`` numbers per episode (from
    :meth:`initial_memory`), may start the body elsewhere (:meth:`place`) and may put a beach
    ball in the world (``ball``, a :class:`animat.envs.physics.ball.BallParams`)."""

    name = "task"
    target_size = 0
    obs_size = 0
    memory_size = 0
    default_duration = 10.0
    mean_metrics: tuple[str, ...] = ()
    ball = None

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

    def world_terms(self, world: World, last: np.ndarray):
        """E_v (B,), metrics (B,) each, and the updated memory (B, M), from the world."""
        e_v, metrics = self.terms(world.com, world.com_vel, world.frames, world.targets,
                                  world.length, last)
        return e_v, metrics, world.memory

    def world_observe(self, world: World) -> np.ndarray:
        """(B, obs_size) task part of the observation, from the world."""
        return self.observe(world.com, world.com_vel, world.frames, world.targets,
                            world.length)

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """(target_size,) parameters of a new episode."""
        return np.zeros(self.target_size)

    def observe(self, com, com_vel, frames, targets, length) -> np.ndarray:
        """(B, obs_size) task part of the observation."""
        return np.zeros((com.shape[0], self.obs_size))

    def terms(self, com, com_vel, frames, targets, length, last):
        """E_v (B,) and a dict of metrics (B,) each; ``last`` (B,) marks an episode's last step."""
        raise NotImplementedError

    def final_metrics(self, last: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Episode metrics (B,) each read off the info of the episode's last step."""
        return {}

    def hand_controller(self, speed: float = 1.0) -> Callable[[np.ndarray], np.ndarray]:
        """The hand-designed motor controller for this task: ``t (s) -> u (..., 6)``."""
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


class SingleEpisodeSummary(EpisodeSummary):
    """:class:`EpisodeSummary` of one episode in a single env (``info`` of scalars): the
    summary as floats (the interface of :class:`animat.envs.pursuit.PursuitSummary`)."""

    def __init__(self, task: Task) -> None:
        super().__init__(task, 1)

    def summary(self) -> dict[str, float]:
        return {k: float(np.asarray(v).reshape(-1)[0]) for k, v in super().summary().items()}


@dataclass
class SwimTask(Task):
    """Swim forward. u is the swimming speed: the centre of mass's velocity along the start
    heading (+x, where every episode starts facing), BL/s, so that its mean over an episode is
    the net displacement along the start heading per second: a fish that veers or circles
    scores only what it makes good (the paper's E_v, "deviation from desired speed", holds as
    is). Without ``target_speed`` E_v = -u
    (faster is better); with it (in [0, 10] BL/s) E_v = (u - target_speed)^2. Metrics:
    ``speed_bl_per_s`` (u), ``distance_bl`` (net horizontal distance from the start, BL),
    ``heading_deg``."""

    target_speed: float | None = None
    name = "swim"
    default_duration = 10.0
    mean_metrics = ("speed_bl_per_s",)

    def __post_init__(self) -> None:
        if self.target_speed is not None:
            check_number("target_speed", self.target_speed, 0.0, 10.0, "BL/s")
        self.obs_size = 0 if self.target_speed is None else 1

    def observe(self, com, com_vel, frames, targets, length):
        if self.target_speed is None:
            return np.zeros((com.shape[0], 0))
        return np.full((com.shape[0], 1), float(self.target_speed))

    def terms(self, com, com_vel, frames, targets, length, last):
        yaw = heading_yaw(frames)
        speed = com_vel[:, 0] / length
        if self.target_speed is None:
            e_v = -speed
        else:
            e_v = (speed - float(self.target_speed)) ** 2
        return e_v, {"speed_bl_per_s": speed, "heading_deg": np.degrees(yaw),
                     "distance_bl": np.hypot(com[:, 0], com[:, 1]) / length}

    def hand_controller(self, speed: float = 1.0):
        """The swim-MC at ``speed`` in [0, 1], ease-in included."""
        return lambda t: swim_mc(speed, t)


@dataclass
class TurnTask(Task):
    """Turn by ``angle_deg`` (in (0, 180]) to the left (``direction="left"``) or right. E_v is
    the squared heading error (rad^2); observation: sin and cos of the heading error."""

    angle_deg: float = 90.0
    direction: str = "left"
    name = "turn"
    obs_size = 2
    default_duration = 5.0

    def __post_init__(self) -> None:
        if self.direction not in ("left", "right"):
            raise ValueError(f"direction must be 'left' or 'right', got {self.direction!r}")
        check_number("angle_deg", self.angle_deg, 0.0, 180.0, "deg", low_open=True)

    @property
    def target_yaw(self) -> float:
        sign = 1.0 if self.direction == "left" else -1.0
        return sign * np.radians(float(self.angle_deg))

    def _error(self, frames):
        return wrap_angle(heading_yaw(frames) - self.target_yaw)

    def observe(self, com, com_vel, frames, targets, length):
        error = self._error(frames)
        return np.stack([np.sin(error), np.cos(error)], axis=1)

    def terms(self, com, com_vel, frames, targets, length, last):
        error = self._error(frames)
        return error**2, {"heading_deg": np.degrees(heading_yaw(frames)),
                          "heading_error_deg": np.degrees(error)}

    def final_metrics(self, last):
        """``final_heading_error_deg``: the absolute heading error at the end."""
        return {"final_heading_error_deg": np.abs(last["heading_error_deg"])}

    def hand_controller(self, speed: float = 1.0):
        """The turn-MC for this angle and direction (``speed`` is not used)."""
        angle, left = np.radians(float(self.angle_deg)), self.direction == "left"
        return lambda t: turn_mc(angle, t, left)


@dataclass
class ReachTask(Task):
    """Reach a goal point. Each episode's goal lies ``distance_bl`` body lengths from the start,
    at a bearing drawn uniformly from ``bearing_deg`` (0: straight ahead, 180: behind, positive:
    left), at the start depth. E_v = distance to the goal (BL) at every step, plus
    ``final_weight`` times the distance on the episode's last step. Observation: the goal in
    the body frame, BL. Ranges: ``distance_bl`` within [0, 1000] BL, ``bearing_deg`` within
    [-360, 360] deg (each low <= high), ``final_weight`` in [0, 1000]."""

    distance_bl: tuple[float, float] = (2.0, 4.0)
    bearing_deg: tuple[float, float] = (-180.0, 180.0)
    final_weight: float = 20.0
    name = "reach"
    target_size = 3
    obs_size = 3
    default_duration = 20.0

    def __post_init__(self) -> None:
        check_range("distance_bl", self.distance_bl, 0.0, 1000.0, "BL")
        check_range("bearing_deg", self.bearing_deg, -360.0, 360.0, "deg")
        check_number("final_weight", self.final_weight, 0.0, 1000.0)

    def sample(self, rng):
        distance = rng.uniform(*self.distance_bl)
        bearing = np.radians(rng.uniform(*self.bearing_deg))
        return np.array([distance * np.cos(bearing), distance * np.sin(bearing), 0.0])

    def observe(self, com, com_vel, frames, targets, length):
        return world_to_body(targets * length - com, frames) / length

    def terms(self, com, com_vel, frames, targets, length, last):
        distance = np.linalg.norm(targets * length - com, axis=1) / length
        e_v = distance + np.where(last, float(self.final_weight) * distance, 0.0)
        return e_v, {"distance_bl": distance}

    def final_metrics(self, last):
        """``final_distance_bl``: the distance to the goal at the end."""
        return {"final_distance_bl": np.asarray(last["distance_bl"])}


TASKS: dict[str, type[Task]] = {"swim": SwimTask, "turn": TurnTask, "reach": ReachTask}


def make_task(name: str, **kwargs) -> Task:
    """The task ``name`` with its keyword arguments; a ValueError of one line for an unknown
    name or argument (each task checks its arguments' values)."""
    if not (isinstance(name, str) and name in TASKS):
        raise ValueError(f"unknown task {shown(name)}; choose one of {sorted(TASKS)}")
    known = sorted(f.name for f in fields(TASKS[name])) if is_dataclass(TASKS[name]) else []
    unknown = sorted(map(str, set(kwargs) - set(known)))
    if known and unknown:
        raise ValueError(f"task {name!r} has no argument(s) {unknown}; its arguments: {known}")
    return TASKS[name](**kwargs)
