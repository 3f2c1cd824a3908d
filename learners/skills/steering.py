"""Closed-loop maneuvering over a repertoire: the skills chosen from the goal's bearing and
range as the fish goes (the paper's "maneuvering to reach a visible target", Section 4.2),
where the macro learner (:mod:`animat.learners.macro`) fixes one open-loop sequence per goal.

Every ``interval_s`` the steering reads the goal in the body frame (``Animat/FishReach-v0``'s
observation, BL) and picks a skill by a few hand-set rules (:class:`SteeringParams`):

* within ``arrive_bl`` of the goal: rest (muscles relaxed), so the fish glides to it;
* the goal off to one side by more than ``turn_above_deg`` (or, while a turn to that side is
  under way, more than ``turn_below_deg``): the turn under way, or, when none is (or it has
  played the episode it was learned over), the repertoire's turn to that side whose angle is
  nearest the bearing;
* otherwise a swim: the slowest within ``slow_within_bl``, the fastest beyond
  ``fast_beyond_bl``, the one between (by their abstracted speeds) in between.

Or a table of moves chooses (:meth:`SkillSteering.from_table`): for each cell of the goal's
|bearing| and range, rest, a swim, or a turn toward the goal; the switching learner
(:mod:`animat.learners.switching`) learns one.

A skill chosen again goes on from where it is; a new one starts from its beginning. A turn is
played for at most the episode it was learned over (or ``turn_for_s``): then the steering
chooses afresh, and a turn chosen again starts again (the fish rests if a decision is not yet
due; a turn's abstraction is a mirrored series, which would play the turn backwards). A swim
is periodic and goes on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from animat.envs.registration import task_of
from animat.envs.tasks import ReachTask

from ..controllers.repertoire import REST, Repertoire, play_skills, switch_skills


@dataclass(frozen=True)
class SteeringParams:
    """The steering's rules (see the module docstring).

    Attributes:
        interval_s: s between decisions (rounded to whole env steps, at least one).
        turn_above_deg: deg, |bearing| above which a turn starts.
        turn_below_deg: deg, |bearing| below which a turn under way stops.
        arrive_bl: BL, the range within which the fish rests.
        slow_within_bl, fast_beyond_bl: BL, the ranges that choose the slowest and the fastest
            swim.
        turn_for_s: s, the longest a turn plays before the steering chooses afresh (None: the
            episode it was learned over).
        range_edges_bl: BL, where a table of moves splits the goal's range (increasing, each
            > 0; a table has one range bin more than edges).
    """

    interval_s: float = 0.25
    turn_above_deg: float = 30.0
    turn_below_deg: float = 15.0
    arrive_bl: float = 0.3
    slow_within_bl: float = 1.0
    fast_beyond_bl: float = 3.0
    turn_for_s: float | None = None
    range_edges_bl: tuple[float, ...] = (1.0, 2.0, 4.0)

    def __post_init__(self) -> None:
        edges = self.range_edges_bl
        if not (isinstance(edges, (list, tuple)) and edges
                and all(isinstance(e, (int, float)) and 0 < e < math.inf for e in edges)
                and all(a < b for a, b in zip(edges, edges[1:]))):
            raise ValueError(f"steering: range_edges_bl must be increasing numbers > 0 (BL), "
                             f"got {edges!r:.60}")
        object.__setattr__(self, "range_edges_bl", tuple(float(e) for e in edges))
        checks = [(0 < self.interval_s < math.inf, "interval_s must be > 0 s"),
                  (0 <= self.turn_below_deg <= self.turn_above_deg <= 180,
                   "need 0 <= turn_below_deg <= turn_above_deg <= 180"),
                  (0 <= self.arrive_bl <= self.slow_within_bl <= self.fast_beyond_bl < math.inf,
                   "need 0 <= arrive_bl <= slow_within_bl <= fast_beyond_bl (BL)"),
                  (self.turn_for_s is None or 0 < self.turn_for_s < math.inf,
                   "turn_for_s must be > 0 s (or null: the turn's whole episode)")]
        for ok, message in checks:
            if not ok:
                raise ValueError(f"steering: {message}")


@dataclass(frozen=True)
class Turn:
    """A repertoire turn: its skill index, side (+1 left, -1 right) and angle, deg."""

    index: int
    side: int
    angle: float


def check_reach(env_id: str, env_kwargs: dict | None, owner: str) -> None:
    """ValueError in one line naming ``owner`` unless the env's task is a reach (the steering
    reads its goal from the reach task's observation entries)."""
    if task_of(env_id, env_kwargs).name != ReachTask.name:
        raise ValueError(f"{owner} steers to a goal: it needs a reach env (e.g. "
                         f"Animat/FishReach-v0), not {env_id}")


def repertoire_moves(repertoire: Repertoire) -> tuple[list[int], list[Turn]]:
    """The repertoire's swims (skill indices into ``repertoire.names``, slowest first, by
    their abstracted speeds) and turns (from their tasks' angle and direction); a ValueError
    naming what is missing when there is no swim or no turn to either side."""
    swims, turns = [], []
    for index, name in enumerate(repertoire.names):
        meta = repertoire[name].metadata
        if meta.get("task") == "swim":
            speed = meta.get("abstracted_metrics", {}).get("eval/speed_bl_per_s", 0.0)
            swims.append((float(speed), index))
        elif meta.get("task") == "turn":
            kwargs = meta.get("env_kwargs", {})
            side = 1 if kwargs.get("direction", "left") == "left" else -1
            turns.append(Turn(index, side, float(kwargs.get("angle_deg", 90.0))))
    missing = [what for what, ok in (("a swim", swims), ("a left turn",
                                     any(t.side > 0 for t in turns)),
                                     ("a right turn", any(t.side < 0 for t in turns))) if not ok]
    if missing:
        raise ValueError(f"steering needs {', '.join(missing)} in the repertoire; it has "
                         f"{repertoire.names}")
    return [index for _, index in sorted(swims)], turns


# A table of moves: a move for each cell of the goal's |bearing| (BEARING_BINS equal bins over
# [0, 180] deg) and range (bins split at the steering's range_edges_bl, BL; by default
# RANGE_EDGES_BL, a table of TABLE_SHAPE).
BEARING_BINS = 6
RANGE_EDGES_BL = SteeringParams.range_edges_bl
TABLE_SHAPE = (BEARING_BINS, len(RANGE_EDGES_BL) + 1)


def table_shape(params: SteeringParams) -> tuple[int, int]:
    """(|bearing| bins, range bins) of a table of moves for the steering ``params``."""
    return BEARING_BINS, len(params.range_edges_bl) + 1


def table_moves(swims: list[int], turns: list[Turn]) -> list[tuple[int, int]]:
    """The moves a table's codes name, each (skill index if the goal is to the left, to the
    right): code 0 rests, then the swims (slowest first), then the turns toward the goal
    (smallest angle first; as many as both sides have)."""
    sides = [sorted((t for t in turns if t.side == side), key=lambda t: t.angle)
             for side in (1, -1)]
    toward = [(left.index, right.index) for left, right in zip(*sides)]
    return [(REST, REST), *((swim, swim) for swim in swims), *toward]


def check_table(table, moves: int, shape: tuple[int, int] = TABLE_SHAPE) -> np.ndarray:
    """``table`` as an int array (..., *shape) of codes in [0, moves); a ValueError in one
    line otherwise."""
    codes = np.asarray(table)
    if (codes.shape[-2:] != shape or codes.ndim not in (2, 3)
            or not np.issubdtype(codes.dtype, np.integer) or codes.min() < 0
            or codes.max() >= moves):
        raise ValueError(f"a table of moves must be integers in [0, {moves}) of shape "
                         f"{shape} (|bearing| bins, range bins), got {codes.tolist()!r:.80}")
    return codes


class SkillSteering:
    """The steering of B fish at once: ``reset(B)``, then ``act(goals)`` once an env step.

    Args:
        repertoire: the skills it chooses from (:func:`repertoire_moves`).
        params: its rules (with a ``table``, only ``interval_s`` and ``turn_for_s`` are used).
        dt: s, the env step.
        table: None (the rules choose), or a table of moves (:func:`table_shape`) of codes
            (:func:`table_moves`) for every fish, or one per fish (B, bearing bins, range
            bins) (the switching learner's, :mod:`animat.learners.switching`).
    """

    def __init__(self, repertoire: Repertoire, params: SteeringParams, dt: float,
                 table: np.ndarray | None = None) -> None:
        self.params, self.dt = params, float(dt)
        self.controllers = [repertoire[name].controller for name in repertoire.names]
        # per skill, then resting last (REST = -1 indexes it): durations s, periodic or not
        self.durations = np.array([repertoire[name].duration for name in repertoire.names]
                                  + [np.inf])
        self.swims, self.turns = repertoire_moves(repertoire)
        self.periodic = np.ones(len(self.controllers) + 1, dtype=bool)
        turns = [turn.index for turn in self.turns]
        self.periodic[turns] = False
        self.turn_side = np.zeros(len(self.controllers) + 1, dtype=int)  # +1 left, -1 right
        self.turn_side[turns] = [turn.side for turn in self.turns]
        if params.turn_for_s is not None:
            self.durations[turns] = np.minimum(self.durations[turns], params.turn_for_s)
        self.every = max(1, int(round(params.interval_s / self.dt)))
        self.moves = table_moves(self.swims, self.turns)
        self.table = None if table is None else check_table(table, len(self.moves),
                                                            table_shape(params))
        self.reset(len(self.table) if self.table is not None and self.table.ndim == 3 else 1)

    def reset(self, batch: int) -> None:
        """Begin B episodes: every fish resting, no step played (a table of moves per fish,
        (B, bearing bins, range bins), must have B rows; one table is every fish's)."""
        if self.table is not None and self.table.ndim == 3 and len(self.table) != batch:
            raise ValueError(f"{len(self.table)} tables of moves for {batch} fish")
        self.skill = np.full(batch, REST)
        self.clock = np.zeros(batch, dtype=int)  # env steps played of the current skill
        self.step, self.seen, self.count = 0, 0.0, 0

    def act(self, goals: np.ndarray) -> np.ndarray:
        """(B, A) env actions in [-1, 1] for the goals (B, >=2) in the body frame, BL (x
        forward, y left)."""
        goals = np.atleast_2d(np.asarray(goals, dtype=float))[:, :2]
        self.seen, self.count = self.seen + goals, self.count + 1
        if self.step % self.every == 0:  # decide on the goal seen since the last decision
            switch_skills(self.skill, self.clock, self.choose(self.seen / self.count),
                          self.durations, self.periodic, self.dt)
            self.seen, self.count = 0.0, 0
        u = play_skills(self.controllers, self.durations, self.periodic, self.skill,
                        self.clock, self.dt, len(self.controllers[0].mean))
        self.step += 1
        return (2.0 * np.clip(u, 0.0, 1.0) - 1.0).astype(np.float32)

    def choose(self, goals: np.ndarray) -> np.ndarray:
        """(B,) the skill index (or :data:`REST`) for each goal, by the table of moves where
        there is one (:meth:`from_table`), else by the module's rules; a fish whose goal is
        not finite (its body diverged) rests."""
        lost = ~np.isfinite(goals).all(axis=1)
        if lost.any():
            chosen = self.choose(np.where(lost[:, None], 1.0, goals))
            return np.where(lost, REST, chosen)
        if self.table is not None:
            return self.from_table(goals)
        p = self.params
        bearing = np.degrees(np.arctan2(goals[:, 1], goals[:, 0]))
        distance = np.hypot(goals[:, 0], goals[:, 1])
        side = np.where(bearing >= 0, 1, -1)
        under_way = (self.clock * self.dt < self.durations[self.skill]) & (self.skill != REST)
        turning_that_way = under_way & (self.turn_side[self.skill] == side)
        off = np.abs(bearing)
        turn = (off > p.turn_above_deg) | (turning_that_way & (off > p.turn_below_deg))
        chosen = np.full(len(goals), self.swims[len(self.swims) // 2])
        chosen[distance < p.slow_within_bl] = self.swims[0]
        chosen[distance > p.fast_beyond_bl] = self.swims[-1]
        for row in np.flatnonzero(turn):
            chosen[row] = (self.skill[row] if turning_that_way[row]
                           else self._nearest_turn(side[row], off[row]))
        chosen[distance < p.arrive_bl] = REST
        return chosen

    def from_table(self, goals: np.ndarray) -> np.ndarray:
        """(B,) the skill index each fish's table gives for its goal's cell: |bearing| in
        :data:`BEARING_BINS` equal bins over [0, 180] deg, range split at the steering's
        ``range_edges_bl``; a turn is toward the goal's side."""
        bearing = np.degrees(np.arctan2(goals[:, 1], goals[:, 0]))
        cell_b = np.minimum((np.abs(bearing) / (180.0 / BEARING_BINS)).astype(int),
                            BEARING_BINS - 1)
        cell_r = np.searchsorted(self.params.range_edges_bl, np.hypot(goals[:, 0], goals[:, 1]))
        table = self.table if self.table.ndim == 3 else self.table[None]
        codes = table[np.arange(len(goals)) % len(table), cell_b, cell_r]
        side = (bearing < 0).astype(int)  # 0: left, 1: right
        return np.asarray(self.moves)[codes, side]

    def _nearest_turn(self, side: int, angle: float) -> int:
        """The skill index of the turn to ``side`` whose angle is nearest ``angle`` deg."""
        return min((t for t in self.turns if t.side == side),
                   key=lambda t: abs(t.angle - angle)).index


class SteeringAgent:
    """One fish's steering as an agent (SB3's ``predict``) in the reach env it steers, whose
    observation ends with the task's entries, the goal in the body frame (``ReachTask``)."""

    def __init__(self, steering: SkillSteering, env_id: str = "",
                 env_kwargs: dict | None = None) -> None:
        self.steering = steering
        self.env_id, self.env_kwargs = env_id, dict(env_kwargs or {})
        self.reset()

    def reset(self) -> None:
        self.steering.reset(1)

    def predict(self, obs, state=None, episode_start=None, deterministic: bool = True):
        goal = np.asarray(obs)[-ReachTask.obs_size:]
        return self.steering.act(goal[None])[0], None
