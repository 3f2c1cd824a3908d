"""Navigation-level control of fish: (speed, turn, pitch) commands run through the motor
controllers, for any number of fish at once.

The paper's navigation sends a turn angle to the left- or right-turn-MC when it is above a
threshold, and otherwise swims with the swim-MC; up and down go to the fin-MC. A
:class:`Navigator` keeps, per fish, which MC is running and since when: a turn command of
``turn`` in [-1, 1] (positive: left) with ``|turn| > turn_threshold`` starts a turn of
``|turn| * max_turn`` that runs to its end before the next command is taken; otherwise the
swim-MC runs at ``speed`` in [0, 1] (its ease-in restarts after a turn). The result is the
fish env's action: the six actuations as ``2u - 1`` and the two fin entries.

A swim whose speed changes keeps its phase: the swim-MC's frequency grows with its speed, so
played at the time since the swim began, a small change of speed at 10 s would jump the tail
beat's phase by about a radian (0.2 cycles per 0.01 of speed). The navigator counts the tail
beats the swim has made and plays the MC at the time that many beats take at the new speed.
A turn strokes by the fish's forward speed when it begins (``actions``' ``forward``, BL/s;
``turn_mc``'s ``speed``): the reactive water turns a fish under way further.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .fish import (
    MAX_SPEED,
    FinParams,
    SwimParams,
    TurnParams,
    calibrated,
    fin_mc,
    swim_mc,
    to_action,
    turn_duration,
    turn_mc,
)


@dataclass(frozen=True)
class NavigationParams:
    """turn_threshold: |turn| below which the fish swims; max_turn: rad, the turn of a
    command of 1; swim, turn: the MCs' parameters (the water's calibration, by default the
    default water's:
    :func:`animat.envs.motor.fish.calibrated`)."""

    turn_threshold: float = 0.15
    max_turn: float = np.pi / 2
    swim: SwimParams = field(default_factory=SwimParams)
    turn: TurnParams = field(default_factory=TurnParams)


def navigation_for(water) -> NavigationParams:
    """The default navigation with the motor controllers calibrated for ``water`` (a
    :class:`~animat.envs.physics.system.Water`)."""
    swim, turn = calibrated(water.model)
    return NavigationParams(swim=swim, turn=turn)


class Navigator:
    """Motor state of ``count`` fish: the running MC's kind (0 swim, +1 left turn, -1 right
    turn), its angle and its start time (s); a swim's speed, since when it holds and the tail
    beats made by then (its phase); a turn's forward speed at its start (BL/s)."""

    def __init__(self, count: int, params: NavigationParams = NavigationParams()) -> None:
        self.params = params
        self.kind = np.zeros(count, dtype=int)
        self.angle = np.zeros(count)
        self.start = np.zeros(count)
        self.speed = np.full(count, np.nan)  # the swim's speed since ``since`` (nan: none yet)
        self.since = np.zeros(count)  # s, when the swim took that speed
        self.beats = np.zeros(count)  # tail-beat cycles the swim had made by then
        self.turn_from = np.zeros(count)  # BL/s, the forward speed the running turn began at

    def reset(self, rows: np.ndarray) -> None:
        self.kind[rows], self.angle[rows], self.start[rows] = 0, 0.0, 0.0
        self.speed[rows], self.turn_from[rows] = np.nan, 0.0

    def _swim_times(self, rows: np.ndarray, speed: np.ndarray, time: np.ndarray) -> np.ndarray:
        """(R,) s: for the swimming fish ``rows``, the time at which the swim-MC at ``speed``
        (R,) has made the tail beats each one's swim has made by ``time`` (R,) (the time since
        the swim began while its speed holds)."""
        was = self.speed[rows]
        changed = was != speed  # a new speed (nan: a new swim)
        fresh, moved = changed & np.isnan(was), changed & ~np.isnan(was)
        self.beats[rows[fresh]], self.since[rows[fresh]] = 0.0, self.start[rows[fresh]]
        kept = rows[moved]
        self.beats[kept] += self._hz(was[moved]) * (time[moved] - self.since[kept])
        self.since[kept] = time[moved]
        self.speed[rows[changed]] = speed[changed]
        return self.beats[rows] / self._hz(speed) + (time - self.since[rows])

    def _hz(self, speed):
        swim = self.params.swim
        return swim.min_hz + (swim.max_hz - swim.min_hz) * speed

    def actions(self, commands: np.ndarray, time: float | np.ndarray,
                reflex: np.ndarray | None = None,
                forward: np.ndarray | None = None) -> np.ndarray:
        """(count, 8) fish-env actions (6 actuations, 2 fins) at ``time`` (s, scalar or per
        fish) for commands (count, 3): speed in [0, 1], turn and pitch in [-1, 1]. Where
        ``reflex`` (count,) is True, a turn the other way than the command's is cut short for
        it (a reflex, such as collision avoidance, pre-empts the running MC). ``forward``
        (count,) BL/s: each fish's speed along its heading now, which a turn begun now strokes
        by (default 0: from rest; :func:`forward_speeds` reads it off the kinematics). Every
        fish at once, in arrays; a command that is not a number is a ValueError, before any
        fish's state changes."""
        commands = np.asarray(commands, dtype=float)
        if not np.isfinite(commands).all():
            raise ValueError("navigation commands must be finite numbers (speed, turn, pitch)")
        time = np.broadcast_to(np.asarray(time, dtype=float), self.kind.shape)
        forward = np.zeros(self.kind.shape) if forward is None else np.clip(
            np.asarray(forward, dtype=float), -MAX_SPEED, MAX_SPEED)
        speed = np.minimum(np.maximum(commands[:, 0], 0.0), 1.0)
        turn = np.minimum(np.maximum(commands[:, 1], -1.0), 1.0)
        pitch = np.minimum(np.maximum(commands[:, 2], -1.0), 1.0)
        params, wanted = self.params, np.abs(turn) > self.params.turn_threshold
        over = (self.kind != 0) & (time - self.start >= turn_duration(self.angle, params.turn))
        self.kind[over], self.start[over], self.speed[over] = 0, time[over], np.nan
        if reflex is not None:  # the reflex's turn starts now
            self.kind[np.asarray(reflex, bool) & (self.kind * turn < 0) & wanted] = 0
        begin = (self.kind == 0) & wanted
        self.kind[begin] = np.where(turn[begin] > 0, 1, -1)
        self.start[begin], self.angle[begin] = time[begin], np.abs(turn[begin]) * params.max_turn
        self.speed[begin], self.turn_from[begin] = np.nan, forward[begin]
        u = np.empty((len(self.kind), 6))
        swim = np.flatnonzero(self.kind == 0)
        u[swim] = swim_mc(speed[swim], self._swim_times(swim, speed[swim], time[swim]),
                          params.swim)
        turning = np.flatnonzero(self.kind != 0)
        u[turning] = turn_mc(self.angle[turning], time[turning] - self.start[turning],
                             self.kind[turning] > 0, params.turn, self.turn_from[turning])
        out = np.empty((len(self.kind), 8), np.float32)
        out[:, :6] = to_action(u)
        out[:, 6:] = fin_mc(pitch=pitch) / FinParams().max_angle
        return out


def forward_speeds(kinematics, length: float) -> np.ndarray:
    """(F,) BL/s: each fish's centre-of-mass velocity along its heading (``kinematics`` of
    :class:`~animat.envs.core.batch.BodyBatch`: ``com_vel`` (F, 3) m/s, ``frames`` (F, 3, 3)
    rows forward, left, up), for :meth:`Navigator.actions`' ``forward``; ``length`` m."""
    return np.einsum("fk,fk->f", kinematics.com_vel, kinematics.frames[:, 0]) / length
