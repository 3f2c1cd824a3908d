"""The dolphin's basic motor tasks (the paper's Section 4.2), which basic training learns into
its repertoire, and the start under water that they and the stunts (:mod:`animat.envs.tasks.stunts`)
share. Each implements the one task API (:class:`animat.envs.tasks.base.Task`: ``terms`` of
the :class:`~animat.envs.tasks.base.World`); shapes and units as there.

Every dolphin task starts the body ``start_depth`` m under the surface (z = 0; in [-100, 1000]
m), heading +x, pitched by ``start_pitch_deg`` (in [-90, 90]), at ``start_speed`` (0: at rest;
in [0, 20] m/s).

* ``dolphin_forward`` (move-forward): E_v = -u, the speed along the start heading, BL/s.
* ``dolphin_turn``: ``direction`` up, down, left or right by ``angle_deg``; E_v is the squared
  pitch or yaw error, rad^2.
* ``dolphin_arc``: a turn of radius ``radius_bl`` (in (0, 100] BL) swum round at speed;
  E_v = -the speed along the circle, BL/s.
* ``dolphin_spin``: a pitch spin (a turn of no radius); E_v = -the body's pitch rate in the
  ``direction`` (its angular momentum about the lateral axis over its inertia), rad/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import check_number, shown
from ..motor.dolphin import dolphin_calibrated, dolphin_swim_mc, dolphin_turn_mc
from ..physics.observe import momenta
from .base import Task, Terms, World, heading_yaw, wrap_angle
from .locomotion import SwimTask, TurnTask, yaw_rate
from .start import StartSpread

MAX_HEIGHT, MAX_DEPTH = 100.0, 1000.0  # m, a start above and under the surface
MAX_START_SPEED = 20.0  # m/s
# The dolphin's tasks in the pool: set in the pool's frame (the surface, the ball), so its
# heading does not spread; its body bent up to 10 deg, pitched up to 5 deg, 0.1 BL deeper or
# shallower, gliding at up to 0.2 BL/s on top of the task's start speed, drifting and yawing a
# little.
DOLPHIN_START = StartSpread(pitch_deg=5.0, bend_deg=10.0, speed_bl=0.2, drift_bl=0.05,
                            yaw_rate_deg=10.0, depth_bl=0.1)


def check_pitch_direction(direction: object) -> None:
    """``direction`` up or down (a pitch's: the arc's and the spin's); else a ValueError of
    one line."""
    if not (isinstance(direction, str) and direction in ("up", "down")):
        raise ValueError(f"direction must be up or down, got {shown(direction)}")


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
    task's dataclass fields; spread about them by :data:`DOLPHIN_START`."""

    start_depth: float
    start_pitch_deg: float
    start_speed: float
    start_spread = DOLPHIN_START

    def __post_init__(self) -> None:
        """The start's checks (:meth:`check_start`), then the task's own (the next class in
        the method resolution order: the fish's swim or turn task, or :class:`Task`): the
        start first, since a task's checks may read it (the dolphin turn's angle limit reads
        ``start_pitch_deg``)."""
        self.check_start()
        super().__post_init__()

    def check_start_spread(self, spread: StartSpread) -> None:
        """The dolphin's tasks are set in the pool's frame: no heading spread."""
        if spread.heading_deg:
            raise ValueError(f"task {self.name!r} is set in the pool's frame: start_spread "
                             f"heading_deg must be 0, got {spread.heading_deg:g}")

    def check_start(self) -> None:
        """``start_depth`` in [-100, 1000] m (negative: above the surface),
        ``start_pitch_deg`` in [-90, 90], ``start_speed`` in [0, 20] m/s (a dolphin's top
        speed is ~11 m/s); else a ValueError of one line naming the argument."""
        check_number("start_depth", self.start_depth, -MAX_HEIGHT, MAX_DEPTH, "m",
                     note="negative: above the surface")
        check_number("start_pitch_deg", self.start_pitch_deg, -90.0, 90.0, "deg")
        check_number("start_speed", self.start_speed, 0.0, MAX_START_SPEED, "m/s")

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

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"):
        swim = dolphin_calibrated(model).swim
        return lambda t: dolphin_swim_mc(speed, t, swim)


@dataclass
class DolphinTurnTask(Underwater, TurnTask):
    """Turn ``direction`` (up, down, left, right) by ``angle_deg``: E_v of the error of the
    pitch (up, down) or of the yaw (left, right) and of the pitch or yaw rate, as the fish's
    (:meth:`TurnTask.objective`: by default the squared error, rad^2); observation: the
    error's sine and cosine (the fish's turn task, in both planes). Its arguments are
    checked as the fish's (:meth:`TurnTask.__post_init__`: the weights' ranges as there),
    in its own directions and, up or down, within a pitch of 90 deg."""

    angle_deg: float = 45.0
    direction: str = "up"
    start_depth: float = 3.0
    start_pitch_deg: float = 0.0
    start_speed: float = 0.0
    name = "dolphin_turn"
    memory_size = 0  # its error is the pitch's, or the heading's within a half turn
    default_duration = 4.0

    def check_direction(self) -> None:
        """``direction`` up, down, left or right; else a ValueError of one line."""
        if not (isinstance(self.direction, str)
                and self.direction in ("up", "down", "left", "right")):
            raise ValueError(f"direction must be up, down, left or right, got "
                             f"{shown(self.direction)}")

    def check_angle(self) -> None:
        """``angle_deg`` in (0, 180] deg left or right, and up or down at most to a vertical
        pitch from ``start_pitch_deg`` (checked before: :meth:`Underwater.__post_init__`);
        else a ValueError of one line."""
        limit = 180.0
        if self.direction in ("up", "down"):  # a pitch beyond +-90 deg is not a pitch
            sign = 1.0 if self.direction == "up" else -1.0
            limit = 90.0 - sign * float(self.start_pitch_deg)
        check_number("angle_deg", self.angle_deg, 0.0, limit, "deg", low_open=True,
                     note=f"for {self.direction} from start_pitch_deg {self.start_pitch_deg:g}")

    def _error(self, world: World) -> np.ndarray:
        """(B,) the pitch error, or the yaw error from the start heading, rad."""
        sign = 1.0 if self.direction in ("up", "left") else -1.0
        target = sign * np.radians(float(self.angle_deg))
        if self.direction in ("up", "down"):
            return pitch_of(world.frames) - (np.radians(self.start_pitch_deg) + target)
        return wrap_angle(heading_yaw(world.frames) - world.start_yaw - target)

    def observe(self, world: World) -> np.ndarray:
        """(B, 2) sine and cosine of the pitch or yaw error."""
        error = self._error(world)
        return np.stack([np.sin(error), np.cos(error)], axis=1)

    def terms(self, world: World, last: np.ndarray) -> Terms:
        frames = world.frames
        error = self._error(world)
        rate = pitch_rate(world) if self.direction in ("up", "down") else yaw_rate(world)
        return self.objective(error, rate, last), {
            "pitch_deg": np.degrees(pitch_of(frames)),
            "heading_deg": np.degrees(wrap_angle(heading_yaw(frames) - world.start_yaw)),
            "turn_error_deg": np.degrees(error)}, world.memory

    def final_metrics(self, last):
        """``final_turn_error_deg``: the absolute pitch or yaw error at the end."""
        return {"final_turn_error_deg": np.abs(last["turn_error_deg"])}

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"):
        angle, calibration = np.radians(float(self.angle_deg)), dolphin_calibrated(model)
        return lambda t: dolphin_turn_mc(self.direction, angle, t, calibration)


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
        """The start's checks (inherited), then ``direction`` up or down and ``radius_bl`` in
        (0, 100] BL; else a ValueError of one line."""
        super().__post_init__()
        check_pitch_direction(self.direction)
        check_number("radius_bl", self.radius_bl, 0.0, 100.0, "BL", low_open=True)

    def terms(self, world: World, last: np.ndarray) -> Terms:
        com, length = world.com, world.length
        a = np.radians(self.start_pitch_deg)
        heading, normal = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        sign = -1.0 if self.direction == "down" else 1.0  # the centre: below or above
        r = com[:, [0, 2]] - sign * self.radius_bl * length * normal  # (B, 2) from the centre
        v = world.com_vel[:, [0, 2]]
        tangent = -sign * (r @ normal[:, None] * heading - r @ heading[:, None] * normal)
        u_arc = np.einsum("bk,bk->b", tangent, v) / np.maximum(np.linalg.norm(r, axis=1),
                                                              1e-9)
        return -u_arc / length, {"arc_speed_bl_per_s": u_arc / length,
                                 "pitch_deg": np.degrees(pitch_of(world.frames))}, world.memory

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"):
        swim = dolphin_calibrated(model).swim
        return lambda t: dolphin_swim_mc(speed, t, swim)


def pitch_rate(world: World) -> np.ndarray:
    """(B,) the body's nose-up pitch rate, rad/s: its angular momentum about its centre of
    mass, along the lateral axis, over its moment of inertia about that axis (the spin that a
    flight keeps, whatever the body's shape does)."""
    masses = world.body.masses
    _, momentum = momenta(world.x, world.v, masses, world.position)
    r, left = world.x - world.position[:, None], world.frames[:, 1]
    along = np.einsum("bnk,bk->bn", r, left)
    inertia = np.einsum("n,bn->b", masses, np.einsum("bnk,bnk->bn", r, r) - along**2)
    return -np.einsum("bk,bk->b", momentum, left) / inertia  # about +left is nose down


@dataclass
class DolphinSpinTask(Underwater, Task):
    """Spin: pitch ``direction`` (up or down) as fast as the body can, about its centre of
    mass (a turn of no radius, the way a somersault turns). E_v = -the pitch rate in the
    ``direction`` (:func:`pitch_rate`), rad/s. Metrics: ``spin_deg_per_s`` (its episode mean),
    ``pitch_deg``."""

    direction: str = "down"
    start_depth: float = 3.0
    start_pitch_deg: float = 0.0
    start_speed: float = 0.0
    name = "dolphin_spin"
    default_duration = 4.0
    mean_metrics = ("spin_deg_per_s",)

    def __post_init__(self) -> None:
        """The start's checks (inherited), then ``direction`` up or down; else a ValueError
        of one line."""
        super().__post_init__()
        check_pitch_direction(self.direction)

    def terms(self, world: World, last: np.ndarray) -> Terms:
        sign = 1.0 if self.direction == "up" else -1.0
        spin = sign * pitch_rate(world)
        return -spin, {"spin_deg_per_s": np.degrees(spin),
                       "pitch_deg": np.degrees(pitch_of(world.frames))}, world.memory

    def hand_controller(self, speed: float = 1.0, model: str = "reactive"):
        calibration = dolphin_calibrated(model)
        return lambda t: dolphin_turn_mc(self.direction, np.pi / 2, t, calibration)
