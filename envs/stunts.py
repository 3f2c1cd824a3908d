"""The dolphin's tasks (the paper's Section 4.2): 5 basic motor tasks and the SeaWorld stunts.

Every dolphin task starts the body at rest ``start_depth`` m under the surface (z = 0),
heading +x, pitched by ``start_pitch_deg``. Shapes and units as in :mod:`animat.envs.tasks`.

Basic tasks (basic training learns each into the repertoire):
``dolphin_forward`` (move-forward: E_v = -u, the speed along the start heading, BL/s) and
``dolphin_turn`` (``direction`` up, down, left or right by ``angle_deg``: E_v is the squared
pitch or yaw error, rad^2).

Stunts, each a score S that the reward pays out as it grows (``E_v = -(S_t - S_t-1) / dt``
from the second step on, so the task part of an episode's return is ``mu2`` times S at its
last step minus S at its first):

* ``leap``: S = the apex of the centre of mass above the surface, BL.
* ``nose_ball`` / ``tail_ball``: a beach ball rests on a support above the water
  (:mod:`animat.envs.physics.ball`). S = -(closest approach of the named part to the ball,
  BL) + 1 if the named part is the first to touch it + 1 more if the ball then leaves its
  support (``ball_hit``: both).
* ``somersault``: S = the largest |pitch rotation| of one flight (one stretch of the centre of
  mass above the surface), in turns, + 0.5 min(apex, 0) (the way up).
* ``belly_flop``: S = the re-entry splash (the impact momentum of the faces going under the
  surface once the dolphin has been out, :func:`animat.envs.physics.forces.add_face_forces`),
  in units of ``mass * sqrt(g L)``, + 0.5 min(apex, 0).

Every stunt reports the same metrics (read off the last step): ``apex_height_bl``,
``airborne`` (1 if the centre of mass went above the surface), ``rotation_deg`` (pitch
rotation above the surface, signed, over all flights), ``flight_rotation_deg`` (the largest
|pitch rotation| of one flight), ``reentry_splash``, ``entry_pitch_deg`` (pitch as the centre of
mass went back under, negative nose down; 0 if it did not: ``reentered`` says whether it did);
with a ball also
``nose_gap_bl``, ``tail_gap_bl`` (closest approach to the ball), ``first_touch`` (-1 none,
0 body, 1 nose, 2 tail: the part with most of the contact impulse in the env step the ball was
first touched), ``ball_off`` (1 if the ball left its support) and ``ball_hit``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from animat.envs.dolphin import LEFT_TIP, RIGHT_TIP
from animat.envs.dolphin_motor import dolphin_swim_mc, dolphin_turn_mc
from animat.envs.physics.ball import NOSE_PART, TAIL_PART, BallParams
from animat.envs.tasks import (
    TASKS,
    SwimTask,
    Task,
    TurnTask,
    World,
    heading_yaw,
    world_to_body,
    wrap_angle,
)

NOSE_NODES = (0,)
TAIL_NODES = (17, 18, 19, 20, LEFT_TIP, RIGHT_TIP)


def placed(body, depth: float, pitch_deg: float) -> np.ndarray:
    """(N, 3) the rest shape pitched nose-up by ``pitch_deg`` about its centre of mass, with
    the centre of mass ``depth`` m under z = 0."""
    rest = body.rest_positions
    com = body.masses @ rest / body.total_mass
    a = np.radians(pitch_deg)
    rotation = np.array([[np.cos(a), 0.0, -np.sin(a)], [0.0, 1.0, 0.0],
                         [np.sin(a), 0.0, np.cos(a)]])
    return (rest - com) @ rotation.T + np.array([0.0, 0.0, -depth])


def pitch_of(frames: np.ndarray) -> np.ndarray:
    """(B,) pitch of the forward vector above the horizontal, rad (positive: nose up)."""
    return np.arcsin(np.clip(frames[:, 0, 2], -1.0, 1.0))


class Underwater:
    """A dolphin task's start: ``start_depth`` m (negative: above the surface),
    ``start_pitch_deg`` and ``start_speed`` m/s, the velocity of every node along the pitched
    heading (0: at rest; a glide at speed, the start of a turn learned while swimming), the
    task's dataclass fields."""

    start_depth: float
    start_pitch_deg: float
    start_speed: float

    def check_start(self) -> None:
        if not np.isfinite(self.start_depth):
            raise ValueError(f"start_depth must be a number of metres (negative: above the "
                             f"surface), got {self.start_depth!r}")
        if not -90.0 <= self.start_pitch_deg <= 90.0:
            raise ValueError(f"start_pitch_deg must be in [-90, 90], got "
                             f"{self.start_pitch_deg!r}")
        if not (np.isfinite(self.start_speed) and self.start_speed >= 0.0):
            raise ValueError(f"start_speed must be a speed >= 0 m/s, got {self.start_speed!r}")

    def place(self, body):
        return placed(body, self.start_depth, self.start_pitch_deg)

    def start_velocity(self, body):
        a = np.radians(self.start_pitch_deg)
        heading = np.array([np.cos(a), 0.0, np.sin(a)])
        return np.broadcast_to(self.start_speed * heading, body.rest_positions.shape).copy()


@dataclass
class DolphinForwardTask(Underwater, SwimTask):
    """Move forward (the fish's swim task, started under water)."""

    start_depth: float = 3.0
    start_pitch_deg: float = 0.0
    start_speed: float = 0.0
    name = "dolphin_forward"
    default_duration = 4.0

    def __post_init__(self) -> None:
        super().__post_init__()
        self.check_start()

    def hand_controller(self, speed: float = 1.0):
        return lambda t: dolphin_swim_mc(speed, t)


@dataclass
class DolphinTurnTask(Underwater, TurnTask):
    """Turn ``direction`` (up, down, left, right) by ``angle_deg``: E_v the squared error of
    the pitch (up, down) or of the yaw (left, right), rad^2; observation: its sine and
    cosine (the fish's turn task, in both planes)."""

    angle_deg: float = 45.0
    direction: str = "up"
    start_depth: float = 3.0
    start_pitch_deg: float = 0.0
    start_speed: float = 0.0
    name = "dolphin_turn"
    default_duration = 4.0

    def __post_init__(self) -> None:
        if self.direction not in ("up", "down", "left", "right"):
            raise ValueError(f"direction must be up, down, left or right, got "
                             f"{self.direction!r}")
        limit = 180.0
        if self.direction in ("up", "down"):  # a pitch beyond +-90 deg is not a pitch
            sign = 1.0 if self.direction == "up" else -1.0
            limit = 90.0 - sign * float(self.start_pitch_deg)
        if not 0.0 < float(self.angle_deg) <= limit:
            raise ValueError(f"angle_deg must be in (0, {limit:g}] for {self.direction} from "
                             f"start_pitch_deg {self.start_pitch_deg:g}, got {self.angle_deg!r}")
        self.check_start()

    def _error(self, frames):
        sign = 1.0 if self.direction in ("up", "left") else -1.0
        target = sign * np.radians(float(self.angle_deg))
        if self.direction in ("up", "down"):
            return pitch_of(frames) - (np.radians(self.start_pitch_deg) + target)
        return wrap_angle(heading_yaw(frames) - target)

    def terms(self, com, com_vel, frames, targets, length, last):
        error = self._error(frames)
        return error**2, {"pitch_deg": np.degrees(pitch_of(frames)),
                          "heading_deg": np.degrees(heading_yaw(frames)),
                          "turn_error_deg": np.degrees(error)}

    def final_metrics(self, last):
        """``final_turn_error_deg``: the absolute pitch or yaw error at the end."""
        return {"final_turn_error_deg": np.abs(last["turn_error_deg"])}

    def hand_controller(self, speed: float = 1.0):
        angle = np.radians(float(self.angle_deg))
        return lambda t: dolphin_turn_mc(self.direction, angle, t)


@dataclass
class DolphinArcTask(Underwater, Task):
    """Swim an arc (a turn of radius ``radius_bl`` taken at speed, the paper's "turns of
    different radii"): pitching ``direction`` (up or down) round a centre ``radius_bl`` body
    lengths from the start's centre of mass along the normal of the start heading (above or
    below it for a level start). E_v = -u_arc, the centre of mass's
    speed along the circle (BL/s: the angular speed about the centre times the radius), so
    that the faster the dolphin swims round the arc the better, and a straight swim makes
    ever less of it. Metrics: ``arc_speed_bl_per_s``, ``pitch_deg``."""

    direction: str = "down"
    radius_bl: float = 2.0
    start_depth: float = 3.0
    start_pitch_deg: float = 0.0
    start_speed: float = 0.0
    name = "dolphin_arc"
    default_duration = 4.0
    mean_metrics = ("arc_speed_bl_per_s",)

    def __post_init__(self) -> None:
        if self.direction not in ("up", "down"):
            raise ValueError(f"direction must be up or down, got {self.direction!r}")
        if not (np.isfinite(self.radius_bl) and self.radius_bl > 0.0):
            raise ValueError(f"radius_bl must be a length > 0 BL, got {self.radius_bl!r}")
        self.check_start()

    def terms(self, com, com_vel, frames, targets, length, last):
        a = np.radians(self.start_pitch_deg)
        heading, normal = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        sign = -1.0 if self.direction == "down" else 1.0  # the centre: below or above
        r = com[:, [0, 2]] - sign * self.radius_bl * length * normal  # (B, 2) from the centre
        v = com_vel[:, [0, 2]]
        tangent = -sign * (r @ normal[:, None] * heading - r @ heading[:, None] * normal)
        u_arc = np.einsum("bk,bk->b", tangent, v) / np.maximum(np.linalg.norm(r, axis=1),
                                                              1e-9)
        return -u_arc / length, {"arc_speed_bl_per_s": u_arc / length,
                                 "pitch_deg": np.degrees(pitch_of(frames))}

    def hand_controller(self, speed: float = 1.0):
        return lambda t: dolphin_swim_mc(speed, t)


# Episode memory of a stunt, by column.
(APEX, AIRBORNE, SPLASH, ROTATION, FORWARD_X, FORWARD_Y, FORWARD_Z, ENTRY_PITCH, REENTERED,
 NOSE_GAP, TAIL_GAP, SCORE, FIRST_TOUCH, BALL_OFF, FLIGHT, BEST_FLIGHT) = range(16)
BALL_OFF_DISTANCE = 0.1  # m the ball must move from its rest to have left its support
FINAL_METRICS = ("apex_height_bl", "airborne", "rotation_deg", "flight_rotation_deg",
                 "reentry_splash", "entry_pitch_deg")
BALL_METRICS = ("nose_gap_bl", "tail_gap_bl", "first_touch", "ball_off", "ball_hit")


def splash_unit_of(world: World) -> float:
    """The splash's unit, ``mass sqrt(g L)`` kg m/s (g of Water's default, 9.81 m/s^2): the
    momentum of the body falling from half its length."""
    return world.body.total_mass * np.sqrt(9.81 * world.length)


def _gaps(world: World, nodes: tuple[int, ...], radius: float) -> np.ndarray:
    """(B,) distance from the ball's surface to the nearest of ``nodes``, m."""
    offsets = world.x[:, list(nodes)] - world.ball[:, None, :3]
    return np.linalg.norm(offsets, axis=2).min(axis=1) - radius


def _pitch_step(previous: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """(B,) signed rotation (rad, nose up positive) of the forward vector from ``previous``
    (B, 3) to this step's, about the body's lateral axis; 0 where there is no previous."""
    forward, left = frames[:, 0], frames[:, 1]
    cross = np.cross(previous, forward)
    angle = np.arctan2(-np.einsum("bk,bk->b", cross, left),
                       np.einsum("bk,bk->b", previous, forward))
    return np.where(np.linalg.norm(previous, axis=1) > 0.5, angle, 0.0)


@dataclass
class StuntTask(Underwater, Task):
    """Base of the stunts: the episode memory and metrics they share; a stunt defines
    :meth:`score`. ``start_depth`` m, ``start_pitch_deg`` as the basic tasks."""

    start_depth: float = 3.0
    start_pitch_deg: float = 0.0
    start_speed: float = 0.0
    name = "stunt"
    memory_size = 16
    obs_size = 1
    default_duration = 8.0

    def __post_init__(self) -> None:
        self.check_start()

    def initial_memory(self) -> np.ndarray:
        memory = np.zeros(self.memory_size)
        memory[[APEX, NOSE_GAP, TAIL_GAP]] = -np.inf, np.inf, np.inf
        memory[[ENTRY_PITCH, SCORE]] = np.nan
        memory[FIRST_TOUCH] = -1.0
        pitch = np.radians(self.start_pitch_deg)  # the placed body's heading
        memory[FORWARD_X:FORWARD_Z + 1] = np.cos(pitch), 0.0, np.sin(pitch)
        return memory

    def world_observe(self, world: World) -> np.ndarray:
        """The centre of mass's height above the surface, BL."""
        return ((world.position[:, 2] - world.surface_z) / world.length)[:, None]

    def remember(self, world: World) -> np.ndarray:
        """The memory updated by this step (a copy)."""
        m = world.memory.copy()
        height = world.position[:, 2] - world.surface_z
        above = height > 0.0
        m[:, APEX] = np.maximum(m[:, APEX], height)
        was_airborne = m[:, AIRBORNE] > 0
        m[:, SPLASH] += np.where(was_airborne, world.splash, 0.0)
        turned = np.where(above, _pitch_step(m[:, FORWARD_X:FORWARD_Z + 1], world.frames), 0.0)
        m[:, ROTATION] += turned
        m[:, FLIGHT] = np.where(above, m[:, FLIGHT] + turned, 0.0)  # this flight's, signed
        m[:, BEST_FLIGHT] = np.maximum(m[:, BEST_FLIGHT], np.abs(m[:, FLIGHT]))
        m[:, FORWARD_X:FORWARD_Z + 1] = world.frames[:, 0]
        entering = was_airborne & ~above & (m[:, REENTERED] == 0)
        m[:, ENTRY_PITCH] = np.where(entering, np.degrees(pitch_of(world.frames)),
                                     m[:, ENTRY_PITCH])
        m[:, REENTERED] = np.maximum(m[:, REENTERED], entering)
        m[:, AIRBORNE] = np.maximum(m[:, AIRBORNE], above)
        if self.ball is not None:
            radius = self.ball.radius
            m[:, NOSE_GAP] = np.minimum(m[:, NOSE_GAP], _gaps(world, NOSE_NODES, radius))
            m[:, TAIL_GAP] = np.minimum(m[:, TAIL_GAP], _gaps(world, TAIL_NODES, radius))
            touched = world.touch.max(axis=1) > 0
            # the part with most of the contact in the env step of the first touch
            first = np.where(touched, np.argmax(world.touch, axis=1), -1)
            m[:, FIRST_TOUCH] = np.where(m[:, FIRST_TOUCH] < 0, first, m[:, FIRST_TOUCH])
            moved = np.linalg.norm(world.ball[:, :3] - self.ball.rest, axis=1)
            m[:, BALL_OFF] = np.maximum(m[:, BALL_OFF], moved > BALL_OFF_DISTANCE)
        return m

    def score(self, m: np.ndarray, world: World) -> np.ndarray:
        """(B,) the stunt's score S from the updated memory."""
        raise NotImplementedError

    def ball_hit(self, m: np.ndarray) -> np.ndarray:
        return np.zeros(len(m))

    def world_terms(self, world: World, last: np.ndarray):
        m = self.remember(world)
        score = self.score(m, world)
        gain = np.where(np.isnan(m[:, SCORE]), 0.0, score - m[:, SCORE])
        m[:, SCORE] = score
        length = world.length
        splash_unit = splash_unit_of(world)
        metrics = {
            "height_bl": (world.position[:, 2] - world.surface_z) / length,
            "score": score,
            "apex_height_bl": m[:, APEX] / length, "airborne": m[:, AIRBORNE],
            "rotation_deg": np.degrees(m[:, ROTATION]),
            "flight_rotation_deg": np.degrees(m[:, BEST_FLIGHT]),
            "reentry_splash": m[:, SPLASH] / splash_unit,
            "entry_pitch_deg": np.where(m[:, REENTERED] > 0, m[:, ENTRY_PITCH], 0.0),
            "reentered": m[:, REENTERED],
        }
        if self.ball is not None:
            metrics.update(nose_gap_bl=m[:, NOSE_GAP] / length, tail_gap_bl=m[:, TAIL_GAP] / length,
                           first_touch=m[:, FIRST_TOUCH], ball_off=m[:, BALL_OFF],
                           ball_hit=self.ball_hit(m))
        return -gain / world.dt, metrics, m

    def terms(self, com, com_vel, frames, targets, length, last):
        raise TypeError(f"the {self.name} task needs the world: use world_terms")

    def final_metrics(self, last):
        names = FINAL_METRICS + (BALL_METRICS if self.ball is not None else ())
        return {k: np.asarray(last[k], dtype=float) for k in names + ("reentered",)}


def _below(apex_bl: np.ndarray) -> np.ndarray:
    """The way up, for the stunts that need the dolphin out first: 0.5 min(apex, 0), BL."""
    return 0.5 * np.minimum(apex_bl, 0.0)


@dataclass
class LeapTask(StuntTask):
    """Leap: S = the apex of the centre of mass above the surface, BL."""

    name = "leap"

    def score(self, m, world):
        return m[:, APEX] / world.length


@dataclass
class BallTask(StuntTask):
    """Bounce the beach ball off its support with ``part`` (nose or tail). The ball rests on a
    support with its top at (``ball_x``, ``ball_y``, ``ball_height``) m (by default where the
    leap macro controller of ``configs/dolphin_leap_macro.yaml`` broke the surface: where a
    trainer holds the ball); observation: height, then the ball relative to the centre of
    mass in the body frame, BL."""

    part: str = "nose"
    ball_x: float = 15.3
    ball_y: float = -1.0
    ball_height: float = 1.9
    ball_radius: float = 0.3
    name = "ball"
    obs_size = 4

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.part not in ("nose", "tail"):
            raise ValueError(f"part must be 'nose' or 'tail', got {self.part!r}")
        self.ball = BallParams(radius=float(self.ball_radius),
                               support=(float(self.ball_x), float(self.ball_y),
                                        float(self.ball_height)))

    @property
    def part_index(self) -> int:
        return NOSE_PART if self.part == "nose" else TAIL_PART

    def world_observe(self, world):
        body = world_to_body(world.ball[:, :3] - world.position, world.frames) / world.length
        return np.concatenate([super().world_observe(world), body], axis=1)

    def ball_hit(self, m):
        return ((m[:, FIRST_TOUCH] == self.part_index) & (m[:, BALL_OFF] > 0)).astype(float)

    def score(self, m, world):
        gap = m[:, NOSE_GAP if self.part == "nose" else TAIL_GAP]
        named = (m[:, FIRST_TOUCH] == self.part_index).astype(float)
        return -np.maximum(gap, 0.0) / world.length + named + self.ball_hit(m)


@dataclass
class SomersaultTask(StuntTask):
    """Somersault: S = the largest |pitch rotation| of one flight (one stretch with the
    centre of mass above the surface), in turns, + the way up: leaps that each turn part of
    a circle do not add up to one."""

    name = "somersault"

    def score(self, m, world):
        return m[:, BEST_FLIGHT] / (2.0 * np.pi) + _below(m[:, APEX] / world.length)


@dataclass
class BellyFlopTask(StuntTask):
    """Belly flop: S = the re-entry splash in units of ``mass sqrt(g L)`` + the way up."""

    name = "belly_flop"

    def score(self, m, world):
        return m[:, SPLASH] / splash_unit_of(world) + _below(m[:, APEX] / world.length)


DOLPHIN_TASKS: dict[str, type[Task]] = {
    "dolphin_forward": DolphinForwardTask, "dolphin_turn": DolphinTurnTask,
    "dolphin_arc": DolphinArcTask, "leap": LeapTask,
    "ball": BallTask, "somersault": SomersaultTask, "belly_flop": BellyFlopTask,
}
TASKS.update(DOLPHIN_TASKS)
