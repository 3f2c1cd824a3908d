"""Locomotion tasks of any body: swim (forward, or at a target speed), turn (by an angle,
left or right), reach (a goal point), each with the hand-designed motor controller that solves
it. Each implements the one task API (:class:`animat.envs.tasks.base.Task`: ``terms`` and
``observe`` of the :class:`~animat.envs.tasks.base.World`); shapes and units as there."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import check_number, check_range
from ..motor.fish import calibrated, swim_mc, turn_mc
from .base import Task, Terms, World, heading_yaw, world_to_body, wrap_angle


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

    def observe(self, world: World) -> np.ndarray:
        """(B, 1) the target speed, BL/s ((B, 0) without one)."""
        if self.target_speed is None:
            return np.zeros((world.com.shape[0], 0))
        return np.full((world.com.shape[0], 1), float(self.target_speed))

    def terms(self, world: World, last: np.ndarray) -> Terms:
        com, length = world.com, world.length
        yaw = heading_yaw(world.frames)
        speed = world.com_vel[:, 0] / length
        if self.target_speed is None:
            e_v = -speed
        else:
            e_v = (speed - float(self.target_speed)) ** 2
        return e_v, {"speed_bl_per_s": speed, "heading_deg": np.degrees(yaw),
                     "distance_bl": np.hypot(com[:, 0], com[:, 1]) / length}, world.memory

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"):
        """The swim-MC at ``speed`` in [0, 1], ease-in included, calibrated for ``model``."""
        swim = calibrated(model)[0]
        return lambda t: swim_mc(speed, t, swim)


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

    def _error(self, frames: np.ndarray) -> np.ndarray:
        """(B,) the heading error, rad, from the frames (B, 3, 3)."""
        return wrap_angle(heading_yaw(frames) - self.target_yaw)

    def observe(self, world: World) -> np.ndarray:
        """(B, 2) sine and cosine of the heading error."""
        error = self._error(world.frames)
        return np.stack([np.sin(error), np.cos(error)], axis=1)

    def terms(self, world: World, last: np.ndarray) -> Terms:
        error = self._error(world.frames)
        return error**2, {"heading_deg": np.degrees(heading_yaw(world.frames)),
                          "heading_error_deg": np.degrees(error)}, world.memory

    def final_metrics(self, last):
        """``final_heading_error_deg``: the absolute heading error at the end."""
        return {"final_heading_error_deg": np.abs(last["heading_error_deg"])}

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"):
        """The turn-MC for this angle and direction, calibrated for ``model`` (``speed`` is not
        used)."""
        angle, left = np.radians(float(self.angle_deg)), self.direction == "left"
        turn = calibrated(model)[1]
        return lambda t: turn_mc(angle, t, left, turn)


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

    def observe(self, world: World) -> np.ndarray:
        """(B, 3) the goal relative to the centre of mass in the body frame, BL."""
        length = world.length
        return world_to_body(world.targets * length - world.com, world.frames) / length

    def terms(self, world: World, last: np.ndarray) -> Terms:
        length = world.length
        distance = np.linalg.norm(world.targets * length - world.com, axis=1) / length
        e_v = distance + np.where(last, float(self.final_weight) * distance, 0.0)
        return e_v, {"distance_bl": distance}, world.memory

    def final_metrics(self, last):
        """``final_distance_bl``: the distance to the goal at the end."""
        return {"final_distance_bl": np.asarray(last["distance_bl"])}
