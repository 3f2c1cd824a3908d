"""The dolphin's SeaWorld stunts (the paper's Section 4.2); its basic tasks are in
:mod:`animat.envs.tasks.dolphin`, and every task is named in :data:`animat.envs.tasks.TASKS`.

Every stunt starts as the basic tasks do (:class:`animat.envs.tasks.dolphin.Underwater`) and
implements the one task API (:class:`animat.envs.tasks.base.Task`: ``terms`` and ``observe`` of
the :class:`~animat.envs.tasks.base.World`), keeping an episode memory of 16 numbers by column
(``APEX`` ... ``BEST_FLIGHT``). Shapes and units as in :mod:`animat.envs.tasks.base`.

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
mass went back under, negative nose down; 0 if it did not: ``reentered`` says whether it did),
``entry_roll_deg`` (the roll then, positive with the left side up; 0 if it did not re-enter);
with a ball also
``nose_gap_bl``, ``tail_gap_bl`` (closest approach to the ball), ``first_touch`` (-1 none,
0 body, 1 nose, 2 tail: the part with most of the contact impulse in the env step the ball was
first touched), ``ball_off`` (1 if the ball left its support), ``ball_rise_bl`` (the highest
the ball rose above its rest, BL) and ``ball_hit``.

Each stunt also says whether it was done, in ``is_success`` (1 or 0; the key SB3's logger reads
into its success rate), by what its name means:

* ``leap``: the apex clears :data:`LEAP_CLEARS_BL` (0.5 BL);
* ``somersault``: one flight turns at least :data:`FULL_TURN_DEG` (360 deg) in pitch;
* ``nose_ball``: the rostrum touches the ball first and the ball rises at least
  :data:`BALL_OFF_DISTANCE` (0.1 m) above its rest;
* ``tail_ball``: the flukes touch the ball first and it leaves its support (``ball_hit``);
* ``belly_flop``: the dolphin re-enters belly first: pitch within :data:`FLAT_PITCH_DEG` (20 deg)
  of level and roll within :data:`FLAT_ROLL_DEG` (45 deg), the belly toward the water. That it
  splashes more than a clean re-entry from the same height is a comparison of policies on the
  same starts (the belly flop's ``reentry_splash`` beside the leap's), not one episode's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bodies.dolphin import LEFT_TIP, RIGHT_TIP
from ..bodies.spec import NOSE_PART, TAIL_PART
from ..checks import check_number, shown
from ..physics.ball import BallParams
from .base import Task, Terms, World, world_to_body
from .dolphin import (
    Underwater,
    pitch_of,
)

NOSE_NODES = (0,)
TAIL_NODES = (17, 18, 19, 20, LEFT_TIP, RIGHT_TIP)


# Episode memory of a stunt, by column.
(APEX, AIRBORNE, SPLASH, ROTATION, FORWARD_X, FORWARD_Y, FORWARD_Z, ENTRY_PITCH, REENTERED,
 NOSE_GAP, TAIL_GAP, SCORE, FIRST_TOUCH, BALL_OFF, FLIGHT, BEST_FLIGHT, ENTRY_ROLL,
 BALL_RISE) = range(18)
BALL_OFF_DISTANCE = 0.1  # m the ball must move from its rest to have left its support
# What each stunt's name means (is_success; the module docstring)
LEAP_CLEARS_BL = 0.5  # BL, the apex of a leap
FULL_TURN_DEG = 360.0  # deg of pitch in one flight, a somersault
FLAT_PITCH_DEG, FLAT_ROLL_DEG = 20.0, 45.0  # deg from level, a belly-first entry
MAX_TILT = 2.0  # the largest |pitch| / 90 deg + |roll| / 180 deg, the belly flop's flat_weight
MAX_BALL_OFFSET, MAX_BALL_HEIGHT, MAX_BALL_RADIUS = 1000.0, 100.0, 5.0  # m, BallTask's ranges
FINAL_METRICS = ("apex_height_bl", "airborne", "rotation_deg", "flight_rotation_deg",
                 "reentry_splash", "entry_pitch_deg", "entry_roll_deg", "is_success")
BALL_METRICS = ("nose_gap_bl", "tail_gap_bl", "first_touch", "ball_off", "ball_rise_bl",
                "ball_hit")


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


def roll_of(frames: np.ndarray) -> np.ndarray:
    """(B,) roll about the forward axis, rad: 0 with the back up (the left axis level),
    positive with the left side up, +-pi upside down."""
    return np.arctan2(frames[:, 1, 2], frames[:, 2, 2])


@dataclass
class StuntTask(Underwater, Task):
    """Base of the stunts: the episode memory and metrics they share; a stunt defines
    :meth:`score`. ``start_depth`` m, ``start_pitch_deg`` as the basic tasks."""

    start_depth: float = 3.0
    start_pitch_deg: float = 0.0
    start_speed: float = 0.0
    name = "stunt"
    memory_size = 18
    obs_size = 1
    default_duration = 8.0

    def initial_memory(self) -> np.ndarray:
        memory = np.zeros(self.memory_size)
        memory[[APEX, NOSE_GAP, TAIL_GAP]] = -np.inf, np.inf, np.inf
        memory[[ENTRY_PITCH, SCORE]] = np.nan
        memory[FIRST_TOUCH] = -1.0
        pitch = np.radians(self.start_pitch_deg)  # the placed body's heading
        memory[FORWARD_X:FORWARD_Z + 1] = np.cos(pitch), 0.0, np.sin(pitch)
        return memory

    def observe(self, world: World) -> np.ndarray:
        """(B, 1) the centre of mass's height above the surface, BL."""
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
        m[:, ENTRY_ROLL] = np.where(entering, np.degrees(roll_of(world.frames)),
                                    m[:, ENTRY_ROLL])
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
            m[:, BALL_RISE] = np.maximum(m[:, BALL_RISE], world.ball[:, 2] - self.ball.rest[2])
        return m

    def score(self, m: np.ndarray, world: World) -> np.ndarray:
        """(B,) the stunt's score S from the updated memory."""
        raise NotImplementedError

    def ball_hit(self, m: np.ndarray) -> np.ndarray:
        return np.zeros(len(m))

    def succeeded(self, m: np.ndarray, world: World) -> np.ndarray:
        """(B,) 1 where the stunt was done as its name means (the module docstring), else 0,
        from the updated memory."""
        raise NotImplementedError

    def terms(self, world: World, last: np.ndarray) -> Terms:
        """E_v = -(S_t - S_t-1) / dt (0 on the first step), the metrics and the memory."""
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
            "entry_roll_deg": np.where(m[:, REENTERED] > 0, m[:, ENTRY_ROLL], 0.0),
            "reentered": m[:, REENTERED],
            "is_success": self.succeeded(m, world).astype(float),
        }
        if self.ball is not None:
            metrics.update(nose_gap_bl=m[:, NOSE_GAP] / length, tail_gap_bl=m[:, TAIL_GAP] / length,
                           first_touch=m[:, FIRST_TOUCH], ball_off=m[:, BALL_OFF],
                           ball_rise_bl=m[:, BALL_RISE] / length, ball_hit=self.ball_hit(m))
        return -gain / world.dt, metrics, m

    def final_metrics(self, last):
        names = FINAL_METRICS + (BALL_METRICS if self.ball is not None else ())
        return {k: np.asarray(last[k], dtype=float) for k in names + ("reentered",)}


def _below(apex_bl: np.ndarray) -> np.ndarray:
    """The way up, for the stunts that need the dolphin out first: 0.5 min(apex, 0), BL."""
    return 0.5 * np.minimum(apex_bl, 0.0)


@dataclass
class LeapTask(StuntTask):
    """Leap: S = the apex of the centre of mass above the surface, BL. Done (``is_success``)
    when the apex clears :data:`LEAP_CLEARS_BL` (0.5 BL)."""

    name = "leap"

    def score(self, m, world):
        return m[:, APEX] / world.length

    def succeeded(self, m, world):
        return m[:, APEX] / world.length >= LEAP_CLEARS_BL


@dataclass
class BallTask(StuntTask):
    """Bounce the beach ball off its support with ``part`` (nose or tail). The ball rests on a
    support with its top at (``ball_x``, ``ball_y``, ``ball_height``) m (by default where a
    leap learned in the paper's water broke the surface: where a trainer holds the ball);
    observation: height, then the ball relative to the centre of mass in the body frame, BL.
    Ranges: ``ball_x``, ``ball_y`` in [-1000, 1000] m, ``ball_height`` in [-100, 100] m (from
    the surface, z = 0), ``ball_radius`` in (0, 5] m. Done (``is_success``) when the named
    part touches the ball first and the ball leaves its support; for the nose, up: it rises
    at least :data:`BALL_OFF_DISTANCE` (0.1 m) above its rest."""

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
            raise ValueError(f"part must be 'nose' or 'tail', got {shown(self.part)}")
        for name in ("ball_x", "ball_y"):
            check_number(name, getattr(self, name), -MAX_BALL_OFFSET, MAX_BALL_OFFSET, "m")
        check_number("ball_height", self.ball_height, -MAX_BALL_HEIGHT, MAX_BALL_HEIGHT, "m")
        check_number("ball_radius", self.ball_radius, 0.0, MAX_BALL_RADIUS, "m", low_open=True)
        self.ball = BallParams(radius=float(self.ball_radius),
                               support=(float(self.ball_x), float(self.ball_y),
                                        float(self.ball_height)))

    @property
    def part_index(self) -> int:
        return NOSE_PART if self.part == "nose" else TAIL_PART

    def observe(self, world: World) -> np.ndarray:
        """(B, 4) the height above the surface, then the ball relative to the centre of mass
        in the body frame, BL."""
        body = world_to_body(world.ball[:, :3] - world.position, world.frames) / world.length
        return np.concatenate([super().observe(world), body], axis=1)

    def ball_hit(self, m):
        return ((m[:, FIRST_TOUCH] == self.part_index) & (m[:, BALL_OFF] > 0)).astype(float)

    def succeeded(self, m, world):
        """The named part touched the ball first and the ball left its support: up, for the
        nose (it rose at least :data:`BALL_OFF_DISTANCE`)."""
        hit = self.ball_hit(m) > 0
        return hit & (m[:, BALL_RISE] >= BALL_OFF_DISTANCE) if self.part == "nose" else hit

    def score(self, m, world):
        gap = m[:, NOSE_GAP if self.part == "nose" else TAIL_GAP]
        named = (m[:, FIRST_TOUCH] == self.part_index).astype(float)
        return -np.maximum(gap, 0.0) / world.length + named + self.ball_hit(m)


@dataclass
class SomersaultTask(StuntTask):
    """Somersault: S = the largest |pitch rotation| of one flight (one stretch with the
    centre of mass above the surface), in turns, + the way up: leaps that each turn part of
    a circle do not add up to one. Done (``is_success``) when one flight turns at least
    :data:`FULL_TURN_DEG` (360 deg)."""

    name = "somersault"

    def score(self, m, world):
        return m[:, BEST_FLIGHT] / (2.0 * np.pi) + _below(m[:, APEX] / world.length)

    def succeeded(self, m, world):
        return np.degrees(m[:, BEST_FLIGHT]) >= FULL_TURN_DEG


@dataclass
class BellyFlopTask(StuntTask):
    """Belly flop: S = the re-entry splash in units of ``mass sqrt(g L)`` + the way up. Done
    (``is_success``) when the dolphin re-enters belly first: pitch within
    :data:`FLAT_PITCH_DEG` (20 deg) of level and roll within :data:`FLAT_ROLL_DEG` (45 deg)
    (``entry_pitch_deg``, ``entry_roll_deg``); that it splashes more than a clean re-entry
    from the same height is measured against the leap's policy on the same starts.
    ``flat_weight`` (in [0, 100]; default 0, the score above) takes ``flat_weight`` times the
    re-entry's tilt, |pitch| / 90 deg + |roll| / 180 deg, off S, and the largest tilt (2)
    until the dolphin is back in (so that staying in or over the water is never flatter): a
    score for a flop that lands flat, not only one that splashes."""

    flat_weight: float = 0.0
    name = "belly_flop"

    def __post_init__(self) -> None:
        super().__post_init__()
        check_number("flat_weight", self.flat_weight, 0.0, 100.0)

    def score(self, m, world):
        tilt = np.where(m[:, REENTERED] > 0, np.abs(np.nan_to_num(m[:, ENTRY_PITCH])) / 90.0
                        + np.abs(m[:, ENTRY_ROLL]) / 180.0, MAX_TILT)
        return (m[:, SPLASH] / splash_unit_of(world) + _below(m[:, APEX] / world.length)
                - float(self.flat_weight) * tilt)

    def succeeded(self, m, world):
        """Re-entered belly first: pitch within :data:`FLAT_PITCH_DEG` of level and roll
        within :data:`FLAT_ROLL_DEG`."""
        return ((m[:, REENTERED] > 0) & (np.abs(m[:, ENTRY_PITCH]) <= FLAT_PITCH_DEG)
                & (np.abs(m[:, ENTRY_ROLL]) <= FLAT_ROLL_DEG))
