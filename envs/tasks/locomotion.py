"""Locomotion tasks of any body: swim (forward, or at a target speed), turn (by an angle,
left or right), reach (a goal point), each with the hand-designed motor controller that solves
it. Each implements the one task API (:class:`animat.envs.tasks.base.Task`: ``terms`` and
``observe`` of the :class:`~animat.envs.tasks.base.World`); shapes and units as there."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import check_number, check_range, shown
from ..motor.fish import calibrated, swim_mc, turn_mc
from ..physics.observe import momenta
from .base import (
    Task,
    Terms,
    World,
    along_start_heading,
    from_start_frame,
    heading_yaw,
    world_to_body,
    wrap_angle,
)
from .start import FISH_START


@dataclass
class SwimTask(Task):
    """Swim forward. u is the swimming speed: the centre of mass's velocity along the start
    heading (``World.start_yaw``), BL/s, so that its mean over an episode is
    the net displacement along the start heading per second: a fish that veers or circles
    scores only what it makes good (the paper's E_v, "deviation from desired speed", holds as
    is). Without ``target_speed`` E_v = -u
    (faster is better); with it (in [0, 10] BL/s) E_v = (u - target_speed)^2. Metrics:
    ``speed_bl_per_s`` (u), ``distance_bl`` (net horizontal distance from the start, BL),
    ``heading_deg`` (from the start heading). Starts: :data:`~animat.envs.tasks.start.FISH_START`
    (as the turn and the reach)."""

    target_speed: float | None = None
    name = "swim"
    start_spread = FISH_START
    default_duration = 10.0
    mean_metrics = ("speed_bl_per_s",)

    def __post_init__(self) -> None:
        super().__post_init__()
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
        yaw = wrap_angle(heading_yaw(world.frames) - world.start_yaw)
        speed = along_start_heading(world.com_vel, world.start_yaw) / length
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


def yaw_rate(world: World) -> np.ndarray:
    """(B,) the body's yaw rate, rad/s (positive: to the left): its angular momentum about
    the vertical through its centre of mass over its moment of inertia about that line."""
    masses = world.body.masses
    _, momentum = momenta(world.x, world.v, masses, world.position)
    r = world.x[:, :, :2] - world.position[:, None, :2]
    return momentum[:, 2] / np.einsum("n,bnk->b", masses, r * r)


@dataclass
class TurnTask(Task):
    """Turn by ``angle_deg`` (in (0, 180]) from the start heading to the left
    (``direction="left"``) or right. E_v = ``path_weight`` e^2 + ``final_weight`` (e^2 +
    (``settle_s`` w)^2) on the episode's last step, e the heading error (rad) and w the yaw
    rate (rad/s, :func:`yaw_rate`): by default (1, 0) the squared error all along (the paper's
    integral); a final weight scores where the turn ends and that it has settled there (not
    still swinging: ``settle_s`` seconds of the yaw rate weigh as much as the error they would
    turn). The heading is followed through the episode (its memory: the heading turned so far,
    unwrapped, and the last heading), so that a turn of 180 deg to the left is not one to the
    right and a fish that spins a full circle is a circle off. Observation: sin and cos of the
    heading error; ``heading_deg`` is the heading turned from the start heading (unwrapped);
    ``final_yaw_rate_deg_s`` the yaw rate at the end. Ranges: ``path_weight`` and
    ``final_weight`` in [0, 1000], ``settle_s`` in [0, 10] s."""

    angle_deg: float = 90.0
    direction: str = "left"
    path_weight: float = 1.0
    final_weight: float = 0.0
    settle_s: float = 0.5
    name = "turn"
    start_spread = FISH_START
    obs_size = 2
    memory_size = 2  # the heading turned (unwrapped) and the last heading, rad from the start's
    default_duration = 5.0

    def __post_init__(self) -> None:
        """The arguments' checks (the ranges of the class docstring): the direction, the
        angle, then the weights. A subclass that turns other ways (the dolphin's) overrides
        :meth:`check_direction` and :meth:`check_angle` and inherits the rest."""
        super().__post_init__()
        self.check_direction()
        self.check_angle()
        self.check_weights()

    def check_direction(self) -> None:
        """``direction`` 'left' or 'right'; else a ValueError of one line."""
        if not (isinstance(self.direction, str) and self.direction in ("left", "right")):
            raise ValueError(f"direction must be 'left' or 'right', got {shown(self.direction)}")

    def check_angle(self) -> None:
        """``angle_deg`` in (0, 180] deg; else a ValueError of one line."""
        check_number("angle_deg", self.angle_deg, 0.0, 180.0, "deg", low_open=True)

    def check_weights(self) -> None:
        """``path_weight`` and ``final_weight`` in [0, 1000], ``settle_s`` in [0, 10] s: E_v's
        weights (:meth:`objective`), finite so that every reward is; else a ValueError of one
        line naming the argument."""
        check_number("path_weight", self.path_weight, 0.0, 1000.0)
        check_number("final_weight", self.final_weight, 0.0, 1000.0)
        check_number("settle_s", self.settle_s, 0.0, 10.0, "s")

    @property
    def target_yaw(self) -> float:
        sign = 1.0 if self.direction == "left" else -1.0
        return sign * np.radians(float(self.angle_deg))

    def _turned(self, world: World) -> tuple[np.ndarray, np.ndarray]:
        """(B,) the heading turned since the start, unwrapped, rad (the memory's, moved on by
        the last step's change, taken as the shorter way round), and (B,) the heading now, rad
        from the start heading in [-pi, pi)."""
        heading = wrap_angle(heading_yaw(world.frames) - world.start_yaw)
        turned, last = world.memory[:, 0], world.memory[:, 1]
        return turned + wrap_angle(heading - last), heading

    def observe(self, world: World) -> np.ndarray:
        """(B, 2) sine and cosine of the heading error."""
        error = self._turned(world)[0] - self.target_yaw
        return np.stack([np.sin(error), np.cos(error)], axis=1)

    def terms(self, world: World, last: np.ndarray) -> Terms:
        turned, heading = self._turned(world)
        error = turned - self.target_yaw
        rate = yaw_rate(world)
        return self.objective(error, rate, last), {
            "heading_deg": np.degrees(turned), "heading_error_deg": np.degrees(error),
            "yaw_rate_deg_s": np.degrees(rate)}, np.stack([turned, heading], axis=1)

    def objective(self, error: np.ndarray, rate: np.ndarray, last: np.ndarray) -> np.ndarray:
        """(B,) E_v of the error (B,) rad and the turn's rate (B,) rad/s (the class
        docstring)."""
        settled = error**2 + (float(self.settle_s) * rate) ** 2
        return float(self.path_weight) * error**2 + np.where(
            last, float(self.final_weight) * settled, 0.0)

    def final_metrics(self, last):
        """``final_heading_error_deg``: the absolute heading error at the end;
        ``final_yaw_rate_deg_s``: the absolute yaw rate there."""
        return {"final_heading_error_deg": np.abs(last["heading_error_deg"]),
                "final_yaw_rate_deg_s": np.abs(last["yaw_rate_deg_s"])}

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"):
        """The turn-MC for this angle and direction, calibrated for ``model`` (``speed`` is not
        used)."""
        angle, left = np.radians(float(self.angle_deg)), self.direction == "left"
        turn = calibrated(model)[1]
        return lambda t: turn_mc(angle, t, left, turn)


FAR_BL = 1.0e6  # the reach's closest distance before its first step, BL
HOLD_TOLERANCE_S = 1e-6  # s, the rounding of a sum of env steps


@dataclass
class ReachTask(Task):
    """Reach a goal point. Each episode's goal lies ``distance_bl`` body lengths from the start,
    at a bearing from the start heading drawn uniformly from ``bearing_deg`` (0: straight ahead,
    180: behind, positive: left), at the start depth. E_v = ``path_weight`` times the distance to
    the goal (BL) at every step, plus, on the episode's last step, ``final_weight`` times the
    distance there and ``closest_weight`` times the closest the fish came. Observation: the
    goal in the body frame, BL. The goal counts as reached when the fish comes within
    ``reached_bl`` of it at any step (its memory: the closest it has been): the ``reached``
    metric, 1 or 0 (over episodes, the share reached), beside ``closest_bl`` and
    ``final_distance_bl``; it counts as held when the fish ends within ``reached_bl`` of it and
    has stayed there for the episode's last ``hold_s`` seconds (its memory: how long it has
    been within, s): the ``held`` metric, 1 or 0. Ranges: ``distance_bl`` within [0, 1000] BL,
    ``bearing_deg`` within [-360, 360] deg (each low <= high), the weights in [0, 1000],
    ``reached_bl`` in [0, 1000] BL, ``hold_s`` in [0, 3600] s."""

    distance_bl: tuple[float, float] = (2.0, 4.0)
    bearing_deg: tuple[float, float] = (-180.0, 180.0)
    final_weight: float = 20.0
    path_weight: float = 1.0
    closest_weight: float = 0.0
    reached_bl: float = 0.5
    hold_s: float = 1.0
    name = "reach"
    start_spread = FISH_START
    target_size = 3
    obs_size = 3
    # the closest the centre of mass has been to the goal, BL; how long it has been within
    # reached_bl of it without a break, s
    memory_size = 2
    default_duration = 20.0

    def __post_init__(self) -> None:
        super().__post_init__()
        check_range("distance_bl", self.distance_bl, 0.0, 1000.0, "BL")
        check_range("bearing_deg", self.bearing_deg, -360.0, 360.0, "deg")
        for name in ("final_weight", "path_weight", "closest_weight"):
            check_number(name, getattr(self, name), 0.0, 1000.0)
        check_number("reached_bl", self.reached_bl, 0.0, 1000.0, "BL")
        check_number("hold_s", self.hold_s, 0.0, 3600.0, "s")

    def initial_memory(self) -> np.ndarray:
        """(2,) farther than any goal can be, BL (a goal is at most 1000 BL away); no time
        within reach yet, s."""
        return np.array([FAR_BL, 0.0])

    def sample(self, rng):
        """(3,) the goal in the start frame (x along the start heading), BL."""
        distance = rng.uniform(*self.distance_bl)
        bearing = np.radians(rng.uniform(*self.bearing_deg))
        return np.array([distance * np.cos(bearing), distance * np.sin(bearing), 0.0])

    def observe(self, world: World) -> np.ndarray:
        """(B, 3) the goal relative to the centre of mass in the body frame, BL."""
        return world_to_body(self._to_goal(world), world.frames) / world.length

    def _to_goal(self, world: World) -> np.ndarray:
        """(B, 3) from the centre of mass to the goal, world frame, m."""
        return from_start_frame(world.targets, world.start_yaw) * world.length - world.com

    def terms(self, world: World, last: np.ndarray) -> Terms:
        distance = np.linalg.norm(self._to_goal(world), axis=1) / world.length
        closest = np.minimum(world.memory[:, 0], distance)
        within_s = np.where(distance <= float(self.reached_bl), world.memory[:, 1] + world.dt,
                            0.0)
        end = float(self.final_weight) * distance + float(self.closest_weight) * closest
        e_v = float(self.path_weight) * distance + np.where(last, end, 0.0)
        return e_v, {"distance_bl": distance, "closest_bl": closest, "within_s": within_s}, \
            np.stack([closest, within_s], axis=1)

    def final_metrics(self, last):
        """``final_distance_bl``: the distance to the goal at the end; ``closest_bl``: the
        closest the fish came; ``reached``: 1 where that is within ``reached_bl``, else 0;
        ``held``: 1 where the fish ended within ``reached_bl`` and had been for the last
        ``hold_s`` (a step counts as its whole ``dt``; the tolerance is rounding's), else 0."""
        closest = np.asarray(last["closest_bl"])
        held = np.asarray(last["within_s"]) >= float(self.hold_s) - HOLD_TOLERANCE_S
        return {"final_distance_bl": np.asarray(last["distance_bl"]), "closest_bl": closest,
                "reached": (closest <= float(self.reached_bl)).astype(float),
                "held": (held & (np.asarray(last["distance_bl"]) <= float(self.reached_bl))
                         ).astype(float)}
